"""A racked table asks for the break, not for a pot.

A photo taken before a game starts shows the object balls still in their triangle. No pot is on (every ball is
frozen against others), and a planner looking for one finds only a soft safety. :func:`racked_balls` tells a rack
(at least :data:`RACKED_BALLS` object balls within :data:`RACK_REACH` ball diameters of their middle: the corners
of a 15-ball triangle lie 2.31 diameters from its centre, balls spread after a break lie much further) and
:func:`break_advice` gives the break: the cue ball sent full at the rack's nearest ball at full power. With ball in
hand, :func:`break_spot` says where the cue ball is put for it.

No chance comes with it. The event physics treats a rack of touching balls as a sequence of two-ball collisions,
which passes a break's force through the rack unlike real balls (on the standard rack, struck full from the head
spot, it pots a ball in 65 % of breaks at 6 m/s and 7 % at 8 m/s: ``benchmarks/rack_break.py``), so a measured chance
would mislead.

Example:
    >>> from pix2pockets.state import eight_ball_rack
    >>> layout = eight_ball_rack()
    >>> len(racked_balls(layout))
    15
    >>> break_advice(layout).kind
    'break'
"""

from __future__ import annotations

import math

import numpy as np

from pix2pockets.pipeline.result import MAX_SPEED, ShotAdvice
from pix2pockets.rules import InHand
from pix2pockets.state import BallClass, Shot, TableLayout

RACKED_BALLS = 12
"""Object balls that must lie together for a rack (a ball or three may sit apart or be missed in the photo)."""
RACK_REACH = 2.8
"""Largest distance of a racked ball from the rack's middle [ball diameters] (2.31 in an exact triangle)."""
OPEN_TABLE = "open"
"""The group of a break: the table is open."""


def racked_balls(layout: TableLayout) -> np.ndarray:
    """Indices of the racked object balls of ``layout``, empty when its balls are not racked (see the module)."""
    objects = np.array([i for i, b in enumerate(layout.balls) if b.ball_class is not BallClass.CUE], dtype=int)
    if len(objects) < RACKED_BALLS:
        return np.zeros(0, dtype=int)
    xy = layout.positions[objects]
    middle = np.median(xy, axis=0)
    near = np.linalg.norm(xy - middle, axis=1) <= RACK_REACH * 2 * layout.spec.ball_radius
    if near.sum() < RACKED_BALLS:
        return np.zeros(0, dtype=int)
    return objects[near]


def break_advice(layout: TableLayout) -> ShotAdvice:
    """The break on a racked ``layout``: the cue ball full at the racked ball nearest to it, at full power
    (:data:`~pix2pockets.pipeline.result.MAX_SPEED`), centre ball; no chance (see the module).

    Raises:
        ValueError: no cue ball, or the balls are not racked.
    """
    if layout.cue_index is None:
        raise ValueError("no cue ball found on the table")
    rack = racked_balls(layout)
    if not len(rack):
        raise ValueError("the balls are not racked")
    cue = layout.positions[layout.cue_index]
    head = int(rack[np.argmin(np.linalg.norm(layout.positions[rack] - cue, axis=1))])
    target = layout.positions[head]
    direction = (target - cue) / max(float(np.linalg.norm(target - cue)), 1e-9)
    contact = target - direction * (layout.spec.ball_radius + layout.spec.cue_radius)
    angle = math.atan2(float(direction[1]), float(direction[0]))
    return ShotAdvice(
        target_ball=head,
        pocket=None,
        kind="break",
        cue_angle=angle,
        speed=MAX_SPEED,
        success_probability=None,
        group=OPEN_TABLE,
        cue_path=np.array([cue, contact]),
        object_path=np.zeros((0, 2)),
        ghost=contact,
        stroke=Shot(angle=angle, speed=MAX_SPEED),
    )


def _break_line(layout: TableLayout, area: InHand) -> tuple[float, bool]:
    """The x of the line the break on the racked ``layout`` is played from behind [m] (the head string, or the baulk
    line for ``InHand.BAULK``) at the end away from the rack, and whether that end is ``x = 0``.

    Raises:
        ValueError: the balls are not racked.
    """
    rack = racked_balls(layout)
    if not len(rack):
        raise ValueError("the balls are not racked")
    spec = layout.spec
    from_end = spec.baulk_line_x if area is InHand.BAULK else spec.head_string_x
    near_zero = float(np.median(layout.positions[rack, 0])) >= spec.length / 2
    return (from_end if near_zero else spec.length - from_end), near_zero


def behind_break_line(layout: TableLayout, xy: np.ndarray, area: InHand) -> bool:
    """Whether the point ``xy`` (2,) [m] lies where the break on the racked ``layout`` is played from: behind the head
    string (the kitchen), or the baulk line for ``InHand.BAULK``, at the end away from the rack; up to a ball radius
    beyond the line counts (a cue ball put on the line, located from a photo).

    Raises:
        ValueError: the balls are not racked.
    """
    line, near_zero = _break_line(layout, area)
    slack = layout.spec.ball_radius
    return bool(xy[0] <= line + slack) if near_zero else bool(xy[0] >= line - slack)


def break_spot(layout: TableLayout, area: InHand) -> np.ndarray:
    """Where the cue ball is put for the break with ball in hand [m], (2,): on the long axis at the end away from the
    rack, on the head string (a quarter of the length from that end) or, in ``InHand.BAULK``, just behind the baulk
    line (a fifth). The table frame's ends come from the photo's fit, so the end is the one away from the rack.

    Raises:
        ValueError: the balls are not racked.
    """
    line, near_zero = _break_line(layout, area)
    behind = layout.spec.cue_radius if area is InHand.BAULK else 0.0  # wholly behind the baulk line
    return np.array([line - behind if near_zero else line + behind, layout.spec.width / 2])

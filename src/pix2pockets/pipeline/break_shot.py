"""A racked table asks for the break, not for a pot.

A photo taken before a game starts shows the object balls still in their triangle. No pot is on (every ball is
frozen against others), and a planner looking for one finds only a soft safety. :func:`racked_balls` tells a rack
(at least :data:`RACKED_BALLS` object balls within :data:`RACK_REACH` ball diameters of their middle: the corners
of a 15-ball triangle lie 2.31 diameters from its centre, balls spread after a break lie much further) and
:func:`break_advice` gives the break: the cue ball sent full at the rack's nearest ball at full power. With ball in
hand, :func:`break_spot` says where the cue ball is put for it.

Its chance is measured on the rack as it is racked, not as it is located: a photo places each ball a few millimetres
off, and balls a few millimetres apart take a break's force one after another instead of together
(:mod:`pix2pockets.physics.event._impact`). :func:`tight_rack` moves the racked balls onto a tight triangle where the
photo shows the rack, and :func:`hand_racked` leaves the tenths of a millimetre between them that a triangle racked by
hand leaves; the break's chance is then the share of executions that pocket an object ball and keep the cue ball on
the table (:func:`pix2pockets.pipeline.planning.break_chance`).

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
from scipy.optimize import linear_sum_assignment

from pix2pockets.pipeline.result import MAX_SPEED, ShotAdvice
from pix2pockets.rules import InHand
from pix2pockets.state import BallClass, Shot, TableLayout, rack_positions

RACKED_BALLS = 12
"""Object balls that must lie together for a rack (a ball or three may sit apart or be missed in the photo)."""
RACK_REACH = 2.8
"""Largest distance of a racked ball from the rack's middle [ball diameters] (2.31 in an exact triangle)."""
OPEN_TABLE = "open"
"""The group of a break: the table is open."""
RACKED_GAP = 0.2e-3
"""Mean gap between neighbouring balls of a triangle racked by hand [m]: balls are made to 0.127 mm either side of
their diameter (WPA equipment specifications), so a racked triangle's balls do not all touch."""
RACKED_JITTER = 0.05e-3
"""Spread of each racked ball about its place in a triangle racked by hand [m], per axis."""


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
    (:data:`~pix2pockets.pipeline.result.MAX_SPEED`), centre ball; its chance is measured apart (see the module).

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


def tight_rack(layout: TableLayout, fits: int = 3) -> TableLayout | None:
    """``layout`` with its racked balls moved onto a tight 15-ball triangle (:func:`~pix2pockets.state.rack_positions`,
    apex toward the other end of the table) where they lie.

    The object balls near the rack (within :data:`RACK_REACH` plus one diameter of its middle, so a ball the photo
    puts a little off the triangle still counts) go each to its own spot (least total distance); those within a
    diameter of their spot are moved onto it, and the triangle is shifted onto their mean place, ``fits`` times.
    None when the balls are not racked, or when the triangle would leave the table or touch a ball left where it is.
    """
    rack = racked_balls(layout)
    if not len(rack):
        return None
    spec = layout.spec
    diameter = 2 * spec.ball_radius
    middle = np.median(layout.positions[rack], axis=0)
    objects = np.array([i for i, b in enumerate(layout.balls) if b.ball_class is not BallClass.CUE], dtype=int)
    near = objects[np.linalg.norm(layout.positions[objects] - middle, axis=1) <= (RACK_REACH + 1) * diameter]
    located = layout.positions[near]
    spots = rack_positions(spec)
    if float(middle[0]) < spec.length / 2:  # racked at the other end: apex toward x = length
        spots = np.column_stack([spec.length - spots[:, 0], spots[:, 1]])
    spots = spots + (middle - np.median(spots, axis=0))
    for _ in range(fits):
        rows, cols = linear_sum_assignment(np.linalg.norm(located[:, None, :] - spots[None, :, :], axis=2))
        keep = np.linalg.norm(located[rows] - spots[cols], axis=1) <= diameter
        rows, cols = rows[keep], cols[keep]
        spots = spots + (located[rows] - spots[cols]).mean(axis=0)
    placed = spots[cols]
    if not spec.contains(placed, margin=spec.ball_radius).all():
        return None
    moved = near[rows]
    others = np.setdiff1d(np.arange(len(layout)), moved)
    radii = layout.radii
    gaps = np.linalg.norm(placed[:, None, :] - layout.positions[others][None, :, :], axis=2)
    if np.any(gaps < radii[moved][:, None] + radii[others][None, :]):
        return None
    positions = layout.positions.copy()
    positions[moved] = placed
    return TableLayout(layout.balls, positions, spec)


def hand_racked(tight: TableLayout, rng: np.random.Generator) -> TableLayout:
    """A tight rack (:func:`tight_rack`) as a triangle racks it by hand: the racked balls spread about their middle
    so that neighbours lie :data:`RACKED_GAP` apart on average, each moved by :data:`RACKED_JITTER` per axis (drawn
    again until no two balls touch). A perfect triangle breaks the same way every time (one ball into one pocket);
    these gaps make each break its own, as on a real table.
    """
    rack = racked_balls(tight)
    diameter = 2 * tight.spec.ball_radius
    middle = tight.positions[rack].mean(axis=0)
    radii = tight.radii
    spread = middle + (tight.positions[rack] - middle) * (1 + RACKED_GAP / diameter)
    while True:
        positions = tight.positions.copy()
        positions[rack] = spread + rng.normal(0.0, RACKED_JITTER, (len(rack), 2))
        gaps = np.linalg.norm(positions[rack][:, None] - positions[None], axis=2) - radii[rack][:, None] - radii[None]
        gaps[np.arange(len(rack)), rack] = np.inf
        if gaps.min() > 0:
            return TableLayout(tight.balls, positions, tight.spec)


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

"""Ball in hand: where to put the cue ball, and the shot from there.

After a foul the incoming player places the cue ball anywhere free on the table (8-ball), or behind the baulk line
when it dropped (blackball, WEPF rules). :func:`best_placement` chooses the spot:

1. **Spots**: a grid of :data:`SPOT_STEP` over the area, each at least a cue-ball-plus-ball distance (and half a
   radius) from every ball, is scored by the geometric chance of each direct pot from there
   (:func:`~pix2pockets.planner.position.direct_pot_probabilities` at :data:`RANKING_SIGMA` of aim). Each (ball,
   pocket) pair keeps its straightest spot between :data:`MIN_CUE_DISTANCE` and twice that from the ball (room for
   a natural stroke, near enough for an easy pot; the chance times the distance ranks them, which takes out the
   chance's fall with distance); a spot nearer or farther only where none of those is free.
2. **Verified**: the spots of the ``verified`` best pairs are handed to the planner, and the spot whose best
   suggestion is likeliest to succeed (then the most valuable) is taken. Where no direct pot exists from anywhere,
   the planner tries a coarse grid of spots (:data:`FALLBACK_GRID`) instead.

Example:
    >>> placed, shot = best_placement(layout_without_cue, planner, GameState(Group.SOLIDS), rng)  # doctest: +SKIP
    >>> placed.positions[placed.cue_index], shot.success_probability  # doctest: +SKIP
"""

from __future__ import annotations

import math

import numpy as np

from pix2pockets.planner.base import Planner, Suggestion, legal_targets
from pix2pockets.planner.position import direct_pot_probabilities
from pix2pockets.rules import GameState, InHand
from pix2pockets.state import Ball, TableLayout

SPOT_STEP = 0.025
"""Spacing of the spots tried [m] (about half a ball's diameter)."""
RANKING_SIGMA = math.radians(3.0)
"""Aim spread [rad] the spots are ranked with: wide enough that the chances do not all come out near 1 close to the
ball, so that a nearer and straighter pot ranks higher, as it does for any player."""
MIN_CUE_DISTANCE = 0.15
"""Cue ball to object ball [m] a spot keeps where it can (about three diameters: room for the cue and a natural
stroke), up to twice that."""
VERIFIED_SPOTS = 4
"""Spots (of distinct ball-pocket pairs) handed to the planner."""
FALLBACK_GRID = (4, 2)
"""Spots tried where no direct pot exists from anywhere: a grid of this many columns (along the table) and rows."""


def free_spots(layout: TableLayout, area: InHand = InHand.TABLE, step: float = SPOT_STEP) -> np.ndarray:
    """Grid spots (k, 2) [m] where the cue ball may be put: inside the cushions (behind the baulk line for
    :attr:`InHand.BAULK`), clear of every ball on ``layout``.

    Raises:
        ValueError: ``area`` is :attr:`InHand.NONE`.
    """
    if area is InHand.NONE:
        raise ValueError("ball in hand needs an area to place the cue ball in (table or baulk)")
    spec = layout.spec
    r = spec.ball_radius
    reach = spec.baulk_line_x if area is InHand.BAULK else spec.length - r
    xs = np.arange(r + 0.5 * step, reach, step)
    ys = np.arange(r + 0.5 * step, spec.width - r, step)
    spots = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1).reshape(-1, 2)
    if len(layout):
        clearance = spec.cue_contact_distance + 0.5 * r
        gaps = np.linalg.norm(spots[:, None, :] - layout.positions[None, :, :], axis=2)
        spots = spots[gaps.min(axis=1) >= clearance]
    return spots


def grid_spots(layout: TableLayout, area: InHand = InHand.TABLE, grid: tuple[int, int] = FALLBACK_GRID) -> np.ndarray:
    """The free spot nearest each point of a ``grid`` (columns along the table, rows) over the area (k, 2) [m]; empty
    when no spot is free."""
    cols, rows = grid
    spec = layout.spec
    free = free_spots(layout, area)
    if not len(free):
        return free
    reach = spec.baulk_line_x if area is InHand.BAULK else spec.length
    points = np.array(
        [[reach * (i + 0.5) / cols, spec.width * (j + 0.5) / rows] for i in range(cols) for j in range(rows)]
    )
    return free[np.unique(np.linalg.norm(points[:, None] - free[None], axis=2).argmin(axis=1))]


def in_hand_spots(
    layout: TableLayout,
    state: GameState,
    area: InHand = InHand.TABLE,
    verified: int = VERIFIED_SPOTS,
    step: float = SPOT_STEP,
) -> np.ndarray:
    """The best spot for each of the ``verified`` likeliest direct pots (k, 2) [m], likeliest first; empty when no
    direct pot of a legal ball exists from any free spot.

    ``layout`` holds no cue ball; ``state`` says which balls are legal.
    """
    targets = legal_targets(layout, state)
    spots = free_spots(layout, area, step)
    if not targets or not len(spots):
        return np.zeros((0, 2))
    spec = layout.spec
    positions = np.vstack([layout.positions, spots[:1]])
    cue = len(layout)
    chances = np.empty((len(spots), len(targets), len(spec.pockets)))
    for k, xy in enumerate(spots):
        positions[cue] = xy
        chances[k] = direct_pot_probabilities(positions, cue, targets, spec, RANKING_SIGMA)
    distance = np.linalg.norm(spots[:, None, :] - layout.positions[targets][None, :, :], axis=2)
    in_band = (distance >= MIN_CUE_DISTANCE) & (distance <= 2 * MIN_CUE_DISTANCE)
    ranked = chances * distance[:, :, None] + in_band[:, :, None] * (chances > 0)  # a spot in the band first
    best_spot = ranked.reshape(len(spots), -1).argmax(axis=0)  # per (ball, pocket) pair
    pair_chance = chances.reshape(len(spots), -1)[best_spot, np.arange(best_spot.size)]
    order = [j for j in np.argsort(-pair_chance, kind="stable") if pair_chance[j] > 0][:verified]
    return spots[best_spot[order]]


def best_placement(
    layout: TableLayout,
    planner: Planner,
    state: GameState,
    rng: np.random.Generator | None = None,
    area: InHand = InHand.TABLE,
    verified: int = VERIFIED_SPOTS,
    spots: np.ndarray | None = None,
) -> tuple[TableLayout, Suggestion]:
    """``layout`` with the cue ball put where ``planner`` likes its best shot most (see the module's text), and that
    shot.

    The planner's best suggestion from each candidate spot (``spots`` (k, 2) [m] when given) is ranked by its
    success estimate, then its value.

    Raises:
        ValueError: the layout already has a cue ball, ``area`` is :attr:`InHand.NONE`, no spot is free, or the planner
            suggests nothing from any of them.
    """
    if layout.cue_index is not None:
        raise ValueError("the layout already has a cue ball; ball in hand places a missing one")
    if spots is None:
        spots = in_hand_spots(layout, state, area, verified)
        if not len(spots):
            spots = grid_spots(layout, area)
    if not len(spots):
        raise ValueError("no free spot for the cue ball")
    best, best_key = None, None
    for xy in spots:
        placed = TableLayout((*layout.balls, Ball.numbered(0)), np.vstack([layout.positions, xy]), layout.spec)
        suggestions = planner.suggest(placed, state, rng)
        if not suggestions:
            continue
        top = suggestions[0]
        key = (top.success_probability or 0.0, top.value)
        if best_key is None or key > best_key:
            best, best_key = (placed, top), key
    if best is None:
        raise ValueError("the planner found no shot from any free spot for the cue ball")
    return best

"""Ball in hand: free spots, straight-in spots for the likeliest pots, the planner's pick among them."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.geometry import table_preset
from pix2pockets.planner.ball_in_hand import (
    MIN_CUE_DISTANCE,
    best_placement,
    free_spots,
    grid_spots,
    in_hand_spots,
)
from pix2pockets.planner.base import Suggestion
from pix2pockets.rules import GameState, InHand
from pix2pockets.state import Ball, Shot, TableLayout
from pix2pockets.state.ball import Group

SPEC = table_preset("9ft")
SOLIDS = GameState(Group.SOLIDS)


def layout_of(numbers: list[int], xy: list[tuple[float, float]]) -> TableLayout:
    return TableLayout(tuple(Ball.numbered(n) for n in numbers), np.array(xy, dtype=float), SPEC)


class Recorder:
    """A planner that likes spots by their x [m] and keeps the cue ball positions it was asked about."""

    name = "recorder"

    def __init__(self):
        self.seen = []

    def suggest(self, layout, state, rng=None):
        cue = layout.positions[layout.cue_index]
        self.seen.append(cue.copy())
        return [Suggestion(Shot(angle=0.0, speed=1.0), success_probability=float(cue[0] / SPEC.length))]


def test_free_spots_lie_inside_the_cushions_clear_of_the_balls():
    layout = layout_of([1, 9], [(1.0, 0.6), (2.0, 0.3)])
    spots = free_spots(layout)
    r = SPEC.ball_radius
    assert len(spots) > 1000
    assert np.all(spots >= r) and np.all(spots[:, 0] <= SPEC.length - r) and np.all(spots[:, 1] <= SPEC.width - r)
    gaps = np.linalg.norm(spots[:, None] - layout.positions[None], axis=2)
    assert gaps.min() >= SPEC.cue_contact_distance
    assert np.all(free_spots(layout, InHand.BAULK)[:, 0] <= SPEC.baulk_line_x)
    with pytest.raises(ValueError, match="needs an area"):
        free_spots(layout, InHand.NONE)


def test_the_best_spot_is_straight_behind_the_ball_away_from_the_pocket():
    ball = np.array([0.45, 0.35])  # near the bottom-left corner pocket
    layout = layout_of([3, 11, 12], [tuple(ball), (2.2, 1.0), (2.3, 0.9)])
    spots = in_hand_spots(layout, SOLIDS, verified=2)
    assert len(spots) == 2
    pocket = min(SPEC.pockets, key=lambda p: np.linalg.norm(np.asarray(p.centre) - ball))
    to_pocket = np.asarray(pocket.centre) - ball
    to_ball = ball - spots[0]
    cut = math.degrees(math.acos(to_pocket @ to_ball / np.linalg.norm(to_pocket) / np.linalg.norm(to_ball)))
    assert cut < 6.0
    assert np.linalg.norm(to_ball) >= MIN_CUE_DISTANCE


def test_no_spot_without_a_legal_ball():
    layout = layout_of([9, 10], [(1.0, 0.6), (2.0, 0.3)])  # solids cleared and no 8 on the table
    assert len(in_hand_spots(layout, SOLIDS)) == 0


def test_the_planner_picks_among_the_spots_and_the_cue_ball_goes_there():
    layout = layout_of([1, 2, 8], [(0.6, 0.3), (1.9, 0.9), (1.3, 0.6)])
    planner = Recorder()
    placed, top = best_placement(layout, planner, SOLIDS, np.random.default_rng(0), verified=3)
    assert len(planner.seen) == 3
    chosen = max(planner.seen, key=lambda xy: xy[0])
    assert np.allclose(placed.positions[placed.cue_index], chosen)
    assert placed.balls[: len(layout)] == layout.balls
    assert top.success_probability == pytest.approx(chosen[0] / SPEC.length)
    assert np.allclose(best_placement(layout, planner, SOLIDS)[0].positions[-1], chosen)


def test_without_a_direct_pot_the_planner_tries_a_coarse_grid():
    layout = layout_of([9, 10], [(1.0, 0.6), (2.0, 0.3)])
    planner = Recorder()
    placed, _ = best_placement(layout, planner, SOLIDS, np.random.default_rng(0), InHand.BAULK)
    assert 1 < len(planner.seen) <= 8
    assert placed.positions[placed.cue_index, 0] <= SPEC.baulk_line_x
    with pytest.raises(ValueError, match="already has a cue ball"):
        best_placement(placed, planner, SOLIDS, np.random.default_rng(0))


def test_grid_spots_are_free_and_one_per_grid_point_at_most():
    layout = layout_of([1, 9], [(SPEC.length / 8, SPEC.width / 4), (2.0, 0.3)])  # a ball on a grid point
    spots = grid_spots(layout)
    assert 1 < len(spots) <= 8
    assert np.linalg.norm(spots[:, None] - layout.positions[None], axis=2).min() >= SPEC.cue_contact_distance
    assert np.all(grid_spots(layout, InHand.BAULK)[:, 0] <= SPEC.baulk_line_x)


def test_a_planner_with_nothing_to_suggest_is_a_clear_error():
    class Silent:
        def suggest(self, layout, state, rng=None):
            return []

    layout = layout_of([1, 2], [(0.6, 0.3), (1.9, 0.9)])
    with pytest.raises(ValueError, match="found no shot from any free spot"):
        best_placement(layout, Silent(), SOLIDS)

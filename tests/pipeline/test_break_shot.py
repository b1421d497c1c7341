"""A racked table gets the break: the rack told from other layouts, the stroke, the text and the JSON."""

import json
import math

import numpy as np
import pytest

from pix2pockets.pipeline.break_shot import (
    OPEN_TABLE,
    RACKED_GAP,
    behind_break_line,
    break_advice,
    break_spot,
    hand_racked,
    racked_balls,
    tight_rack,
)
from pix2pockets.pipeline.planning import break_chance, default_planner, place_in_hand, plan_shot
from pix2pockets.pipeline.result import MAX_SPEED, LocatedBall
from pix2pockets.rules import InHand
from pix2pockets.state import TableLayout, eight_ball_rack, random_layout
from pix2pockets.testing import NearestPocketPlanner


def test_a_rack_is_racked_and_scattered_balls_are_not():
    rack = eight_ball_rack(rng=np.random.default_rng(0))
    assert len(racked_balls(rack)) == 15
    rng = np.random.default_rng(1)
    for _ in range(20):
        assert not len(racked_balls(random_layout(rng, list(range(16)))))


def test_a_rack_with_balls_missing_or_knocked_away_is_still_racked_up_to_a_point():
    rack = eight_ball_rack(rng=np.random.default_rng(0))
    moved = rack.positions.copy()
    moved[[13, 14, 15]] = [[0.3, 0.3], [0.5, 0.9], [1.2, 1.0]]  # three balls away from the rack
    assert len(racked_balls(TableLayout(rack.balls, moved, rack.spec))) == 12
    moved[12] = [0.8, 0.2]  # a fourth: too few left together
    assert not len(racked_balls(TableLayout(rack.balls, moved, rack.spec)))


def test_the_break_sends_the_cue_ball_full_at_the_nearest_racked_ball_at_full_power():
    rack = eight_ball_rack(rng=np.random.default_rng(0))
    advice = break_advice(rack)
    cue, head = rack.positions[rack.cue_index], rack.positions[advice.target_ball]
    nearest = min(racked_balls(rack), key=lambda i: np.linalg.norm(rack.positions[i] - cue))
    assert advice.target_ball == nearest and advice.kind == "break" and advice.pocket is None
    assert advice.speed == MAX_SPEED and advice.power_level == 30
    assert math.isclose(advice.cue_angle, math.atan2(*(head - cue)[::-1]))
    gap = np.linalg.norm(advice.ghost - head)  # the cue ball's centre at contact
    assert math.isclose(gap, rack.spec.ball_radius + rack.spec.cue_radius)
    assert advice.success_probability is None and advice.chance is None and advice.group == OPEN_TABLE


def spread_rack(scale: float, seed: int = 0, jitter: float = 0.001) -> TableLayout:
    """The standard rack spread about its middle by ``scale`` and jittered by up to ``jitter`` [m] per axis: a rack
    as a photo locates it, its balls a few millimetres apart."""
    rack = eight_ball_rack(rng=np.random.default_rng(seed))
    middle = rack.positions[1:].mean(axis=0)
    spread = rack.positions.copy()
    spread[1:] = middle + scale * (spread[1:] - middle)
    spread[1:] += np.random.default_rng(seed + 1).uniform(-jitter, jitter, spread[1:].shape)
    return TableLayout(rack.balls, spread, rack.spec)


@pytest.mark.parametrize("scale", [1.05, 1.12])
def test_a_located_rack_is_made_tight_where_it_lies(scale):
    exact = eight_ball_rack(rng=np.random.default_rng(0))
    tight = tight_rack(spread_rack(scale))
    assert np.abs(tight.positions - exact.positions).max() < 2e-3  # every ball back on its spot, the apex too
    turned = TableLayout(exact.balls, exact.positions * [-1, 1] + [exact.spec.length, 0], exact.spec)
    assert np.allclose(tight_rack(turned).positions, turned.positions)  # the apex toward the other end
    assert tight_rack(random_layout(np.random.default_rng(3), list(range(16)))) is None


def test_a_hand_racked_triangle_leaves_tenths_of_a_millimetre_between_its_balls():
    tight = eight_ball_rack(rng=np.random.default_rng(0))
    one, same, other = (hand_racked(tight, np.random.default_rng(s)) for s in (5, 5, 6))
    assert np.array_equal(one.positions, same.positions) and not np.array_equal(one.positions, other.positions)
    pos, d = one.positions[1:], 2 * tight.spec.ball_radius
    gaps = np.linalg.norm(pos[:, None] - pos[None], axis=2)[np.triu_indices(15, 1)] - d
    neighbours = gaps[gaps < 0.5 * d]
    assert len(neighbours) == 30 and neighbours.min() > 0  # the triangle's 30 contacts, none overlapping
    assert np.mean(neighbours) == pytest.approx(RACKED_GAP, rel=0.3)
    assert np.array_equal(one.positions[0], tight.positions[0])  # the cue ball stays


def test_the_break_has_a_chance_measured_on_the_tight_rack():
    """Struck at full power, most breaks pot a ball; the chance is the same however loosely the photo placed the
    balls, since it is measured on the rack made tight."""
    planner = default_planner()
    loose, tighter = break_chance(planner, spread_rack(1.12), 120), break_chance(planner, spread_rack(1.05), 120)
    assert 0.3 < loose.p < 0.95 and loose.samples == 120 and loose.noise == "pro"
    assert abs(loose.p - tighter.p) <= 0.1
    advice = plan_shot(spread_rack(1.12), "auto", planner, chance_samples=120)
    assert advice.kind == "break" and advice.success_probability == pytest.approx(advice.chance.p)
    assert break_chance(NearestPocketPlanner(), spread_rack(1.12)) is None  # no simulator, no chance


def test_plan_shot_on_a_rack_gives_the_break_whatever_the_group():
    rack = eight_ball_rack(rng=np.random.default_rng(0))
    for group in ("solids", "stripes", "auto"):
        assert plan_shot(rack, group, NearestPocketPlanner()).kind == "break"
    scattered = random_layout(np.random.default_rng(2), list(range(16)))
    assert plan_shot(scattered, "auto", NearestPocketPlanner()).kind != "break"


def test_the_break_reads_as_a_break_and_writes_valid_json():
    rack = eight_ball_rack(rng=np.random.default_rng(0))
    advice = break_advice(rack)
    balls = tuple(LocatedBall("solid", 0.9, (0, 0, 1, 1), (0, 0), tuple(xy), (0, 0)) for xy in rack.positions.tolist())
    assert advice.describe(balls).startswith("Break: the cue ball full into the")
    d = json.loads(json.dumps(advice.to_dict()))
    assert d["kind"] == "break" and d["success_probability"] is None and d["power_level"] == 30


def test_no_break_without_a_cue_ball_or_a_rack():
    rack = eight_ball_rack(rng=np.random.default_rng(0))
    with pytest.raises(ValueError, match="no cue ball"):
        break_advice(rack.without([rack.cue_index]))
    with pytest.raises(ValueError, match="not racked"):
        break_advice(random_layout(np.random.default_rng(3), list(range(16))))


def test_ball_in_hand_on_a_rack_is_put_where_the_break_is_played_from_away_from_the_rack():
    rack = eight_ball_rack(rng=np.random.default_rng(0))
    spec = rack.spec
    balls = rack.without([rack.cue_index])
    assert np.allclose(break_spot(balls, InHand.TABLE), [spec.head_string_x, spec.width / 2])
    assert np.allclose(break_spot(balls, InHand.BAULK), [spec.baulk_line_x - spec.cue_radius, spec.width / 2])
    turned = TableLayout(balls.balls, balls.positions * [-1, 1] + [spec.length, 0], spec)  # the rack at the other end
    assert np.allclose(break_spot(turned, InHand.TABLE), [spec.length - spec.head_string_x, spec.width / 2])
    placed, _ = place_in_hand(turned, "auto", NearestPocketPlanner(), InHand.TABLE)
    assert np.allclose(placed.positions[placed.cue_index], break_spot(turned, InHand.TABLE))
    assert plan_shot(placed, "auto", NearestPocketPlanner()).kind == "break"
    with pytest.raises(ValueError, match="not racked"):
        break_spot(random_layout(np.random.default_rng(4), list(range(1, 16))), InHand.TABLE)


def test_behind_the_break_line_is_the_end_away_from_the_rack():
    rack = eight_ball_rack(rng=np.random.default_rng(0))
    spec = rack.spec
    head = rack.positions[rack.cue_index]  # the head spot, on the head string
    assert behind_break_line(rack, head, InHand.TABLE)
    assert not behind_break_line(rack, head, InHand.BAULK)  # the baulk line lies nearer the head rail
    assert behind_break_line(rack, np.array([spec.baulk_line_x - 0.01, 0.3]), InHand.BAULK)
    assert not behind_break_line(rack, np.array([spec.length / 2, spec.width / 2]), InHand.TABLE)
    turned = TableLayout(rack.balls, rack.positions * [-1, 1] + [spec.length, 0], spec)  # the rack at the other end
    assert behind_break_line(turned, np.array([spec.length - 0.1, 0.5]), InHand.TABLE)
    assert not behind_break_line(turned, head, InHand.TABLE)
    with pytest.raises(ValueError, match="not racked"):
        behind_break_line(random_layout(np.random.default_rng(4), list(range(1, 16))), head, InHand.TABLE)

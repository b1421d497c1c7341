"""The ``paper`` backend: the paper's environment dynamics on its table."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.geometry.raster import PAPER_LAYOUT, paper_table
from pix2pockets.physics import StopAfter, make_simulator
from pix2pockets.physics.paper import (
    PAPER_MAX_SPEED,
    PAPER_PX,
    PaperParams,
    paper_continuous_speed,
    paper_level_speed,
    paper_power_level,
)
from pix2pockets.physics.paper.reference import PymunkPaperWorld
from pix2pockets.planner.paper_protocol import PAPER_SEED_BASE, paper_start_layout
from pix2pockets.state import Ball, EventType, Shot, TableLayout

SPEC = paper_table()
R = SPEC.ball_radius
DT = 1.0 / 300.0
DAMP = 0.9 ** (1.0 / 300.0)


def paper_layout(*uv: tuple[float, float]) -> TableLayout:
    """Cue ball at the first point, balls 1, 2, ... at the others, in the paper's zoom-2 pixels."""
    balls = (Ball.numbered(0), *(Ball.numbered(k) for k in range(1, len(uv))))
    return TableLayout(balls, PAPER_LAYOUT.to_table(np.array(uv, dtype=float)), SPEC)


@pytest.fixture(scope="module")
def sim():
    return make_simulator("paper")


def test_power_levels_are_the_papers():
    assert paper_level_speed(1) == pytest.approx(10 * PAPER_PX)
    assert paper_level_speed(30) == pytest.approx(500 * PAPER_PX) == pytest.approx(PAPER_MAX_SPEED)
    assert paper_continuous_speed(1.0) == pytest.approx(360 * PAPER_PX)
    assert paper_power_level(PAPER_MAX_SPEED) == 30
    assert paper_power_level(paper_level_speed(7)) == 7
    np.testing.assert_allclose(np.diff(paper_level_speed(np.arange(1, 31))), 2 * 245 / 29 * PAPER_PX)


@pytest.mark.parametrize("level", [0, 31, 2.5])
def test_bad_power_level(level):
    with pytest.raises(ValueError, match="power level"):
        paper_level_speed(level)


def test_lone_ball_stops_where_pymunk_stops_it(sim):
    # pymunk moves v dt per step, then damps v by 0.9^dt; the ball sleeps at the first step it starts at or
    # below 5 px/s. The closed form lands on the same step and the same position.
    layout = paper_layout((300.0, 400.0))
    v0 = 100.0  # px/s along +u
    res = sim.simulate(layout, Shot(angle=0.0, speed=v0 * PAPER_PX))
    n = next(k for k in range(1, 100_000) if v0 * DAMP ** (k - 1) <= 5.0)
    expected = 300.0 + v0 * DT * (1 - DAMP**n) / (1 - DAMP)
    final_u = PAPER_LAYOUT.from_table(res.final.positions)[0, 0]
    assert final_u == pytest.approx(expected, abs=1e-6)
    assert res.duration == pytest.approx(n * DT)


def test_head_on_hit_stops_the_cue_ball_dead(sim):
    layout = paper_layout((300.0, 400.0), (600.0, 400.0))
    res = sim.simulate(layout, Shot(angle=0.0, speed=0.3), stop=StopAfter.FIRST_CONTACT)
    assert res.first_contact == 1
    full = sim.simulate(layout, Shot(angle=0.0, speed=0.3))
    hit = next(e for e in full.events if e.kind is EventType.BALL_BALL)
    stops = [e for e in full.events if e.kind is EventType.ROLLING_TO_STATIONARY and e.ball == 0]
    assert stops and stops[0].time == pytest.approx(hit.time + DT)  # ideal elastic: all momentum passes on


def test_cut_shots_come_out_thin(sim):
    # The contact is resolved at the first step the balls overlap: the line of centres is then turned a
    # little further than at the ghost-ball contact, so the object ball leaves a little thinner (soft
    # strokes here, so that it stops before a cushion and its rest position gives its direction).
    obj = np.array([700.0, 500.0])
    cut = math.radians(30.0)
    ghost = obj - 28.0 * np.array([math.cos(cut), -math.sin(cut)])  # the object ball should leave at 30 deg
    cue = ghost - 300.0 * np.array([1.0, 0.0])
    layout = paper_layout(tuple(cue), tuple(obj))
    angles = []
    for speed_px in np.linspace(60.0, 110.0, 6):
        res = sim.simulate(layout, Shot(angle=0.0, speed=float(speed_px) * PAPER_PX))
        assert res.first_contact == 1 and not res.pocketed and 1 not in res.rails_touched
        d = res.final.positions[1] - layout.positions[1]
        angles.append(math.degrees(math.atan2(d[1], d[0])))
    assert all(30.0 - 1e-9 <= a < 30.8 for a in angles)
    assert max(angles) > 30.05


def test_cushion_rebound_is_a_mirror_image(sim):
    # 45 degrees into the top cushion (v = 81 px): out at 45 degrees, slower.
    layout = paper_layout((400.0, 300.0))
    res = sim.simulate(layout, Shot(angle=math.radians(45.0), speed=0.2), stop=StopAfter.REST)
    hits = [e for e in res.events if e.kind is EventType.BALL_CUSHION]
    assert hits and hits[0].other == 4  # the top head-half cushion
    d = res.final.positions[0] - layout.positions[0]
    assert d[0] > 0  # still heading toward +x after the rebound


def test_a_ball_placed_in_a_pocket_circle_drops_at_the_first_step(sim):
    layout = paper_layout((600.0, 400.0), (100.0, 100.0))  # 42.4 px from the top-left pocket centre
    res = sim.simulate(layout, Shot(angle=0.0, speed=0.1))
    drops = [e for e in res.events if e.kind is EventType.POCKET]
    assert [(e.ball, e.other, e.time) for e in drops] == [(1, 5, pytest.approx(DT))]


def test_straight_in_shot_pockets(sim):
    aim = PAPER_LAYOUT.target_points[2]  # bottom-right corner aiming point (1375, 725)
    into = np.array([-1.0, -1.0]) / math.sqrt(2)
    obj, cue = aim + 200 * into, aim + 500 * into
    layout = paper_layout(tuple(cue), tuple(obj))
    d = layout.positions[1] - layout.positions[0]
    res = sim.simulate(layout, Shot(angle=math.atan2(d[1], d[0]), speed=paper_level_speed(10)))
    assert res.first_contact == 1
    assert res.pocketed == (1,)
    assert res.pocketed_into == (2,)


def test_batch_matches_single_shots_and_is_deterministic(sim):
    layout = paper_start_layout(PAPER_SEED_BASE)
    rng = np.random.default_rng(3)
    angles, speeds = rng.uniform(-3, 3, 6), rng.uniform(0.1, 0.97, 6)
    shots = [Shot(angle=float(a), speed=float(s)) for a, s in zip(angles, speeds, strict=True)]
    batch = sim.simulate_arrays(layout, shots)
    for k, shot in enumerate(shots):
        one = sim.simulate(layout, shot)
        again = sim.simulate(layout, shot)
        assert one.pocketed == again.pocketed
        np.testing.assert_array_equal(one.final.positions, again.final.positions)
        assert set(one.pocketed) == set(np.flatnonzero(batch.pocket[k] >= 0))
        np.testing.assert_allclose(batch.final_positions[k, list(one.final_ids)], one.final.positions)


def test_shot_past_the_time_cap_fails_cleanly():
    sim = make_simulator("paper", max_time=0.5)
    layout = paper_layout((300.0, 400.0))
    with pytest.raises(RuntimeError, match="did not settle"):
        sim.simulate(layout, Shot(angle=0.0, speed=0.5))
    out = sim.simulate_arrays(layout, [Shot(angle=0.0, speed=0.5)])
    assert out.status[0] == 1


@pytest.mark.parametrize("kw", [{"damping": 1.0}, {"substep": 0.0}, {"cushion_restitution": 1.5}, {"max_events": 3}])
def test_bad_params(kw):
    with pytest.raises(ValueError):
        PaperParams(**kw)


def test_unknown_param():
    with pytest.raises(ValueError, match="unknown paper-simulator parameter"):
        make_simulator("paper", gravity=9.81)


def test_agrees_with_the_pymunk_world(sim):
    # The same strokes in the pymunk re-creation of the paper's world: same first ball hit, same drops.
    world = PymunkPaperWorld()
    rng = np.random.default_rng(11)
    for i in range(8):
        layout = paper_start_layout(PAPER_SEED_BASE + i)
        target = int(rng.integers(0, 15))
        d = layout.positions[target] - layout.positions[layout.cue_index]
        shot = Shot(angle=math.atan2(d[1], d[0]), speed=paper_level_speed(int(rng.integers(5, 31))))
        ours, theirs = sim.simulate(layout, shot), world.simulate(layout, shot)
        assert dict(zip(ours.pocketed, ours.pocketed_into, strict=True)) == dict(
            zip(theirs.pocketed, theirs.pocketed_into, strict=True)
        )

"""The ``event`` backend: motion laws, collision laws, root finding, early stops, batch API, robustness."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pix2pockets.physics import StopAfter, make_simulator
from pix2pockets.physics.event import EventSimulator, PhysicsParams
from pix2pockets.physics.event import _cache as cache_mod
from pix2pockets.physics.event._motion import (
    COLLIDE_BOUNCE,
    collide_balls,
    collide_cushion,
    kinetic_energy,
)
from pix2pockets.physics.event._roots import first_drop
from pix2pockets.state import Ball, EventType, Shot, TableLayout, eight_ball_rack, random_layout

from .conftest import SPEC, R, layout_of, straight_in_layout

PARAMS = PhysicsParams()
PRM = PARAMS.packed(R, SPEC.cushion_height)
G = PARAMS.g


@pytest.fixture(scope="module")
def sim() -> EventSimulator:
    return EventSimulator()


# ----------------------------------------------------------------------------- parameters
@pytest.mark.parametrize(
    "field, value",
    [("mu_slide", 0.0), ("mu_roll", -1.0), ("e_ball", 1.5), ("e_cushion", -0.1), ("g", math.nan), ("max_events", 3)],
)
def test_bad_params_are_rejected(field, value):
    with pytest.raises(ValueError, match=field):
        PhysicsParams(**{field: value})


def test_make_simulator_passes_params():
    sim = make_simulator("event", mu_roll=0.02)
    assert sim.params.mu_roll == 0.02
    with pytest.raises(ValueError, match="parameter"):
        make_simulator("event", no_such_thing=1.0)


def test_default_spin_friction_follows_pooltool_rule():
    assert PARAMS.spin_friction(R) == pytest.approx(10 * 2 / (5 * 9) * R)


# ----------------------------------------------------------------------------- root finding
def test_first_drop_matches_numpy_roots():
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(400):
        roots = np.sort(rng.uniform(-1, 3, 4))
        scale = rng.choice([-1.0, 1.0]) * rng.uniform(0.1, 10)
        c4, c3, c2, c1, c0 = scale * np.poly(roots)
        horizon = rng.uniform(0.5, 3)
        got = first_drop(c0, c1, c2, c3, c4, horizon)
        expected = math.inf
        if c0 > 0:
            for r in roots:
                deriv = c1 + 2 * c2 * r + 3 * c3 * r**2 + 4 * c4 * r**3
                if 0 < r <= horizon and deriv < 0:
                    expected = r
                    break
        if math.isinf(expected):
            assert math.isinf(got) or got <= horizon
        else:
            assert got == pytest.approx(expected, abs=1e-9)
            checked += 1
    assert checked > 50


def test_first_drop_finds_a_grazing_double_root():
    # (t - 1)^2 * (t + 1) * (t + 2): touches zero at t = 1 without crossing, then never drops below
    c4, c3, c2, c1, c0 = np.poly([1.0, 1.0, -1.0, -2.0])
    t = first_drop(c0, c1, c2, c3, c4, 5.0)
    assert math.isinf(t) or t == pytest.approx(1.0, abs=1e-6)


# ----------------------------------------------------------------------------- motion laws
def test_centre_ball_slides_then_rolls_to_the_analytic_distance(sim):
    v0, x0 = 0.5, 0.5
    result = sim.simulate(layout_of((x0, 0.6)), Shot(angle=0.0, speed=v0))
    kinds = [e.kind for e in result.events]
    assert kinds == [EventType.CUE_STRIKE, EventType.SLIDING_TO_ROLLING, EventType.ROLLING_TO_STATIONARY]
    mu_s, mu_r = PARAMS.mu_slide, PARAMS.mu_roll
    t_slide = 2 * v0 / (7 * mu_s * G)
    x_slide = v0 * t_slide - 0.5 * mu_s * G * t_slide**2
    v_roll = 5 / 7 * v0
    x_roll = v_roll**2 / (2 * mu_r * G)
    assert result.events[1].time == pytest.approx(t_slide, rel=1e-9)
    assert result.duration == pytest.approx(t_slide + v_roll / (mu_r * G), rel=1e-9)
    assert result.final.positions[0, 0] == pytest.approx(x0 + x_slide + x_roll, abs=1e-9)
    assert result.final.positions[0, 1] == pytest.approx(0.6, abs=1e-12)


def test_natural_roll_strike_starts_rolling():
    sim = EventSimulator()
    result = sim.simulate(layout_of((0.5, 0.6)), Shot(angle=0.0, speed=0.5, height=0.4))
    kinds = [e.kind for e in result.events]
    assert EventType.SLIDING_TO_ROLLING not in kinds
    assert kinds[-1] is EventType.ROLLING_TO_STATIONARY


def test_side_spin_outlasting_the_roll_ends_spinning_on_the_spot():
    sim = EventSimulator(mu_roll=0.05)  # rolls out before the side spin decays
    result = sim.simulate(layout_of((0.5, 0.6)), Shot(angle=0.0, speed=0.3, side=0.5))
    kinds = [e.kind for e in result.events]
    assert kinds[-2:] == [EventType.ROLLING_TO_SPINNING, EventType.SPINNING_TO_STATIONARY]


def test_draw_comes_back_and_follow_goes_through(sim):
    layout = layout_of((0.8, 0.6), (1.1, 0.6))
    draw = sim.simulate(layout, Shot(angle=0.0, speed=2.0, height=-0.45))
    follow = sim.simulate(layout, Shot(angle=0.0, speed=2.0, height=0.45))
    assert draw.first_contact == follow.first_contact == 1
    assert draw.final.positions[0, 0] < 0.8
    assert follow.final.positions[0, 0] > 1.1


@pytest.mark.parametrize("side", [-0.4, 0.4])
def test_english_changes_the_cushion_rebound(sim, side):
    layout = layout_of((1.0, 0.3))
    straight = sim.simulate(layout, Shot(angle=-math.pi / 2, speed=1.5), stop=StopAfter.REST)
    english = sim.simulate(layout, Shot(angle=-math.pi / 2, speed=1.5, side=side))
    dx_straight = straight.final.positions[0, 0] - 1.0
    dx = english.final.positions[0, 0] - 1.0
    assert abs(dx_straight) < 1e-9
    assert abs(dx) > 0.01
    # Right english (side > 0) on a ball driven into the bottom rail throws it toward -x, and vice versa.
    assert math.copysign(1.0, dx) == -math.copysign(1.0, side)


# ----------------------------------------------------------------------------- collision laws
def test_ball_collision_conserves_momentum_and_loses_energy():
    rng = np.random.default_rng(0)
    for _ in range(200):
        pos = np.array([[0.0, 0.0], [2 * R, 0.0]])
        ang = rng.uniform(0, 2 * math.pi)
        pos[1] = 2 * R * np.array([math.cos(ang), math.sin(ang)])
        vel = rng.normal(0, 2, (2, 2))
        w = rng.normal(0, 50, (2, 3))
        st = np.array([2, 2])
        p_before = vel.sum(axis=0).copy()
        e_before = kinetic_energy(2, vel, w, st, PRM)
        n = pos[1] / np.linalg.norm(pos[1])
        approach = (vel[0] - vel[1]) @ n
        outcome = collide_balls(0, 1, pos, vel, w, PRM)
        assert np.allclose(vel.sum(axis=0), p_before, atol=1e-12)
        assert kinetic_energy(2, vel, w, st, PRM) <= e_before + 1e-12
        if outcome == COLLIDE_BOUNCE and approach > PARAMS.settle_speed:
            assert (vel[1] - vel[0]) @ n == pytest.approx(PARAMS.e_ball * approach, rel=1e-9)


def test_cushion_collision_loses_energy_and_reflects():
    rng = np.random.default_rng(1)
    for _ in range(300):
        vel = rng.normal(0, 2, (1, 2))
        w = rng.normal(0, 50, (1, 3))
        vel[0, 1] = -abs(vel[0, 1]) - 0.01  # into the bottom cushion, normal (0, 1)
        e_before = kinetic_energy(1, vel, w, np.array([2]), PRM)
        collide_cushion(0, 0.0, 1.0, vel, w, PRM)
        assert kinetic_energy(1, vel, w, np.array([2]), PRM) <= e_before + 1e-12
        assert vel[0, 1] > 0.0


def test_cushion_restitution_along_the_tilted_normal():
    # No spin, no friction: the impulse acts along the contact normal, tilted by the cushion height.
    prm = PhysicsParams(mu_cushion=0.0).packed(R, SPEC.cushion_height)
    sin_tilt = (SPEC.cushion_height - R) / R
    vel, w = np.array([[0.3, -1.0]]), np.zeros((1, 3))
    collide_cushion(0, 0.0, 1.0, vel, w, prm)
    assert vel[0, 1] == pytest.approx(-1.0 + (1 + PARAMS.e_cushion) * (1 - sin_tilt**2), rel=1e-12)
    assert vel[0, 0] == pytest.approx(0.3)
    equator = PhysicsParams(mu_cushion=0.0).packed(R)
    vel = np.array([[0.3, -1.0]])
    collide_cushion(0, 0.0, 1.0, vel, np.zeros((1, 3)), equator)
    assert vel[0, 1] == pytest.approx(PARAMS.e_cushion)


def test_rolling_ball_loses_topspin_at_the_rail():
    vel = np.array([[0.0, -1.0]])
    w = np.array([[1.0 / R, 0.0, 0.0]])  # rolling toward -y: w = z x v / R
    collide_cushion(0, 0.0, 1.0, vel, w, PRM)
    assert abs(w[0, 0]) < 1.0 / R


# ----------------------------------------------------------------------------- events and stops
def test_event_indices_name_cushions_jaws_and_pockets(sim):
    rng = np.random.default_rng(5)
    seen = set()
    for _ in range(40):
        layout = random_layout(rng, list(range(8)))
        result = sim.simulate(layout, Shot(angle=rng.uniform(-math.pi, math.pi), speed=4.0))
        for e in result.events:
            if e.kind is EventType.BALL_CUSHION:
                assert 0 <= e.other < 6
            elif e.kind is EventType.BALL_JAW:
                assert 0 <= e.other < 12
            elif e.kind is EventType.POCKET:
                assert 0 <= e.other < 6
            elif e.kind is EventType.BALL_BALL:
                assert 0 <= e.other < len(layout) and e.other != e.ball
            seen.add(e.kind)
    assert {EventType.BALL_CUSHION, EventType.POCKET, EventType.BALL_BALL} <= seen


def test_first_pocket_stop(sim):
    layout, angle = straight_in_layout()
    result = sim.simulate(layout, Shot(angle=angle, speed=2.0, height=-0.4), stop=StopAfter.FIRST_POCKET)
    assert result.pocketed == (1,)
    assert result.events[-1].kind is EventType.POCKET


def test_lean_batch_matches_full_results(sim):
    rng = np.random.default_rng(11)
    layout = random_layout(rng, list(range(16)))
    angles, speeds = rng.uniform(-3, 3, 30), rng.uniform(1, 6, 30)
    shots = [Shot(angle=a, speed=s, side=0.1, height=-0.2) for a, s in zip(angles, speeds, strict=True)]
    out = sim.simulate_arrays(layout, shots)
    assert np.all(out.status == 0)
    for k, shot in enumerate(shots):
        full = sim.simulate(layout, shot)
        assert out.first_contact[k] == (-1 if full.first_contact is None else full.first_contact)
        assert tuple(np.flatnonzero(out.pocketed[k])) == tuple(sorted(full.pocketed))
        for ball, pocket in zip(full.pocketed, full.pocketed_into, strict=True):
            assert out.pocket[k, ball] == pocket
        assert np.array_equal(out.final_positions[k][list(full.final_ids)], full.final.positions)
    assert out.final_cue.shape == (30, 2)


def test_lean_batch_rejects_bad_arrays(sim):
    layout = layout_of((0.5, 0.5), (1.0, 0.5))
    with pytest.raises(ValueError, match="shape"):
        sim.simulate_arrays(layout, np.zeros((3, 4)))
    with pytest.raises(ValueError, match="finite"):
        sim.simulate_arrays(layout, np.full((1, 5), np.nan))


def test_event_budget_raises_and_is_flagged_in_batch():
    sim = EventSimulator(max_events=10)
    layout = eight_ball_rack(SPEC)
    shot = Shot(angle=0.0, speed=10.0)
    with pytest.raises(RuntimeError, match="max_events"):
        sim.simulate(layout, shot)
    assert sim.simulate_arrays(layout, [shot]).status[0] == 1


# ----------------------------------------------------------------------------- robustness
@pytest.mark.parametrize("speed", [1e-4, 0.01, 11.0])
def test_frozen_balls_and_extreme_speeds(sim, speed):
    # cue frozen to ball 1, which is frozen to ball 2 and to the bottom cushion
    layout = layout_of((1.0, R + 2 * R), (1.0, R), (1.0 + 2 * R, R))
    for angle in (-math.pi / 2, -math.pi / 3, 0.0, math.pi):
        for side, height in ((0.0, 0.0), (0.3, -0.3), (-0.3, 0.35)):
            result = sim.simulate(layout, Shot(angle=angle, speed=speed, side=side, height=height))
            assert len(result.final) + len(result.pocketed) == 3


def test_hard_break_with_spin_stays_valid(sim):
    rng = np.random.default_rng(2)
    layout = eight_ball_rack(SPEC, rng)
    for _ in range(5):
        shot = Shot(angle=rng.normal(0, 0.01), speed=11.0, side=rng.uniform(-0.3, 0.3), height=rng.uniform(-0.3, 0.3))
        result = sim.simulate(layout, shot)
        assert len(result.final) + len(result.pocketed) == 16
        assert np.all(np.isfinite(result.final.positions))


# ----------------------------------------------------------------------------- JIT cache location
def test_cache_falls_back_to_temp_when_nothing_is_writable(monkeypatch):
    import numba

    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setattr(cache_mod, "_writable", lambda _path: False)
    monkeypatch.setattr(numba.config, "CACHE_DIR", numba.config.CACHE_DIR)  # restored after the test
    cache_mod.ensure_numba_cache_dir()
    assert "pix2pockets-numba" in numba.config.CACHE_DIR


def test_stale_kernel_cache_is_dropped(tmp_path):
    stale = tmp_path / "_engine.run_shot-1.py311.nbi"
    other = tmp_path / "foreign.func-1.py311.nbi"
    stale.write_text("x")
    other.write_text("x")
    cache_mod._drop_stale(tmp_path)
    assert not stale.exists() and other.exists()
    stale.write_text("x")
    cache_mod._drop_stale(tmp_path)  # stamp matches now: kept
    assert stale.exists()


def test_every_kernel_module_stamps_the_cache():
    """A compiled kernel inlines the helpers of other modules, so an edit to any module holding kernels (or to the
    constants they read) must drop the cache: each must be in the stamp."""
    here = Path(cache_mod.__file__).parent
    kernels = {
        p.stem for p in here.glob("*.py") if any(line.startswith("@njit") for line in p.read_text().splitlines())
    }
    assert kernels | {"params"} <= set(cache_mod._KERNEL_MODULES)


def _two_balls() -> TableLayout:
    balls = (Ball.numbered(0), Ball.numbered(1))
    return TableLayout(balls, np.array([[0.6, 0.635], [1.2, 0.635]]), SPEC)


@pytest.mark.parametrize(("height", "comes_back"), [(-0.5, True), (0.5, False)])
def test_ball_path_runs_from_start_through_the_impact_to_rest(height, comes_back):
    sim = EventSimulator()
    layout = _two_balls()
    shot = Shot(angle=0.0, speed=2.0, height=height)
    path = sim.ball_path(layout, shot, 0)
    result = sim.simulate(layout, shot)
    assert np.allclose(path[0], layout.positions[0])
    assert np.allclose(path[-1], result.final.positions[result.final_ids.index(0)])
    after = sim.ball_path(layout, shot, 0, from_first_contact=True)
    contact = layout.positions[1] - [2 * SPEC.ball_radius, 0.0]
    assert np.allclose(after[0], contact, atol=1e-6)  # where it meets the object ball
    assert (after[-1, 0] < contact[0]) == comes_back  # draw comes back, follow goes through
    assert np.all(np.abs(path[:, 1] - 0.635) < 1e-9)  # a full hit stays on the line of centres


def test_ball_path_of_a_ball_never_met_is_its_spot_and_from_contact_empty():
    sim = EventSimulator()
    balls = (Ball.numbered(0), Ball.numbered(1), Ball.numbered(2))
    layout = TableLayout(balls, np.array([[0.6, 0.635], [1.2, 0.635], [1.2, 1.1]]), SPEC)
    shot = Shot(angle=0.0, speed=1.0)
    assert np.allclose(sim.ball_path(layout, shot, 2), [[1.2, 1.1]])
    assert sim.ball_path(layout, shot, 2, from_first_contact=True).shape == (0, 2)


def test_a_cut_with_draw_bends_the_cue_balls_path_off_the_tangent_line():
    """After a cut the cue ball leaves along the tangent line and its backspin pulls it round while it slides: the
    path is sampled along the parabola, not drawn as a chord."""
    sim = EventSimulator()
    layout = _two_balls()
    ghost = layout.positions[1] - [2 * SPEC.ball_radius, 0.0]
    cue = np.array([0.6, 0.5])
    layout = TableLayout(layout.balls, np.array([cue, layout.positions[1]]), SPEC)
    angle = math.atan2(*(ghost - cue)[::-1])
    path = sim.ball_path(layout, Shot(angle=angle, speed=3.0, height=-0.5), 0, from_first_contact=True, step=0.01)
    gaps = np.linalg.norm(np.diff(path, axis=0), axis=1)
    assert gaps.max() < 0.015  # points about every step along the way
    start, later = path[0], path[10]
    normal = np.array([start[1] - later[1], later[0] - start[0]]) / np.linalg.norm(later - start)
    assert np.abs((path[:11] - start) @ normal).max() > 0.005  # the first 10 cm bend by more than 5 mm

"""Balls of different sizes and masses: a UK set's 1 7/8 in, 94 g cue ball among 2 in, 116 g object balls."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pix2pockets.geometry import table_preset
from pix2pockets.physics import available_simulators, make_simulator
from pix2pockets.physics.event._motion import collide_balls, kinetic_energy, lock_cluster
from pix2pockets.physics.event.params import PhysicsParams
from pix2pockets.state import Ball, Shot, TableLayout, random_layout

UK = table_preset("uk7")
RC, RO = UK.cue_radius, UK.ball_radius
MC = UK.cue_mass / UK.ball_mass  # the cue ball's mass relative to an object ball
BACKENDS = [b for b in available_simulators() if b != "paper"]
"""The engines with balls of their own sizes (the paper's physics keeps its one ball size)."""


def uk_layout(*points: tuple[float, float]) -> TableLayout:
    """Cue ball at the first point, object balls 1, 2, ... at the others, on a UK 7-foot table."""
    balls = (Ball.numbered(0), *(Ball.numbered(k) for k in range(1, len(points))))
    return TableLayout(balls, np.array(points, dtype=float), UK)


def pair_params(e: float = 0.95) -> np.ndarray:
    return PhysicsParams(e_ball=e).packed_balls(RO, UK.cushion_height, [RC, RO], [MC, 1.0])


def test_uk_presets_carry_the_wepf_cue_ball():
    assert (UK.cue_radius, UK.ball_radius) == pytest.approx((0.0238125, 0.0254))
    assert UK.cue_mass == pytest.approx(0.094) and UK.ball_mass == pytest.approx(0.116)
    american = table_preset("9ft")
    assert american.cue_radius == american.ball_radius and american.cue_mass == american.ball_mass


@pytest.mark.parametrize("e", [0.95, 1.0, 0.5])
def test_head_on_impact_of_a_lighter_cue_ball_matches_the_analytic_answer(e):
    """Velocities after a central impact: ``v_c' = (m_c - e m_o) v / (m_c + m_o)``, ``v_o' = (1 + e) m_c v /
    (m_c + m_o)``; momentum kept, energy lost ``m_c m_o (1 - e^2) v^2 / (2 (m_c + m_o))``."""
    v = 2.0
    pos = np.array([[0.5, 0.5], [0.5 + RC + RO, 0.5]])
    vel = np.array([[v, 0.0], [0.0, 0.0]])
    w = np.zeros((2, 3))
    st = np.zeros(2, dtype=np.int64)
    prm = pair_params(e)
    before = kinetic_energy(2, vel, w, st, prm)
    collide_balls(0, 1, pos, vel, w, prm)
    assert vel[0, 0] == pytest.approx((MC - e) / (MC + 1.0) * v)
    assert vel[1, 0] == pytest.approx((1.0 + e) * MC / (MC + 1.0) * v)
    assert MC * vel[0, 0] + vel[1, 0] == pytest.approx(MC * v)  # momentum (per object-ball mass)
    lost = before - kinetic_energy(2, vel, w, st, prm)
    assert lost == pytest.approx(0.5 * MC / (MC + 1.0) * (1.0 - e * e) * v * v)
    if e > MC:  # the lighter ball comes back off the heavier one
        assert vel[0, 0] < 0.0


def test_a_locked_pair_keeps_its_momentum():
    pos = np.array([[0.5, 0.5], [0.5 + RC + RO, 0.5]])
    vel = np.array([[0.3, 0.0], [0.3005, 0.0]])
    w = np.zeros((2, 3))
    prm = pair_params()
    momentum = MC * vel[0] + vel[1]
    assert lock_cluster(0, 1, 2, pos, vel, w, np.zeros(2, dtype=np.int64), prm, np.zeros(2, dtype=np.bool_)) == 2
    assert np.allclose(vel[0], vel[1]) and np.allclose(MC * vel[0] + vel[1], momentum)


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_smaller_cue_ball_passes_a_ball_a_2_in_cue_ball_would_touch(backend):
    """An object ball off the cue ball's line by more than the two radii but less than two object-ball radii."""
    sim = make_simulator(backend)
    offset = 0.5 * (RC + RO + 2 * RO)
    layout = uk_layout((0.4, 0.5), (0.9, 0.5 + offset))
    result = sim.simulate(layout, Shot(angle=0.0, speed=1.5))
    assert result.first_contact is None
    even = TableLayout(layout.balls, layout.positions, replace(UK, cue_ball_radius=None, cue_ball_mass=None))
    assert sim.simulate(even, Shot(angle=0.0, speed=1.5)).first_contact == 1


def test_a_cue_ball_frozen_to_a_rail_sits_closer_than_an_object_ball():
    layout = uk_layout((RC, 0.5), (1.0, 0.5))  # touching the head cushion
    assert layout.radii.tolist() == pytest.approx([RC, RO])
    with pytest.raises(ValueError, match="off the playing surface"):
        uk_layout((0.8, 0.5), (RC, 0.5))  # an object ball there is inside the cushion
    with pytest.raises(ValueError, match="overlap"):
        uk_layout((0.5, 0.5), (0.5 + RC + RO - 1e-4, 0.5))


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_cue_ball_rolling_along_a_rail_stays_on_the_table(backend):
    """Frozen to the rail at its own radius, a small cue ball rolled along the rail is not taken for a ball in a
    pocket mouth (it sits closer to the rail than an object ball can)."""
    layout = uk_layout((RC, 0.4), (1.5, 0.6))
    result = make_simulator(backend).simulate(layout, Shot(angle=math.pi / 2, speed=0.02))
    assert 0 not in result.pocketed
    cue = list(result.final_ids).index(0)
    assert result.final.positions[cue, 0] == pytest.approx(RC, abs=2e-3)


@pytest.mark.parametrize("backend", BACKENDS)
@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.integers(0, 2**32 - 1),
    angle=st.floats(-math.pi, math.pi),
    speed=st.floats(0.1, 9.0),
)
def test_uk_shots_end_in_valid_layouts(backend, seed, angle, speed):
    layout = random_layout(np.random.default_rng(seed), list(range(16)), UK)
    d = layout.positions[1] - layout.positions[0]
    angle = math.atan2(d[1], d[0]) + 0.05 * math.sin(angle)  # into the pack often
    result = make_simulator(backend).simulate(layout, Shot(angle=angle, speed=speed))
    final = result.final
    TableLayout(final.balls, final.positions, final.spec)  # re-validates with each ball's own radius
    assert len(final) + len(result.pocketed) == len(layout)


def test_uk_energy_never_increases():
    sim = make_simulator("event")
    rng = np.random.default_rng(3)
    for _ in range(10):
        layout = random_layout(rng, list(range(16)), UK)
        shot = Shot(angle=rng.uniform(-math.pi, math.pi), speed=rng.uniform(0.5, 8), side=0.2, height=-0.3)
        _, energy = sim.simulate_traced(layout, shot)
        assert np.all(np.diff(energy) <= 1e-9 * energy[0])

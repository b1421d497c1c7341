"""Impacts on touching balls resolved together as compliant spheres (``physics/event/_impact.py``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.geometry import table_preset
from pix2pockets.physics.event._impact import compliant_impact, contact_time, impact_group
from pix2pockets.physics.event._motion import ST_POCKETED, ST_STATIONARY
from pix2pockets.physics.event.params import PhysicsParams
from pix2pockets.physics.event.simulator import EventSimulator
from pix2pockets.state import Shot, eight_ball_rack

SPEC = table_preset("9ft")
R = SPEC.ball_radius
PRM = PhysicsParams().packed(R, SPEC.cushion_height)


def in_line(n: int, gap: float = 0.0) -> np.ndarray:
    """Centres (n, 2) [m] of ``n`` balls in a row along x, ``gap`` [m] apart."""
    return np.array([[k * (2 * R + gap), 0.0] for k in range(n)])


def resolve(pos: np.ndarray, vel: np.ndarray, reach: float = 1e-3) -> np.ndarray:
    """Velocities after ball 0 strikes ball 1 with every ball of ``pos`` in the group."""
    vel = vel.copy()
    compliant_impact(0, 1, len(pos), pos, vel, PRM, np.ones(len(pos), dtype=np.bool_), reach)
    return vel


@pytest.mark.parametrize("speed", [0.5, 3.0, 10.0])
def test_two_balls_part_with_the_two_ball_restitution(speed):
    vel = resolve(in_line(2), np.array([[speed, 0.0], [0.0, 0.0]]))
    assert (vel[1, 0] - vel[0, 0]) / speed == pytest.approx(0.95, abs=0.005)
    assert vel.sum(axis=0) == pytest.approx([speed, 0.0])


def test_a_row_of_frozen_balls_sends_the_last_one_on_and_keeps_momentum():
    speed = 4.0
    vel = resolve(in_line(4), np.array([[speed, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]))
    assert vel.sum(axis=0) == pytest.approx([speed, 0.0], abs=1e-12)
    energy = float((vel**2).sum()) / speed**2
    assert 0.8 < energy < 0.95  # each contact loses a little, none gains
    assert vel[3, 0] > 0.85 * speed  # the far ball takes most of the speed ...
    assert np.all(np.abs(vel[:3, 0]) < 0.2 * speed)  # ... the others keep a little each way


def test_a_ball_struck_into_a_pair_side_by_side_splits_it_symmetrically():
    c = R * math.sqrt(3.0)
    pos = np.array([[-2 * R, 0.0], [0.0, 0.0], [c, R], [c, -R]])
    vel = resolve(pos, np.array([[3.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]))
    assert vel[2, 0] == pytest.approx(vel[3, 0]) and vel[2, 1] == pytest.approx(-vel[3, 1])
    assert vel[2, 1] > 0.0 and vel[2, 0] > 0.0  # each leaves along its line of centres with ball 1


def test_a_lighter_cue_ball_into_frozen_balls_keeps_momentum_and_bounces_back():
    """The UK set's 94 g cue ball into two frozen 116 g object balls: momentum kept with the balls' own masses."""
    uk = table_preset("uk7")
    rc, ro, mc = uk.cue_radius, uk.ball_radius, uk.cue_mass / uk.ball_mass
    prm = PhysicsParams().packed_balls(ro, uk.cushion_height, [rc, ro, ro], [mc, 1.0, 1.0])
    pos = np.array([[0.0, 0.0], [rc + ro, 0.0], [rc + 3 * ro, 0.0]])
    vel = np.array([[2.0, 0.0], [0.0, 0.0], [0.0, 0.0]])
    compliant_impact(0, 1, 3, pos, vel, prm, np.ones(3, dtype=np.bool_), 1e-3)
    masses = np.array([mc, 1.0, 1.0])
    assert (masses[:, None] * vel).sum(axis=0) == pytest.approx([2.0 * mc, 0.0], abs=1e-12)
    assert vel[0, 0] < 0.0 < vel[2, 0]  # the light cue ball comes back, the far ball goes on
    assert float((masses * (vel**2).sum(axis=1)).sum()) < 4.0 * mc


def test_the_group_holds_the_balls_within_reach_of_the_pair_only():
    pos = np.vstack([in_line(3), [[10 * R, 0.0]]])
    pos[2, 0] += 0.5e-3  # half a millimetre beyond touching
    st = np.full(4, ST_STATIONARY)
    member = np.zeros(4, dtype=np.bool_)
    assert impact_group(0, 1, 4, pos, np.zeros((4, 2)), st, PRM, 1e-3, member) == 3
    assert member.tolist() == [True, True, True, False]
    assert impact_group(0, 1, 4, pos, np.zeros((4, 2)), st, PRM, 0.2e-3, member) == 2
    st[2] = ST_POCKETED
    assert impact_group(0, 1, 4, pos, np.zeros((4, 2)), st, PRM, 1e-3, member) == 2


def test_contact_time_follows_hertz():
    """About a quarter of a millisecond at a break's speed, longer for slower impacts as ``v^(-1/5)``."""
    fast, slow = contact_time(0, 1, 8.0, PRM), contact_time(0, 1, 8.0 / 32, PRM)
    assert 1e-4 < fast < 5e-4
    assert slow / fast == pytest.approx(2.0)


def test_a_break_opens_the_rack():
    """Struck full from the head spot, the whole rack spreads (as a chain of two-ball impacts, it barely moves)."""
    rack = eight_ball_rack(SPEC)
    cue, apex = rack.positions[rack.cue_index], rack.positions[1]
    aim = math.atan2(float(apex[1] - cue[1]), float(apex[0] - cue[0]))
    result = EventSimulator().simulate(rack, Shot(angle=aim, speed=8.0))
    moved = {i: np.linalg.norm(result.final.positions[k] - rack.positions[i]) for k, i in enumerate(result.final_ids)}
    spread = [moved.get(i, math.inf) for i in range(1, 16)]  # a pocketed ball went far
    assert np.median(spread) > 0.5
    assert sum(d > 0.2 for d in spread) >= 10

"""Friction between the balls at an impact (``PhysicsParams.ball_friction``): throw, momentum, energy, spin."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.geometry import TableSpec, table_preset
from pix2pockets.physics.event import EventSimulator, PhysicsParams
from pix2pockets.physics.event._motion import collide_balls, kinetic_energy
from pix2pockets.physics.event.params import BALL_FRICTION_FIT
from pix2pockets.state import Ball, Shot, TableLayout

SPEC = TableSpec()
R = SPEC.ball_radius
E = PhysicsParams().e_ball


def friction(slip: float) -> float:
    a, b, c = BALL_FRICTION_FIT
    return a + b * math.exp(-c * slip)


def cut(params: PhysicsParams, phi: float, v: float, w0: tuple[float, float, float] = (0.0, 0.0, 0.0)):
    """A cue ball at ``v`` [m/s] along +x with spin ``w0`` [rad/s] meeting a resting object ball at cut angle
    ``phi`` [rad]: the pair's velocities and spins after the impact, and the kinetic energy before and after."""
    n = np.array([math.cos(phi), math.sin(phi)])
    pos = np.array([[0.5, 0.5], [0.5, 0.5] + 2 * R * n])
    vel = np.array([[v, 0.0], [0.0, 0.0]])
    w = np.array([w0, (0.0, 0.0, 0.0)], dtype=float)
    st = np.full(2, 2, dtype=np.int64)  # sliding
    prm = params.packed(R, SPEC.cushion_height)
    before = kinetic_energy(2, vel, w, st, prm)
    collide_balls(0, 1, pos, vel, w, prm)
    return vel, w, before, kinetic_energy(2, vel, w, st, prm)


@pytest.mark.parametrize("cut_deg", [10.0, 30.0, 50.0])
@pytest.mark.parametrize("v", [0.5, 2.0, 5.0])
def test_a_stun_cut_throws_the_object_ball_as_the_rigid_body_answer(cut_deg, v):
    """A stun cue ball meets the object ball's surface slipping at ``v sin(phi)``: the tangential impulse is
    ``mu J_n`` (or what stops the slip, ``m v sin(phi) / 7``), so the throw is
    ``atan(min(mu, 2 tan(phi) / (7 (1 + e))))`` off the line of centres."""
    phi = math.radians(cut_deg)
    vel, _, _, _ = cut(PhysicsParams(ball_friction=True), phi, v)
    leaves = math.atan2(vel[1, 1], vel[1, 0])
    expected = math.atan(min(friction(v * math.sin(phi)), 2 * math.tan(phi) / (7 * (1 + E))))
    assert phi - leaves == pytest.approx(expected, abs=1e-9)
    frictionless, _, _, _ = cut(PhysicsParams(), phi, v)
    assert math.atan2(frictionless[1, 1], frictionless[1, 0]) == pytest.approx(phi, abs=1e-12)


@pytest.mark.parametrize("w0", [(0.0, 0.0, 0.0), (30.0, -20.0, 0.0), (0.0, 0.0, 40.0), (-50.0, 10.0, -25.0)])
def test_friction_keeps_momentum_loses_energy_and_never_reverses_the_slip(w0):
    vel, w, before, after = cut(PhysicsParams(ball_friction=True), math.radians(35.0), 1.5, w0)
    ref, _, _, ref_after = cut(PhysicsParams(), math.radians(35.0), 1.5, w0)
    np.testing.assert_allclose(vel.sum(axis=0), ref.sum(axis=0), atol=1e-12)  # equal masses: the sum of velocities
    assert after <= ref_after + 1e-12 <= before + 1e-12
    # the slip left at the contact points the same way (or stopped), never beyond zero
    n = np.array([math.cos(math.radians(35.0)), math.sin(math.radians(35.0)), 0.0])

    def slip(vel, w):
        u0 = np.r_[vel[0], 0.0] + np.cross(w[0], R * n)
        u1 = np.r_[vel[1], 0.0] + np.cross(w[1], -R * n)
        s = u0 - u1
        return s - (s @ n) * n

    _, w_ref, _, _ = cut(PhysicsParams(), math.radians(35.0), 1.5, w0)
    start, end = slip(ref, w_ref), slip(vel, w)
    assert np.linalg.norm(end[:2]) <= np.linalg.norm(start[:2]) + 1e-12
    assert end[:2] @ start[:2] >= -1e-12


def test_gearing_english_cancels_the_throw_of_a_cut():
    """Side spin that moves the cue ball's contact point with the object ball's surface leaves no slip to throw;
    the same spin the other way doubles the slip."""
    phi = math.radians(30.0)
    v = 1.5
    # the cue ball's contact point slips at v sin(phi) across the line of centres; a z-spin of v sin(phi) / R moves
    # it back by as much
    gearing = v * math.sin(phi) / R
    vel, _, _, _ = cut(PhysicsParams(ball_friction=True), phi, v, (0.0, 0.0, gearing))
    assert math.atan2(vel[1, 1], vel[1, 0]) == pytest.approx(phi, abs=1e-9)
    vel, _, _, _ = cut(PhysicsParams(ball_friction=True), phi, v, (0.0, 0.0, -gearing))
    expected = math.atan(min(friction(2 * v * math.sin(phi)), 4 * math.tan(phi) / (7 * (1 + E))))
    assert phi - math.atan2(vel[1, 1], vel[1, 0]) == pytest.approx(expected, abs=1e-9)


def test_the_simulator_throws_the_object_ball_off_its_frictionless_line():
    phi = math.radians(30.0)
    ob = np.array([1.5, 0.6])
    cue = ob - 2 * R * np.array([math.cos(phi), math.sin(phi)]) - [0.002, 0.0]  # 2 mm before the contact
    layout = TableLayout((Ball.numbered(0), Ball.numbered(1)), np.array([cue, ob]), SPEC)
    shot = Shot(angle=0.0, speed=2.0)
    angles = []
    for on in (False, True):
        path = EventSimulator(ball_friction=on).ball_path(layout, shot, 1)
        far = path[np.argmax(np.linalg.norm(path - ob, axis=1) > 0.05)] - ob
        angles.append(math.atan2(far[1], far[0]))
    assert angles[0] == pytest.approx(phi, abs=1e-6)
    assert math.degrees(angles[0] - angles[1]) == pytest.approx(math.degrees(math.atan(friction(2.0 * 0.5))), abs=0.1)


def test_unequal_balls_keep_their_momentum_with_friction():
    uk = table_preset("uk7")
    rc, ro, mc = uk.cue_radius, uk.ball_radius, uk.cue_mass / uk.ball_mass
    phi = math.radians(40.0)
    n = np.array([math.cos(phi), math.sin(phi)])
    pos = np.array([[0.5, 0.5], [0.5, 0.5] + (rc + ro) * n])
    vel = np.array([[2.0, 0.0], [0.0, 0.0]])
    w = np.zeros((2, 3))
    prm = PhysicsParams(ball_friction=True).packed_balls(ro, uk.cushion_height, [rc, ro], [mc, 1.0])
    collide_balls(0, 1, pos, vel, w, prm)
    np.testing.assert_allclose(mc * vel[0] + vel[1], [mc * 2.0, 0.0], atol=1e-12)
    assert math.atan2(vel[1, 1], vel[1, 0]) < phi  # thrown


def test_ball_friction_must_be_a_switch():
    with pytest.raises(ValueError, match="ball_friction"):
        PhysicsParams(ball_friction=0.06)

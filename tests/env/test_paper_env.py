"""The environments on the paper's physics; the documented frames of both physics modes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.env import PoolEnv
from pix2pockets.geometry.raster import PAPER_LAYOUT, paper_table
from pix2pockets.physics.paper import PAPER_MAX_SPEED, paper_level_speed
from pix2pockets.state import Ball, TableLayout


def _straight_in(spec, obj_from_pocket: float, cue_behind: float) -> tuple[TableLayout, float]:
    """The 8 ``obj_from_pocket`` [m] out from the bottom-right corner, the cue ball ``cue_behind`` [m] behind it."""
    aim = spec.pockets[2].aim
    into = np.array([-1.0, 1.0]) / math.sqrt(2)
    obj = aim + obj_from_pocket * into
    cue = obj + cue_behind * into
    lay = TableLayout((Ball.numbered(0), Ball.numbered(8)), np.array([cue, obj]), spec)
    return lay, math.degrees(math.atan2(-into[1], -into[0]))


@pytest.mark.parametrize(("physics", "level"), [("event", 2), ("paper", 12)])
def test_documented_frames_pot_a_straight_in_shot(physics, level):
    # docs/env.md: direction bin a -> a / 100 - 180 degrees, counter-clockwise from the table's +x axis (head
    # to foot), y up; the bottom-right pocket is pocket 2 at (length, 0).
    env = PoolEnv(balls="two", physics=physics)
    lay, deg = _straight_in(env.spec_table, 0.3, 0.8)
    env.reset(seed=0, options={"layout": lay})
    action = np.array([round((deg + 180.0) * 100) % 36_000, level])
    _obs, reward, terminated, _truncated, info = env.step(action)
    assert info["won"] and info["pocketed"] == 1 and terminated and reward > 0


def test_paper_env_uses_the_papers_table_powers_and_pixels():
    env = PoolEnv(balls="all", physics="paper", obs_units="paper_pixels")
    assert env.spec_table == paper_table()
    np.testing.assert_allclose(env.actions.speeds, paper_level_speed(np.arange(1, 31)))
    assert env.actions.speeds[-1] == pytest.approx(PAPER_MAX_SPEED)
    uv = np.array([[200.0, 300.0], [900.0, 600.0]])  # zoom-2 pixels of the paper's world
    lay = TableLayout((Ball.numbered(0), Ball.numbered(8)), PAPER_LAYOUT.to_table(uv), paper_table())
    obs, _ = env.reset(seed=0, options={"layout": lay})
    rows = obs.reshape(16, 3)
    np.testing.assert_allclose(rows[0, :2], uv[0] / 2, atol=1e-3)  # the nominal 735 x 410 window: half
    np.testing.assert_allclose(rows[8, :2], uv[1] / 2, atol=1e-3)


def test_event_env_pixels_are_the_papers_window():
    env = PoolEnv(balls="two", obs_units="paper_pixels")
    spec = env.spec_table
    lay = TableLayout(
        (Ball.numbered(0), Ball.numbered(8)), np.array([[spec.ball_radius] * 2, [spec.length / 2, 0.6]]), spec
    )
    obs, _ = env.reset(seed=0, options={"layout": lay})
    u, v = obs.reshape(16, 3)[0, :2]
    # cushion faces at u = 40.5 and v = 369.5 of the paper's window; the ball centre a ball radius inside
    assert u == pytest.approx(40.5 + spec.ball_radius / spec.length * 654, abs=1e-3)
    assert v == pytest.approx(369.5 - spec.ball_radius / spec.width * 329, abs=1e-3)


def test_paper_continuous_power_range():
    env = PoolEnv(balls="one", physics="paper", action_type="continuous")
    assert env.actions.decode(np.array([0.0, 1.0]))[1] == pytest.approx(360 * PAPER_LAYOUT.metres_per_px)
    assert env.actions.decode(np.array([0.0, -1.0]))[1] == pytest.approx(10 * PAPER_LAYOUT.metres_per_px)


def test_paper_env_random_steps_stay_valid():
    env = PoolEnv(balls="all", physics="paper", sim_errors="raise")
    env.reset(seed=3)
    rng = np.random.default_rng(0)
    for _ in range(20):
        obs, _r, terminated, truncated, _info = env.step(np.array([rng.integers(36_000), rng.integers(30)]))
        assert np.all(np.isfinite(obs))
        if terminated or truncated:
            env.reset(seed=int(rng.integers(1000)))

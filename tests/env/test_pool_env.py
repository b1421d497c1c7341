"""The Gymnasium environments: API conformance, semantics, determinism, rendering."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env as gym_check_env

import pix2pockets  # noqa: F401  (registers the ids)
from pix2pockets.env import ENV_IDS
from pix2pockets.env.pool_env import PoolEnv
from pix2pockets.state import Ball, Group, TableLayout, eight_ball_rack
from tests.env.conftest import BACKENDS, DEFAULT_PHYSICS, FAST_PHYSICS


def _env(balls: str = "all", backend: str = "pymunk", **kw) -> PoolEnv:
    return PoolEnv(balls=balls, **{**BACKENDS[backend], **kw})


def test_ids_registered_on_import() -> None:
    for env_id in ("pix2pockets/OneBall-v0", "pix2pockets/TwoBall-v0", "pix2pockets/AllBall-v0"):
        assert env_id in gym.registry
    env = gym.make("pix2pockets/TwoBall-v0", **FAST_PHYSICS)
    assert env.unwrapped.setup.value == "two"
    env.close()


@pytest.mark.parametrize("env_id", sorted(ENV_IDS))
@pytest.mark.parametrize("action_type", ["discrete", "continuous"])
def test_check_env_gymnasium_and_sb3(env_id: str, action_type: str) -> None:
    env = gym.make(env_id, action_type=action_type, **DEFAULT_PHYSICS)
    gym_check_env(env.unwrapped, skip_render_check=True)
    sb3_checker = pytest.importorskip("stable_baselines3.common.env_checker")
    sb3_checker.check_env(env.unwrapped, warn=True)
    env.close()


@pytest.mark.parametrize("backend", sorted(BACKENDS))
@pytest.mark.parametrize("balls", ["one", "two", "all"])
def test_seeded_determinism(balls: str, backend: str) -> None:
    noise = {"aim_noise_deg": 0.5, "speed_noise": 0.1}
    a, b = _env(balls, backend, **noise), _env(balls, backend, **noise)
    oa, _ = a.reset(seed=42)
    ob, _ = b.reset(seed=42)
    assert np.array_equal(oa, ob)
    rng = np.random.default_rng(0)
    for _ in range(6):
        action = np.array([rng.integers(36000), rng.integers(30)])
        ra, rb = a.step(action), b.step(action)
        assert np.array_equal(ra[0], rb[0])
        assert ra[1:4] == rb[1:4]
        if ra[2]:
            oa, _ = a.reset()
            ob, _ = b.reset()
            assert np.array_equal(oa, ob)


def test_different_seeds_give_different_layouts() -> None:
    env = _env("all")
    o1, _ = env.reset(seed=1)
    o2, _ = env.reset(seed=2)
    assert not np.array_equal(o1, o2)


def _straight_in_layout() -> TableLayout:
    # cue and 8 on the diagonal toward the bottom-left corner pocket
    return TableLayout((Ball.numbered(0), Ball.numbered(8)), [(0.6, 0.6), (0.3, 0.3)])


def _aim(env: PoolEnv, start: tuple[float, float], target: tuple[float, float], power: int = 8) -> np.ndarray:
    angle = math.atan2(target[1] - start[1], target[0] - start[0])
    return np.array([int(env.actions.bin_of_angle(angle)), power])


@pytest.mark.parametrize("backend", sorted(BACKENDS))
def test_two_ball_straight_in_wins(backend: str) -> None:
    env = _env("two", backend)
    env.reset(seed=0, options={"layout": _straight_in_layout()})
    obs, reward, terminated, truncated, info = env.step(_aim(env, (0.6, 0.6), (0.3, 0.3)))
    assert info["outcome"] == "win" and info["is_success"]
    assert terminated and not truncated
    terms = info["reward_terms"]
    assert terms["win"] == 100 and terms["hit"] == 10 and terms["pocket"] == 50
    assert terms["angle"] == pytest.approx(50.0, abs=1.0)  # straight at the pocket: v ~ 0 deg
    assert reward == pytest.approx(1.0)  # 210 clipped to 210, normalised
    assert np.all(obs.reshape(16, 3)[8] == [-1, -1, 0])  # the 8 is gone


@pytest.mark.parametrize("backend", sorted(BACKENDS))
def test_one_ball_success_has_no_cue_penalty(backend: str) -> None:
    env = _env("one", backend)
    cue_only = TableLayout((Ball.numbered(0),), [(0.4, 0.4)])
    env.reset(seed=0, options={"layout": cue_only})
    _, reward, terminated, _, info = env.step(_aim(env, (0.4, 0.4), (0.0, 0.0)))
    assert info["is_success"] and terminated
    assert info["reward_terms"] == {"win": 100.0}
    assert reward == pytest.approx(100 / 210)


def test_one_ball_miss_distance_penalty() -> None:
    env = _env("one")
    env.reset(seed=0, options={"layout": TableLayout((Ball.numbered(0),), [(1.27, 0.635)])})
    _, reward, terminated, _, info = env.step(np.array([18000 + 4500, 0]))  # soft, toward the top-right
    assert terminated and not info["is_success"]
    assert set(info["reward_terms"]) == {"no_hit"}
    assert -50 / 210 <= reward < 0


@pytest.mark.parametrize("backend", sorted(BACKENDS))
def test_all_ball_turn_continues_after_a_pot(backend: str) -> None:
    balls = (Ball.numbered(0), Ball.numbered(1), Ball.numbered(8), Ball.numbered(9))
    layout = TableLayout(balls, [(0.6, 0.6), (0.3, 0.3), (2.0, 1.0), (1.8, 0.3)])
    env = _env("all", backend)
    env.reset(seed=0, options={"layout": layout, "group": "solids"})
    obs, reward, terminated, _, info = env.step(_aim(env, (0.6, 0.6), (0.3, 0.3)))
    assert info["outcome"] == "continue" and not terminated and reward > 0
    assert np.all(obs.reshape(16, 3)[1] == [-1, -1, 0])
    assert env.targets() == [env.layout.black_index]  # group cleared: the 8 is next
    shot_env = _env("all", backend, mode="shot")
    shot_env.reset(seed=0, options={"layout": layout, "group": "solids"})
    *_, terminated, _, info = shot_env.step(_aim(shot_env, (0.6, 0.6), (0.3, 0.3)))
    assert terminated and info["is_success"]


@pytest.mark.parametrize("backend", sorted(BACKENDS))
def test_early_eight_loses(backend: str) -> None:
    balls = (Ball.numbered(0), Ball.numbered(8), Ball.numbered(2))
    layout = TableLayout(balls, [(0.6, 0.6), (0.3, 0.3), (2.0, 1.0)])
    env = _env("all", backend)
    env.reset(seed=0, options={"layout": layout, "group": "solids"})
    _, reward, terminated, _, info = env.step(_aim(env, (0.6, 0.6), (0.3, 0.3)))
    assert info["outcome"] == "loss" and terminated and not info["is_success"]
    assert info["reward_terms"]["loss"] == -100 and reward < 0


def test_group_option_and_random_group() -> None:
    env = _env("all")
    _, info = env.reset(seed=0, options={"layout": eight_ball_rack(), "group": "stripes"})
    assert env.group is Group.STRIPES and info["group"] == "stripes"
    groups = {env.reset(seed=s)[1]["group"] for s in range(12)}
    assert groups == {"solids", "stripes"}


@pytest.mark.parametrize(
    "balls,layout,match",
    [
        ("one", TableLayout((Ball.numbered(0), Ball.numbered(8)), [(0.5, 0.5), (1.0, 0.5)]), "only the cue"),
        ("two", TableLayout((Ball.numbered(0),), [(0.5, 0.5)]), "needs the 8"),
        ("all", TableLayout((Ball.numbered(8), Ball.numbered(1)), [(0.5, 0.5), (1.0, 0.5)]), "no cue ball"),
        ("all", "not a layout", "must be a TableLayout"),
    ],
)
def test_bad_reset_layouts(balls: str, layout: object, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        _env(balls).reset(options={"layout": layout})


@pytest.mark.parametrize(
    "kw",
    [{"balls": "three"}, {"mode": "forever"}, {"action_type": "box"}, {"render_mode": "svg"}, {"mask_width": -1}],
)
def test_bad_arguments(kw: dict) -> None:
    with pytest.raises(ValueError):
        PoolEnv(**{**FAST_PHYSICS, **kw})


def test_unknown_reset_option() -> None:
    with pytest.raises(ValueError, match="unknown reset options"):
        _env().reset(options={"layuot": None})


def test_check_env_with_rendering() -> None:
    env = gym.make("pix2pockets/TwoBall-v0", render_mode="rgb_array", render_width=300)
    gym_check_env(env.unwrapped)
    env.close()


def test_render_rgb_array() -> None:
    env = _env("all", render_mode="rgb_array", render_width=400)
    env.reset(seed=0)
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[1] == 400
    env.step(np.array([18000, 10]))
    after = env.render()
    assert after.shape == frame.shape and not np.array_equal(after, frame)


def test_render_human_headless(monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("pygame")
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    env = _env("two", render_mode="human", render_width=300)
    env.reset(seed=0)
    obs, *_ = env.step(np.array([100, 3]))
    assert env.observation_space.contains(obs)
    env.close()


def test_paper_pixel_observations() -> None:
    env = _env("two", obs_units="paper_pixels")
    obs, _ = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    assert obs[0] > 1.0  # pixels, not fractions


def test_custom_reward_fn() -> None:
    env = _env("two", reward_fn=lambda ctx: 7.0 if ctx.won else -1.0)
    env.reset(seed=0, options={"layout": _straight_in_layout()})
    _, reward, *_ = env.step(_aim(env, (0.6, 0.6), (0.3, 0.3)))
    assert reward == 7.0


class _FailingSim:
    name = "failing"

    def simulate(self, layout, shot, stop=None):
        raise RuntimeError("shot exceeded 10 events")

    def simulate_batch(self, layout, shots, stop=None):
        return [self.simulate(layout, s) for s in shots]


def test_simulation_failure_truncates_or_raises() -> None:
    env = PoolEnv(balls="two", physics=_FailingSim())
    obs, _ = env.reset(seed=0)
    with pytest.warns(UserWarning, match="truncated"):
        obs2, reward, terminated, truncated, info = env.step(np.array([0, 0]))
    assert truncated and not terminated and reward == 0.0
    assert "exceeded" in info["sim_error"] and np.array_equal(obs, obs2)
    strict = PoolEnv(balls="two", physics=_FailingSim(), sim_errors="raise")
    strict.reset(seed=0)
    with pytest.raises(RuntimeError, match="exceeded"):
        strict.step(np.array([0, 0]))
    with pytest.raises(ValueError, match="sim_errors"):
        PoolEnv(balls="two", physics=_FailingSim(), sim_errors="ignore")


def test_a_blackball_env_plays_on_a_uk_table_with_reds_and_yellows() -> None:
    env = gym.make("pix2pockets/AllBall-v0", ball_set="blackball", **DEFAULT_PHYSICS)
    gym_check_env(env.unwrapped, skip_render_check=True)
    assert env.unwrapped.spec_table.name == "uk7" and 2 * env.unwrapped.spec_table.ball_radius == pytest.approx(0.0508)
    _, info = env.reset(seed=0, options={"layout": eight_ball_rack(env.unwrapped.spec_table), "group": "yellows"})
    assert env.unwrapped.group is Group.STRIPES and info == {"group": "yellows", "ball_set": "blackball"}
    assert {env.reset(seed=s)[1]["group"] for s in range(12)} == {"reds", "yellows"}
    with pytest.raises(ValueError, match="unknown group 'solids' for the blackball set"):
        env.reset(seed=0, options={"group": "solids"})
    env.close()


@pytest.mark.parametrize(("ball_set", "rules"), [("american", "turn_outcome"), ("blackball", "blackball_turn_outcome")])
def test_each_ball_set_judges_shots_by_its_own_rules(ball_set: str, rules: str, monkeypatch) -> None:
    from pix2pockets.env import pool_env
    from pix2pockets.rules import judge_for

    used = []
    monkeypatch.setattr(pool_env, "judge_for", lambda s: used.append(judge_for(s).__name__) or judge_for(s))
    env = PoolEnv(balls="all", ball_set=ball_set, **DEFAULT_PHYSICS)
    env.reset(seed=0)
    env.step(env.action_space.sample())
    assert used == [rules]

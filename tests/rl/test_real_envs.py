"""The RL code on the real pool environments: short training, evaluation, and the agent as a shot function."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("sb3_contrib")

from pix2pockets.rl.agent import load_agent
from pix2pockets.rl.envs import EnvChoice, make_env
from pix2pockets.rl.evaluate import evaluate_model, evaluate_random
from pix2pockets.rl.train import TrainConfig, train
from pix2pockets.state import Ball, Group, Shot, TableLayout


@pytest.fixture(scope="module")
def masked_one_ball(tmp_path_factory):
    out = tmp_path_factory.mktemp("rl") / "one-mppo"
    config = TrainConfig(
        "maskable-ppo",
        "one",
        steps=64,
        seed=0,
        out=str(out),
        progress=False,
        overrides={"n_steps": 32, "batch_size": 16, "n_epochs": 1},
    )
    return train(config)


def test_masked_ppo_one_ball_evaluates(masked_one_ball):
    result = evaluate_model(str(masked_one_ball), episodes=15, seed=1)
    # One shot per 1-ball episode; the direct mask only allows directions at a pocket.
    assert result.shot_success.trials == 15
    assert result.mean_shots == 1.0
    assert result.shot_success.rate >= 0.5


def test_load_agent_suggests_a_shot(masked_one_ball):
    agent = load_agent(masked_one_ball)
    layout = TableLayout((Ball.numbered(0),), np.array([[0.6, 0.5]]))
    shot = agent(layout)
    assert isinstance(shot, Shot)
    assert -math.pi <= shot.angle <= math.pi and shot.speed > 0
    assert agent.suggest(layout) == shot  # deterministic
    with pytest.raises(ValueError, match="no cue ball"):
        agent(TableLayout((Ball.numbered(8),), np.array([[0.6, 0.5]])))
    agent.close()


@pytest.mark.parametrize(("algo", "env"), [("td3", "two"), ("a2c", "all")])
def test_short_training_on_real_envs(algo, env, tmp_path):
    overrides = {"learning_starts": 20, "buffer_size": 500} if algo == "td3" else {"n_steps": 8}
    config = TrainConfig(algo, env, steps=40, seed=2, out=str(tmp_path / algo), progress=False, overrides=overrides)
    result = evaluate_model(str(train(config)), episodes=5, seed=0)
    assert result.choice == EnvChoice(env, continuous=algo == "td3")
    assert 0.0 <= result.shot_success.rate <= 1.0


def test_random_all_ball_counts_every_shot_of_a_turn():
    result = evaluate_random(EnvChoice("all"), episodes=30, seed=0)
    assert result.shot_success.trials >= 30
    assert result.first_shot_success.trials == 30
    # A turn goes on only after a successful shot.
    assert result.shot_success.trials == 30 + result.shot_success.successes - result.full_turn.successes


def test_max_power_mask_on_real_env():
    env = make_env(EnvChoice("two", mask="mirror", max_power=True))
    env.reset(seed=3)
    mask = env.get_wrapper_attr("action_masks")()
    assert mask.shape == (36_030,)
    assert mask[36_000:].sum() == 1 and mask[-1]
    assert mask[:36_000].any()
    group = Group.SOLIDS  # the enum is accepted as the reset group
    layout = TableLayout((Ball.numbered(0), Ball.numbered(8)), np.array([[0.6, 0.5], [1.9, 0.6]]))
    env.reset(options={"layout": layout, "group": group})
    env.close()


def test_agent_as_pipeline_planner(masked_one_ball):
    from pix2pockets.rules import GameState

    planner = load_agent(masked_one_ball).as_planner()
    layout = TableLayout((Ball.numbered(0),), np.array([[0.6, 0.5]]))
    (candidate,) = planner.suggest(layout, GameState(None))
    assert isinstance(candidate.shot, Shot)
    assert candidate.safety == (candidate.target is None)

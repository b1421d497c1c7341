"""The pool environments under RLlib: registered by id, and one short PPO iteration trains on them."""

import os

import pytest

from pix2pockets.env.pool_env import PoolEnv
from pix2pockets.rl.rllib import make_pool_env


def test_env_config_goes_on_top_of_the_id_arguments() -> None:
    env = make_pool_env({"balls": "one"}, {"action_type": "continuous"})
    assert isinstance(env, PoolEnv)
    assert env.setup.value == "one"
    assert env.action_space.shape == (2,)


def test_a_short_ppo_iteration_trains_on_a_registered_id() -> None:
    if os.environ.get("PIX2POCKETS_RLLIB_TESTS") != "require":  # CI's RLlib venv requires it
        pytest.importorskip("ray.rllib", reason="the rllib extra is not installed")
        pytest.importorskip("torch")
    import ray
    from ray.rllib.algorithms.ppo import PPOConfig

    from pix2pockets.rl.rllib import register_rllib_envs

    assert "pix2pockets/OneBall-v0" in register_rllib_envs()
    ray.init(num_cpus=1, include_dashboard=False, log_to_driver=False)
    try:
        config = (
            PPOConfig()
            .environment("pix2pockets/OneBall-v0", env_config={"action_type": "continuous"})
            .env_runners(num_env_runners=0, rollout_fragment_length=32)
            .training(train_batch_size=32, minibatch_size=16, num_epochs=1)
            .debugging(seed=0)
        )
        algo = config.build_algo()
        result = algo.train()
        algo.stop()
    finally:
        ray.shutdown()
    assert result["num_env_steps_sampled_lifetime"] >= 32

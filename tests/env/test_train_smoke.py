"""Smoke training: every baseline of the paper runs a few hundred steps on our environments."""

from __future__ import annotations

import numpy as np
import pytest

from pix2pockets.env.pool_env import PoolEnv
from tests.env.conftest import DEFAULT_PHYSICS

sb3 = pytest.importorskip("stable_baselines3")
torch = pytest.importorskip("torch")

STEPS = 256
OFF_POLICY = {"learning_starts": 64, "batch_size": 32, "buffer_size": 2_000, "train_freq": 8, "gradient_steps": 1}
ALGOS = {
    "PPO": {"n_steps": 64, "batch_size": 32, "n_epochs": 1},
    "A2C": {"n_steps": 32},
    "TD3": OFF_POLICY,
    "SAC": OFF_POLICY,
    "DDPG": OFF_POLICY,
}
CONTINUOUS_ONLY = {"TD3", "SAC", "DDPG"}


@pytest.fixture(autouse=True)
def _one_thread() -> None:
    torch.set_num_threads(1)


@pytest.mark.parametrize("algo", sorted(ALGOS))
def test_sb3_algorithms_train(algo: str) -> None:
    action_type = "continuous" if algo in CONTINUOUS_ONLY else "discrete"
    env = PoolEnv(balls="two", action_type=action_type, **DEFAULT_PHYSICS)
    model = getattr(sb3, algo)("MlpPolicy", env, seed=0, device="cpu", verbose=0, **ALGOS[algo])
    model.learn(total_timesteps=STEPS)
    obs, _ = env.reset(seed=1)
    action, _ = model.predict(obs, deterministic=True)
    assert env.action_space.contains(action)
    env.close()


@pytest.mark.parametrize("balls,mask_kind", [("all", "direct"), ("two", "mirror")])
def test_maskable_ppo_trains_with_hitpoint_masks(balls: str, mask_kind: str) -> None:
    contrib = pytest.importorskip("sb3_contrib")
    from sb3_contrib.common.maskable.utils import get_action_masks

    env = PoolEnv(balls=balls, mask_kind=mask_kind, **DEFAULT_PHYSICS)
    model = contrib.MaskablePPO("MlpPolicy", env, n_steps=64, batch_size=32, n_epochs=1, seed=0, device="cpu")
    model.learn(total_timesteps=STEPS)
    obs, _ = env.reset(seed=3)
    masks = get_action_masks(env)
    action, _ = model.predict(obs, action_masks=masks, deterministic=True)
    assert masks[int(action[0])], "the masked policy chose a masked-out direction"
    assert np.all(masks[36000:])
    env.close()

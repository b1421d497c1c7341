"""The paper's six SB3 algorithms: which action space each needs and how it is configured.

Paper (section 6.2, "Results"): every baseline trains 500,000 timesteps with "three-layer" MLP policies,
action noise for the continuous-action algorithms (TD3, SAC, DDPG), all other hyperparameters SB3 defaults.
We read "three-layer" as three hidden layers of 64 units for actor and critic (:data:`NET_ARCH`) and use
Gaussian action noise with standard deviation :data:`ACTION_NOISE_SIGMA` on the [-1, 1] action box.
"""

from __future__ import annotations

import importlib.util
import os
from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import numpy as np

NET_ARCH = (64, 64, 64)
"""Hidden layers of every policy and value network."""
ACTION_NOISE_SIGMA = 0.1
"""Standard deviation of the Gaussian exploration noise for TD3 / SAC / DDPG (action box is [-1, 1])."""


@dataclass(frozen=True, slots=True)
class AlgoSpec:
    """One algorithm.

    Attributes:
        name: CLI name.
        continuous: needs the ``Box`` action variant.
        action_noise: adds Gaussian action noise (paper: TD3, SAC, DDPG).
        maskable: MaskablePPO (uses ``action_masks()``).
        on_policy: learns from rollouts of ``n_steps`` per environment (PPO, A2C, MaskablePPO).
    """

    name: str
    continuous: bool
    action_noise: bool = False
    maskable: bool = False
    on_policy: bool = False


ALGOS: dict[str, AlgoSpec] = {
    "ppo": AlgoSpec("ppo", continuous=False, on_policy=True),
    "a2c": AlgoSpec("a2c", continuous=False, on_policy=True),
    "td3": AlgoSpec("td3", continuous=True, action_noise=True),
    "ddpg": AlgoSpec("ddpg", continuous=True, action_noise=True),
    "sac": AlgoSpec("sac", continuous=True, action_noise=True),
    "maskable-ppo": AlgoSpec("maskable-ppo", continuous=False, maskable=True, on_policy=True),
}


def algo_spec(name: str) -> AlgoSpec:
    """The spec of algorithm ``name`` with a clear error for unknown names."""
    try:
        return ALGOS[name]
    except KeyError:
        raise ValueError(f"unknown algorithm {name!r}; expected one of {sorted(ALGOS)}") from None


def torch_threads(n_envs: int = 1, cpus: int | None = None) -> int:
    """Torch threads for the training process: one on small machines, otherwise half the cores left over.

    Small MLP updates gain little past a few threads, and on a shared 2-core machine one thread beats two.
    Environments in subprocesses (``n_envs`` > 1) each keep a core busy, so they are taken off first.
    """
    cpus = cpus or os.cpu_count() or 1
    if cpus <= 2:
        return 1
    free = cpus - (n_envs if n_envs > 1 else 0)
    return max(1, min(8, free // 2))


def configure_torch(threads: int | None = None, n_envs: int = 1) -> int:
    """Set torch's thread count (``None``: :func:`torch_threads`) and turn off distribution argument validation.

    The validation re-checks every 36,000-way categorical on each call; it finds nothing in a correct
    policy and costs several percent of MaskablePPO's update time. Returns the thread count.
    """
    import torch

    n = threads or torch_threads(n_envs)
    torch.set_num_threads(n)
    torch.distributions.Distribution.set_default_validate_args(False)
    return n


def progress_bar_missing() -> list[str]:
    """Packages SB3's progress bar needs that are not installed (``tqdm``, ``rich``)."""
    return [name for name in ("tqdm", "rich") if importlib.util.find_spec(name) is None]


def algo_class(name: str) -> type:
    """The SB3 / sb3-contrib class for ``name`` (imports torch)."""
    spec = algo_spec(name)
    if spec.maskable:
        from sb3_contrib import MaskablePPO

        return MaskablePPO
    import stable_baselines3 as sb3

    return {"ppo": sb3.PPO, "a2c": sb3.A2C, "td3": sb3.TD3, "ddpg": sb3.DDPG, "sac": sb3.SAC}[spec.name]


def build_model(name: str, env: gym.Env, seed: int, **overrides: Any) -> Any:
    """A fresh model with the paper's configuration (SB3 defaults otherwise).

    Args:
        name: algorithm name (see :data:`ALGOS`).
        env: the (wrapped) training environment or VecEnv.
        seed: seeds the policy initialisation, the action noise and the env.
        **overrides: extra constructor arguments (tests use small ``n_steps`` / ``learning_starts``).
    """
    spec = algo_spec(name)
    cls = algo_class(name)
    kwargs: dict[str, Any] = {"policy_kwargs": {"net_arch": list(NET_ARCH)}, "seed": seed, "verbose": 0}
    if spec.action_noise:
        from stable_baselines3.common.noise import NormalActionNoise

        n = int(np.prod(env.action_space.shape))
        kwargs["action_noise"] = NormalActionNoise(mean=np.zeros(n), sigma=ACTION_NOISE_SIGMA * np.ones(n))
    kwargs.update(overrides)
    return cls("MlpPolicy", env, **kwargs)


def load_model(
    name: str, path: str, env: gym.Env | None = None, device: str = "cpu", n_steps: int | None = None
) -> Any:
    """Load a saved model of algorithm ``name`` (optionally attached to ``env``) onto ``device``.

    ``n_steps`` replaces an on-policy learner's steps per environment and rollout (e.g. to keep a rollout's total
    when a run resumes with more environments).
    """
    custom = {"n_steps": n_steps} if n_steps is not None else None
    return algo_class(name).load(path, env=env, device=device, custom_objects=custom)

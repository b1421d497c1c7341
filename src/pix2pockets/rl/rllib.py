"""The pool environments for RLlib (Ray's reinforcement-learning library, the ``rllib`` extra).

:func:`register_rllib_envs` puts each Gymnasium id of :mod:`pix2pockets.env.registration` into Ray's registry, so
an RLlib config names it as it would any environment; the config's ``env_config`` goes to
:class:`~pix2pockets.env.pool_env.PoolEnv` as keyword arguments on top of what the id fixes. Env runners on other
processes or nodes build their environments through the same registry entry.

Example:
    >>> from ray.rllib.algorithms.ppo import PPOConfig  # doctest: +SKIP
    >>> register_rllib_envs()  # doctest: +SKIP
    >>> config = PPOConfig().environment("pix2pockets/OneBall-v0", env_config={"action_type": "continuous"})
    >>> algo = config.build_algo()  # doctest: +SKIP
    >>> algo.train()["env_runners"]["episode_return_mean"]  # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import partial
from typing import Any

from pix2pockets.env.registration import ENV_IDS


def make_pool_env(fixed: Mapping[str, Any], env_config: Mapping[str, Any] | None = None):
    """A :class:`~pix2pockets.env.pool_env.PoolEnv` with the id's fixed arguments and ``env_config`` on top."""
    from pix2pockets.env.pool_env import PoolEnv

    return PoolEnv(**{**dict(fixed), **dict(env_config or {})})


def register_rllib_envs() -> list[str]:
    """Register every pool environment id with Ray's registry (idempotent); returns the ids.

    Raises:
        ImportError: Ray is not installed, with the extra to install.
    """
    try:
        from ray.tune.registry import register_env
    except ImportError as err:
        raise ImportError('RLlib needs the rllib extra: pip install ".[rllib]"') from err
    for env_id, fixed in ENV_IDS.items():
        register_env(env_id, partial(make_pool_env, dict(fixed)))
    return list(ENV_IDS)

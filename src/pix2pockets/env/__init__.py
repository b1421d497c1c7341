"""Gymnasium environments for 8-ball: 1-ball, 2-ball and all-ball (see :class:`PoolEnv`).

Importing ``pix2pockets`` registers ``pix2pockets/OneBall-v0``, ``pix2pockets/TwoBall-v0`` and
``pix2pockets/AllBall-v0``. The environment class and its helpers are imported on first use.
"""

from __future__ import annotations

from typing import Any

from pix2pockets.env.registration import ENV_IDS, register_envs

_LAZY = {
    "PoolEnv": "pix2pockets.env.pool_env",
    "EpisodeMode": "pix2pockets.env.pool_env",
    "ActionMap": "pix2pockets.env.actions",
    "ActionType": "pix2pockets.env.actions",
    "BallSetup": "pix2pockets.env.reward",
    "PaperReward": "pix2pockets.env.reward",
    "RewardFn": "pix2pockets.env.reward",
    "ShotContext": "pix2pockets.env.reward",
    "MaskKind": "pix2pockets.env.masks",
    "ObsUnits": "pix2pockets.env.observation",
}

__all__ = ["ENV_IDS", "register_envs", *_LAZY]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'pix2pockets.env' has no attribute {name!r}")

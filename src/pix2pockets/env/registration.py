"""Gymnasium ids of the pool environments (registered on ``import pix2pockets``; cheap, no physics import)."""

from __future__ import annotations

ENV_IDS: dict[str, dict[str, str]] = {
    "pix2pockets/OneBall-v0": {"balls": "one"},
    "pix2pockets/TwoBall-v0": {"balls": "two"},
    "pix2pockets/AllBall-v0": {"balls": "all"},
}
"""Registered ids and the ``PoolEnv`` keyword arguments each one fixes."""

ENTRY_POINT = "pix2pockets.env.pool_env:PoolEnv"


def register_envs() -> None:
    """Register :data:`ENV_IDS` with Gymnasium (idempotent; a no-op without gymnasium)."""
    try:
        from gymnasium.envs.registration import register, registry
    except ImportError:  # gymnasium is a dependency, but never break `import pix2pockets` over it
        return
    for env_id, kwargs in ENV_IDS.items():
        if env_id not in registry:
            register(id=env_id, entry_point=ENTRY_POINT, kwargs=dict(kwargs))

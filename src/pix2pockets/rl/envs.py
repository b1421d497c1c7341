"""Building the training / evaluation environments for the RL baselines.

The environments themselves live in :mod:`pix2pockets.env`; this module only picks the registered id, the
action-space variant an algorithm needs, the hitpoint mask, and adds two thin wrappers:

- :class:`MaxPowerMask`: the paper's ``PPO_mask(rho_max)``: the power part of the action mask allows only
  the strongest level, so the agent chooses the direction alone.
- :class:`ShotOutcome`: counts shots, successful shots and wins per episode and puts them in ``info``
  (``ep_shots``, ``ep_successes``, ``ep_won``) so SB3's ``Monitor`` writes them to the learning-curve CSV.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import numpy as np

ENV_IDS: dict[str, str] = {
    "one": "pix2pockets/OneBall-v0",
    "two": "pix2pockets/TwoBall-v0",
    "all": "pix2pockets/AllBall-v0",
}
"""Short names of the paper's three environments."""

MASKS = ("direct", "mirror")
PHYSICS = ("event", "paper")
"""Simulator backends the RL runs use (``paper``: the paper's own environment dynamics)."""
EPISODE_KEYS = ("ep_shots", "ep_successes", "ep_won")
"""Per-episode counters :class:`ShotOutcome` adds to the final ``info`` (and to the monitor CSV)."""


@dataclass(frozen=True, slots=True)
class EnvChoice:
    """Which environment variant to build.

    Attributes:
        env: ``one``, ``two``, ``all`` or any registered Gymnasium id.
        continuous: the ``Box`` action variant (TD3, SAC, DDPG) instead of ``MultiDiscrete([36000, 30])``.
        mask: hitpoint mask for MaskablePPO (``direct`` or ``mirror`` = direct + mirror), or ``None``.
        max_power: restrict the power part of the mask to the strongest level (needs ``mask``).
        physics: simulator backend of the environment: ``event`` (default) or ``paper`` (the paper's own
            environment dynamics, table and power levels).
    """

    env: str = "one"
    continuous: bool = False
    mask: str | None = None
    max_power: bool = False
    physics: str = "event"

    def __post_init__(self) -> None:
        if not self.env:
            raise ValueError("env must be one, two, all or a registered Gymnasium id")
        if self.mask is not None and self.mask not in MASKS:
            raise ValueError(f"mask must be one of {MASKS} or None, got {self.mask!r}")
        if self.max_power and self.mask is None:
            raise ValueError("max_power restricts the action mask, so it needs a mask (direct or mirror)")
        if self.continuous and self.mask is not None:
            raise ValueError("action masks exist for the discrete action space only")
        if self.physics not in PHYSICS:
            raise ValueError(f"physics must be one of {PHYSICS}, got {self.physics!r}")

    @property
    def env_id(self) -> str:
        """The registered Gymnasium id."""
        return ENV_IDS.get(self.env, self.env)

    def to_dict(self) -> dict[str, Any]:
        return {
            "env": self.env,
            "continuous": self.continuous,
            "mask": self.mask,
            "max_power": self.max_power,
            "physics": self.physics,
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> EnvChoice:
        return cls(
            env=str(data["env"]),
            continuous=bool(data.get("continuous", False)),
            mask=data.get("mask"),
            max_power=bool(data.get("max_power", False)),
            physics=str(data.get("physics", "event")),
        )


def _ensure_registered(env_id: str) -> None:
    if env_id in gym.registry:
        return
    import pix2pockets

    # The environment package registers its ids on import.
    try:
        __import__("pix2pockets.env")
    except ModuleNotFoundError as err:
        raise ValueError(f"environment {env_id!r} is not available: {err}") from None
    if env_id not in gym.registry:
        known = sorted(k for k in gym.registry if k.startswith(pix2pockets.__name__))
        raise ValueError(f"unknown environment {env_id!r}; registered pix2pockets ids: {known}")


def env_kwargs(choice: EnvChoice) -> dict[str, Any]:
    """Keyword arguments for ``gymnasium.make`` that select the action variant and the mask."""
    kwargs: dict[str, Any] = {}
    if choice.continuous:
        kwargs["action_type"] = "continuous"
    if choice.mask is not None:
        kwargs["mask_kind"] = choice.mask
    if choice.physics != "event":
        kwargs["physics"] = choice.physics
    return kwargs


def make_env(choice: EnvChoice, **extra: Any) -> gym.Env:
    """The environment for ``choice``, wrapped with :class:`ShotOutcome` (and :class:`MaxPowerMask`).

    Args:
        choice: the variant.
        **extra: more keyword arguments for ``gymnasium.make`` (e.g. ``render_mode``).
    """
    _ensure_registered(choice.env_id)
    env = gym.make(choice.env_id, **env_kwargs(choice), **extra)
    if choice.max_power:
        env = MaxPowerMask(env)
    return ShotOutcome(env)


def read_outcome(terminated: bool, truncated: bool, info: dict[str, Any]) -> tuple[bool, bool]:
    """Whether a step's shot succeeded and whether it won the game, from the env's ``info``.

    The pool environments report ``info["shot_success"]`` (a legal pot of a target ball, or a win) and
    ``info["outcome"]`` (``"win"`` for a won game) on every step. Without ``shot_success``, a shot that does
    not end the (turn-mode) episode counts as a success.
    """
    won = info.get("outcome") == "win"
    success = bool(info.get("shot_success", won or not (terminated or truncated)))
    return success or won, won


class ShotOutcome(gym.Wrapper):
    """Adds per-episode ``ep_shots``, ``ep_successes`` and ``ep_won`` to the final step's ``info``."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        self._shots = 0
        self._successes = 0

    def reset(self, **kwargs: Any) -> tuple[Any, dict[str, Any]]:
        self._shots = 0
        self._successes = 0
        return self.env.reset(**kwargs)

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(action)
        success, won = read_outcome(terminated, truncated, info)
        self._shots += 1
        self._successes += int(success)
        if terminated or truncated:
            info = {**info, "ep_shots": self._shots, "ep_successes": self._successes, "ep_won": won}
        return obs, reward, terminated, truncated, info

    def action_masks(self) -> np.ndarray:
        """The wrapped env's action mask (MaskablePPO looks it up on the outermost wrapper)."""
        return np.asarray(self.env.get_wrapper_attr("action_masks")(), dtype=bool)


class MaxPowerMask(gym.Wrapper):
    """Allow only the strongest power level in the wrapped env's ``MultiDiscrete([directions, powers])`` mask."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        space = env.action_space
        if not isinstance(space, gym.spaces.MultiDiscrete) or space.nvec.shape != (2,):
            raise ValueError(f"max power needs a MultiDiscrete([directions, powers]) action space, got {space}")
        self._n_dir, self._n_pow = (int(n) for n in space.nvec)

    def action_masks(self) -> np.ndarray:
        mask = np.array(self.env.get_wrapper_attr("action_masks")(), dtype=bool).reshape(-1)
        if mask.size != self._n_dir + self._n_pow:
            raise ValueError(f"expected an action mask of {self._n_dir + self._n_pow} entries, got {mask.size}")
        mask[self._n_dir :] = False
        mask[-1] = True
        return mask

"""A tiny stand-in for the pix2pockets environments, with the same API surface the RL code relies on.

MultiDiscrete([360, 5]) or Box([-1, 1]^2) actions (``action_type``), a 48-float observation,
``action_masks()`` (``mask_kind``), ``info["shot_success"]`` / ``info["outcome"]``; a turn of up to three
"balls". Fast enough for unit tests of the training code.
"""

from __future__ import annotations

from typing import Any, ClassVar

import gymnasium as gym
import numpy as np

STANDIN_ID = "p2p-test/StandIn-v0"
N_DIR, N_POW = 360, 5


class StandInEnv(gym.Env):
    metadata: ClassVar[dict[str, Any]] = {"render_modes": []}

    def __init__(self, action_type: str = "discrete", mask_kind: str = "direct", balls: int = 3) -> None:
        self.continuous = action_type == "continuous"
        self.mask = mask_kind
        self.balls = balls
        self.observation_space = gym.spaces.Box(-1.0, 1.0, (48,), dtype=np.float32)
        if self.continuous:
            self.action_space = gym.spaces.Box(-1.0, 1.0, (2,), dtype=np.float32)
        else:
            self.action_space = gym.spaces.MultiDiscrete([N_DIR, N_POW])
        self._target = 0
        self._left = 0

    def _obs(self) -> np.ndarray:
        obs = np.zeros(48, dtype=np.float32)
        obs[0] = self._target / N_DIR * 2 - 1
        obs[1] = self._left / self.balls
        return obs

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        self._target = int(self.np_random.integers(N_DIR))
        self._left = self.balls
        return self._obs(), {}

    def _direction(self, action: Any) -> int:
        if self.continuous:
            return int((float(np.clip(action[0], -1, 1)) + 1) / 2 * (N_DIR - 1))
        return int(action[0])

    def step(self, action: Any):
        hit = abs(self._direction(action) - self._target) <= 20
        if hit:
            self._left -= 1
            self._target = int(self.np_random.integers(N_DIR))
        won = hit and self._left == 0
        terminated = (not hit) or won
        reward = 1.0 if won else (0.3 if hit else -0.2)
        info = {"shot_success": hit, "outcome": "win" if won else ("continue" if hit else "end_turn")}
        if terminated:
            info["is_success"] = won
        return self._obs(), reward, terminated, False, info

    def action_masks(self) -> np.ndarray:
        if self.continuous:
            raise ValueError("action_masks() needs action_type='discrete'")
        d = np.zeros(N_DIR, dtype=bool)
        d[max(0, self._target - 5) : self._target + 6] = True
        return np.concatenate([d, np.ones(N_POW, dtype=bool)])


def register_standin() -> str:
    if STANDIN_ID not in gym.registry:
        gym.register(STANDIN_ID, entry_point=StandInEnv, max_episode_steps=50)
    return STANDIN_ID

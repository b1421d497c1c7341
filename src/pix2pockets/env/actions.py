"""Action spaces of the pool environments and their mapping to cue strokes.

Discrete (the paper's): ``MultiDiscrete([n_angles, n_powers])`` = ``[36000, 30]``.
    * direction ``a`` -> ``a * 360 / n_angles - 180`` degrees (0.01 degree steps from -180 up to 179.99),
      counter-clockwise from the table's ``+x`` axis (head -> foot);
    * power level ``p`` -> speed ``min_speed + p * (max_speed - min_speed) / (n_powers - 1)`` [m/s],
      linear, by default 0.2 ... 8.0 m/s (a very soft touch to a firm break; 0.27 m/s per level).

Continuous: ``Box(-1, 1, (2,))`` for TD3/SAC/DDPG:
    * ``a[0]`` -> ``180 * a[0]`` degrees;
    * ``a[1]`` -> ``min_speed + (a[1] + 1) / 2 * (continuous_max_speed - min_speed)`` [m/s]
      (``continuous_max_speed`` defaults to ``max_speed``).

With ``physics="paper"`` the environment uses the paper's power mapping (:func:`paper_action_map`): its
30 levels ``(245 / 29 * (l - 1) + 5) * 2`` px/s (0.019-0.971 m/s, linear, so the same formula with those
end points) and its continuous power ``(175 p + 5) * 2`` px/s, ``p = (a[1] + 1) / 2`` (up to 0.699 m/s).

Execution noise (optional, off by default): Gaussian with standard deviation ``aim_noise_deg`` [deg] on
the direction and ``speed_noise`` [m/s] on the speed (clipped at 0), drawn from the environment's
``np_random``. FastFiz tournaments used 0.125 deg and 0.075 m/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

import numpy as np
from gymnasium import spaces

from pix2pockets.state import Shot


class ActionType(StrEnum):
    """Action space flavour."""

    DISCRETE = "discrete"  # MultiDiscrete([n_angles, n_powers]), the paper's
    CONTINUOUS = "continuous"  # Box(-1, 1, (2,))


@dataclass(frozen=True, slots=True)
class ActionMap:
    """Maps actions to :class:`~pix2pockets.state.Shot` strokes.

    Attributes:
        action_type: discrete or continuous.
        n_angles: direction bins of the discrete space (36000 = 0.01 degree).
        n_powers: power levels of the discrete space.
        min_speed: cue-ball speed of the lowest power [m/s].
        max_speed: cue-ball speed of the highest power [m/s].
        aim_noise_deg: standard deviation of the Gaussian direction noise [deg].
        speed_noise: standard deviation of the Gaussian speed noise [m/s].
        continuous_max_speed: cue-ball speed of the highest continuous power [m/s] (``None``: ``max_speed``).
    """

    action_type: ActionType = ActionType.DISCRETE
    n_angles: int = 36_000
    n_powers: int = 30
    min_speed: float = 0.2
    max_speed: float = 8.0
    aim_noise_deg: float = 0.0
    speed_noise: float = 0.0
    continuous_max_speed: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "action_type", ActionType(self.action_type))
        if self.n_angles < 4 or self.n_powers < 2:
            raise ValueError(f"need n_angles >= 4 and n_powers >= 2, got {self.n_angles} and {self.n_powers}")
        if not 0.0 < self.min_speed < self.max_speed:
            raise ValueError(f"need 0 < min_speed < max_speed [m/s], got {self.min_speed} and {self.max_speed}")
        if self.aim_noise_deg < 0 or self.speed_noise < 0:
            raise ValueError(f"noise must be >= 0, got aim {self.aim_noise_deg} deg, speed {self.speed_noise} m/s")
        top = self.continuous_max_speed
        if top is not None and not top > self.min_speed:
            raise ValueError(f"continuous_max_speed must exceed min_speed [m/s], got {top}")

    @property
    def space(self) -> spaces.Space:
        """The Gymnasium action space."""
        if self.action_type is ActionType.DISCRETE:
            return spaces.MultiDiscrete(np.array([self.n_angles, self.n_powers], dtype=np.int64))
        return spaces.Box(low=-1.0, high=1.0, shape=(2,), dtype=np.float32)

    @property
    def speeds(self) -> np.ndarray:
        """Speed of each discrete power level [m/s], shape (n_powers,)."""
        return np.linspace(self.min_speed, self.max_speed, self.n_powers)

    def angle_of_bin(self, a: int | np.ndarray) -> float | np.ndarray:
        """Direction of discrete bin ``a`` [rad]."""
        return np.radians(np.asarray(a) * 360.0 / self.n_angles - 180.0)

    def bin_of_angle(self, angle: float | np.ndarray) -> int | np.ndarray:
        """Nearest discrete direction bin of ``angle`` [rad] (any real angle; wraps around)."""
        deg = np.degrees(np.asarray(angle, dtype=float)) + 180.0
        return np.rint(deg * self.n_angles / 360.0).astype(np.int64) % self.n_angles

    def decode(self, action: np.ndarray) -> tuple[float, float]:
        """The intended (noise-free) ``(angle [rad], speed [m/s])`` of an action.

        Raises:
            ValueError: the action is outside the action space.
        """
        a = np.asarray(action)
        if a.shape != (2,):
            raise ValueError(f"an action has 2 entries (direction, power), got shape {a.shape}")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"action must be finite, got {a}")
        if self.action_type is ActionType.DISCRETE:
            d, p = int(a[0]), int(a[1])
            if not (0 <= d < self.n_angles and 0 <= p < self.n_powers) or np.any(a != np.rint(a)):
                raise ValueError(f"action {a.tolist()} outside MultiDiscrete([{self.n_angles}, {self.n_powers}])")
            return float(self.angle_of_bin(d)), float(self.speeds[p])
        x = np.clip(a.astype(float), -1.0, 1.0)  # SB3 may step slightly out of bounds before clipping
        angle = math.pi * float(x[0])
        top = self.max_speed if self.continuous_max_speed is None else self.continuous_max_speed
        speed = self.min_speed + (float(x[1]) + 1.0) / 2.0 * (top - self.min_speed)
        return angle, speed

    def to_shot(self, action: np.ndarray, rng: np.random.Generator | None = None) -> Shot:
        """The stroke actually played: the decoded action plus execution noise drawn from ``rng``."""
        angle, speed = self.decode(action)
        if rng is not None and self.aim_noise_deg > 0:
            angle += math.radians(self.aim_noise_deg) * float(rng.standard_normal())
        if rng is not None and self.speed_noise > 0:
            speed = max(0.0, speed + self.speed_noise * float(rng.standard_normal()))
        angle = math.atan2(math.sin(angle), math.cos(angle))
        return Shot(angle=angle, speed=speed)


def paper_action_map(
    action_type: ActionType | str = ActionType.DISCRETE, aim_noise_deg: float = 0.0, speed_noise: float = 0.0
) -> ActionMap:
    """The paper's actions in SI units: 36000 directions, its 30 power levels, its continuous power range."""
    from pix2pockets.physics.paper import PAPER_POWER_LEVELS, paper_continuous_speed, paper_level_speed

    return ActionMap(
        ActionType(action_type),
        36_000,
        PAPER_POWER_LEVELS,
        float(paper_level_speed(1)),
        float(paper_level_speed(PAPER_POWER_LEVELS)),
        aim_noise_deg,
        speed_noise,
        paper_continuous_speed(1.0),
    )

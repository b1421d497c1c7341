"""A cue stroke: direction, speed and where the tip meets the cue ball."""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Shot:
    """One stroke on the cue ball.

    Attributes:
        angle: direction of the cue-ball velocity in the table frame [rad], counter-clockwise from +x.
        speed: initial cue-ball speed [m/s].
        side: horizontal tip offset as a fraction of the ball radius, +right (English), in [-0.5, 0.5].
        height: vertical tip offset as a fraction of the ball radius, +up (follow) / -down (draw),
            in [-0.5, 0.5].
        elevation: cue elevation above horizontal [rad], in [0, pi/2).
    """

    angle: float
    speed: float
    side: float = 0.0
    height: float = 0.0
    elevation: float = 0.0

    def __post_init__(self) -> None:
        for name in ("angle", "speed", "side", "height", "elevation"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"Shot.{name} must be finite, got {getattr(self, name)!r}")
        if self.speed < 0:
            raise ValueError(f"Shot.speed must be >= 0 m/s, got {self.speed}")
        if math.hypot(self.side, self.height) > 0.5 + 1e-9:
            raise ValueError(f"tip offset ({self.side}, {self.height}) is beyond 0.5 ball radius: the cue would miscue")
        if not 0.0 <= self.elevation < math.pi / 2:
            raise ValueError(f"Shot.elevation must be in [0, pi/2) rad, got {self.elevation}")

    @property
    def angle_deg(self) -> float:
        """Direction in degrees, in [0, 360)."""
        return math.degrees(self.angle) % 360.0

    @classmethod
    def toward(cls, start: tuple[float, float], target: tuple[float, float], speed: float, **kw: float) -> Shot:
        """A shot from ``start`` aimed at ``target`` (table points [m])."""
        angle = math.atan2(target[1] - start[1], target[0] - start[0])
        return cls(angle=angle, speed=speed, **kw)

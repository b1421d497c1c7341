"""Execution noise: how a real stroke deviates from the planned one.

All models are Gaussian and independent per stroke parameter; ``none`` is the zero model. The ``fastfiz``
preset is the noise of the Computational Pool tournaments (FastFiz): standard deviations of 0.125 deg in
cue direction, 0.075 m/s in speed, 0.1 deg in elevation and 0.5 mm in each tip offset.

Skill levels (:data:`SKILLS`, names ``pro``, ``club``, ``beginner``) are noise models for human players:
``pro`` is FastFiz's published noise; ``club`` and ``beginner`` are estimates (see ``docs/planner.md``,
"Skill levels", for their sources and how they were chosen). A custom model is read from a small JSON file
(:func:`load_noise_file`): ``{"name": "me", "aim_deg": 0.3, "speed_mps": 0.15, "elevation_deg": 0.5,
"tip_mm": 1.5}``.

Example:
    >>> import numpy as np
    >>> from pix2pockets.state import Shot
    >>> noise = noise_model("fastfiz")
    >>> noisy = noise.perturb(Shot(angle=0.0, speed=2.0), np.random.default_rng(0))
    >>> abs(noisy.angle) < 0.05
    True

References:
    Archibald, Altman, Shoham: "Analysis of a winning computational billiards player", IJCAI 2009
    (FastFiz noise model used in the ICGA computational pool tournaments).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol, runtime_checkable

import numpy as np

from pix2pockets.state import Shot

BALL_RADIUS = 0.05715 / 2  # [m] converts tip offsets [m] to fractions of the radius
MAX_TIP = 0.5  # largest tip offset as a fraction of the ball radius (Shot's limit)


@runtime_checkable
class NoiseModel(Protocol):
    """Turns a planned stroke into an executed one."""

    name: str

    def perturb(self, shot: Shot, rng: np.random.Generator) -> Shot:
        """One noisy execution of ``shot``."""
        ...

    def perturb_many(self, shot: Shot, rng: np.random.Generator, n: int) -> list[Shot]:
        """``n`` independent noisy executions of ``shot``."""
        ...

    def apply(self, shot: Shot, z: np.ndarray) -> Shot:
        """``shot`` perturbed by five standard-normal draws ``z``."""
        ...


@dataclass(frozen=True, slots=True)
class GaussianNoise:
    """Independent Gaussian noise on each stroke parameter.

    Attributes:
        name: display name.
        angle_sigma: cue direction standard deviation [rad].
        speed_sigma: cue-ball speed standard deviation [m/s].
        elevation_sigma: cue elevation standard deviation [rad] (folded to stay >= 0).
        tip_sigma: tip offset standard deviation, each axis [m].
        ball_radius: converts ``tip_sigma`` to the fraction of the radius a :class:`Shot` uses [m].
    """

    name: str = "gaussian"
    angle_sigma: float = 0.0
    speed_sigma: float = 0.0
    elevation_sigma: float = 0.0
    tip_sigma: float = 0.0
    ball_radius: float = BALL_RADIUS

    def __post_init__(self) -> None:
        for field in ("angle_sigma", "speed_sigma", "elevation_sigma", "tip_sigma"):
            value = getattr(self, field)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"GaussianNoise.{field} must be a finite number >= 0, got {value!r}")
        if not self.ball_radius > 0:
            raise ValueError(f"GaussianNoise.ball_radius must be positive, got {self.ball_radius}")

    @property
    def is_zero(self) -> bool:
        """Whether the model leaves every shot unchanged."""
        return not (self.angle_sigma or self.speed_sigma or self.elevation_sigma or self.tip_sigma)

    def scaled(self, factor: float) -> GaussianNoise:
        """The same model with every sigma multiplied by ``factor``."""
        if not factor >= 0:
            raise ValueError(f"noise scale must be >= 0, got {factor}")
        return GaussianNoise(
            f"{self.name}x{factor:g}",
            self.angle_sigma * factor,
            self.speed_sigma * factor,
            self.elevation_sigma * factor,
            self.tip_sigma * factor,
            self.ball_radius,
        )

    def perturb(self, shot: Shot, rng: np.random.Generator) -> Shot:
        """One noisy execution of ``shot`` (the rng is advanced even for the zero model, for reproducibility)."""
        return self.apply(shot, rng.standard_normal(5))

    def perturb_many(self, shot: Shot, rng: np.random.Generator, n: int) -> list[Shot]:
        """``n`` noisy executions of ``shot``."""
        if n < 0:
            raise ValueError(f"n must be >= 0, got {n}")
        z = rng.standard_normal((n, 5))
        return [self.apply(shot, row) for row in z]

    def apply(self, shot: Shot, z: np.ndarray) -> Shot:
        """``shot`` perturbed by the standard-normal draws ``z`` (angle, speed, elevation, side, height).

        Planners use the same draws for every candidate (common random numbers) to compare them fairly.
        """
        if self.is_zero:
            return shot
        z = [float(v) for v in z]
        angle = shot.angle + self.angle_sigma * z[0]
        speed = max(0.0, shot.speed + self.speed_sigma * z[1])
        elevation = min(abs(shot.elevation + self.elevation_sigma * z[2]), math.pi / 2 - 1e-6)
        side = shot.side + self.tip_sigma / self.ball_radius * z[3]
        height = shot.height + self.tip_sigma / self.ball_radius * z[4]
        norm = math.hypot(side, height)
        if norm > MAX_TIP:  # a miscue in reality; keep it a legal stroke at the edge of the tip area
            side, height = side * MAX_TIP / norm, height * MAX_TIP / norm
        return Shot(angle=angle, speed=speed, side=side, height=height, elevation=elevation)


NO_NOISE = GaussianNoise("none")
FASTFIZ = GaussianNoise(
    "fastfiz",
    angle_sigma=math.radians(0.125),
    speed_sigma=0.075,
    elevation_sigma=math.radians(0.1),
    tip_sigma=0.0005,
)


def skill_noise(name: str, aim_deg: float, speed_mps: float, elevation_deg: float, tip_mm: float) -> GaussianNoise:
    """A human skill level as Gaussian stroke noise (sigmas in the units players quote: deg, m/s, deg, mm)."""
    return GaussianNoise(
        name,
        angle_sigma=math.radians(aim_deg),
        speed_sigma=speed_mps,
        elevation_sigma=math.radians(elevation_deg),
        tip_sigma=tip_mm / 1000.0,
    )


SKILLS: dict[str, GaussianNoise] = {
    "pro": skill_noise("pro", 0.125, 0.075, 0.1, 0.5),  # FastFiz (published); a robot-level player
    "club": skill_noise("club", 0.2, 0.15, 0.5, 1.5),  # estimate (see docs)
    "beginner": skill_noise("beginner", 0.4, 0.3, 1.0, 3.0),  # estimate (see docs)
}
"""Skill levels, best first. Parameters and sources: ``docs/planner.md`` ("Skill levels")."""

NOISE_PRESETS: dict[str, GaussianNoise] = {
    "none": NO_NOISE,
    "fastfiz": FASTFIZ,
    "fastfiz5x": FASTFIZ.scaled(5.0),
    **SKILLS,
}

_FILE_KEYS = {"name", "aim_deg", "speed_mps", "elevation_deg", "tip_mm"}


def load_noise_file(path: str | Path) -> GaussianNoise:
    """A custom skill level from a JSON file.

    The file holds ``aim_deg`` (cue direction sigma [deg]) and optionally ``speed_mps`` [m/s],
    ``elevation_deg`` [deg], ``tip_mm`` [mm] (each tip axis) and ``name`` (default: the file's stem).

    Raises:
        ValueError: unreadable file, unknown keys, or a sigma that is negative or not a number.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as err:
        raise ValueError(f"cannot read noise file {str(path)!r}: {err}") from None
    if not isinstance(data, dict) or "aim_deg" not in data:
        raise ValueError(f"noise file {str(path)!r} must be a JSON object with at least 'aim_deg'")
    unknown = set(data) - _FILE_KEYS
    if unknown:
        raise ValueError(f"noise file {str(path)!r}: unknown keys {sorted(unknown)}; known: {sorted(_FILE_KEYS)}")
    values = {}
    for key in ("aim_deg", "speed_mps", "elevation_deg", "tip_mm"):
        value = data.get(key, 0.0)
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ValueError(f"noise file {str(path)!r}: {key} must be a number, got {value!r}")
        values[key] = float(value)
    name = str(data.get("name", path.stem))
    try:
        return skill_noise(name, **values)
    except ValueError as err:
        raise ValueError(f"noise file {str(path)!r}: {err}") from None


def aim_noise(sigma_deg: float) -> GaussianNoise:
    """Gaussian noise on the cue direction only (the paper's aim-precision experiment), sigma in degrees."""
    return GaussianNoise(f"aim{sigma_deg:g}", angle_sigma=math.radians(sigma_deg))


def noise_model(name: str) -> GaussianNoise:
    """A noise model by name.

    Names: ``none``, ``fastfiz``, ``fastfiz5x``, the skill levels ``pro``, ``club``, ``beginner``,
    ``aim:<deg>`` (direction only), ``gauss:<deg>:<m/s>`` (direction and speed sigmas), or the path of a
    JSON file ending in ``.json`` (:func:`load_noise_file`).
    """
    if name in NOISE_PRESETS:
        return NOISE_PRESETS[name]
    if name.endswith(".json"):
        return load_noise_file(name)
    parts = name.split(":")
    try:
        if parts[0] == "aim" and len(parts) == 2:
            return aim_noise(float(parts[1]))
        if parts[0] == "gauss" and len(parts) == 3:
            return GaussianNoise(name, angle_sigma=math.radians(float(parts[1])), speed_sigma=float(parts[2]))
    except ValueError as err:
        raise ValueError(f"bad noise model {name!r}: {err}") from None
    raise ValueError(
        f"unknown noise model {name!r}; use one of {sorted(NOISE_PRESETS)}, 'aim:<deg>', 'gauss:<deg>:<m/s>' "
        "or a FILE.json"
    )

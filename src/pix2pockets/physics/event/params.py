"""Physical parameters of the event-based simulator."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# Index of each parameter in the packed float array the compiled kernels read.
P_MU_SLIDE, P_MU_ROLL, P_MU_SPIN, P_E_BALL, P_E_CUSHION, P_MU_CUSHION, P_G, P_R = range(8)
P_V_SETTLE = 8
P_CUSHION_SIN = 9  # sine of the angle between the cushion contact normal and the table plane
P_BALL_FRICTION = 10  # 1.0: ball-ball friction (throw), 0.0: frictionless ball-ball impacts
N_PARAMS = 11
BALL_FIELDS = 3
"""Entries per ball in the optional per-ball block after the ``N_PARAMS`` shared ones: radius [m], mass relative
to an object ball [-] and the sine of its cushion contact tilt (:func:`ball_block`). Without the block every ball
has ``P_R``, mass 1 and ``P_CUSHION_SIN``."""
B_RADIUS, B_MASS, B_CUSHION_SIN = range(BALL_FIELDS)

BALL_FRICTION_FIT = (9.951e-3, 0.108, 1.088)
"""``(a, b, c)`` of the ball-ball friction coefficient ``a + b exp(-c v)`` at contact slip speed ``v`` [m/s]
(Alciatore, TP A-14)."""

SPIN_FRICTION_PER_METRE = 10.0 * 2.0 / (5.0 * 9.0)
"""pooltool's spinning-friction proportionality [1/m]: ``mu_spin = SPIN_FRICTION_PER_METRE * R``."""


@dataclass(frozen=True, slots=True)
class PhysicsParams:
    """Ball, cloth and cushion constants (SI units). Defaults are pooltool 0.6.0's.

    Attributes:
        mu_slide: ball-cloth sliding friction coefficient [-] (0.2).
        mu_roll: ball-cloth rolling resistance coefficient [-] (0.01).
        mu_spin: ball-cloth spinning friction coefficient [-]; ``None`` means pooltool's rule
            ``10 * 2 / (5 * 9) * R`` with ``R`` the ball radius in metres (about 0.0127 for a 57.15 mm
            ball), so the z-spin decays at ``5 * mu_spin * g / (2 R)`` [rad/s^2] (about 10.9 rad/s^2).
        e_ball: ball-ball coefficient of restitution [-] (0.95).
        e_cushion: ball-cushion (and jaw) coefficient of restitution [-] (0.85).
        mu_cushion: ball-cushion Coulomb friction coefficient [-] (0.2).
        g: gravitational acceleration [m/s^2] (9.81).
        ball_friction: friction between the balls at an impact (throw: a cut throws the object ball off the line of
            centres by up to a few degrees, spin is passed between the balls), with the coefficient falling with
            the slip speed ``v`` at the contact [m/s] as Alciatore's fit to measured throw,
            ``0.00995 + 0.108 exp(-1.088 v)`` (``BALL_FRICTION_FIT``); off by default, the frictionless impact the
            shipped benchmarks and agents were measured and trained on.
        settle_speed: a cushion or ball-ball impact slower than this is perfectly inelastic along the
            normal and also loses the spin that would drive the ball back into the contact [m/s]. It
            ends the otherwise endless sequence of ever-smaller bounces of a ball pressed into a rail.
        max_events: maximum number of events in one shot; exceeding it raises ``RuntimeError``
            (``simulate``) or flags the shot (lean batch), so no shot can hang.

    References:
        pooltool 0.6.0 default ball and table parameters and their sources:
        https://pooltool.readthedocs.io (Ball parameters; "spinning friction" proportionality);
        W. Leckie and M. Greenspan, "An event-based pool physics simulator", Advances in Computer
        Games 11, 2006 (the sliding/rolling/spinning motion equations used here);
        D. Alciatore, "Technical proof A-14: ball-ball collision throw" (billiards.colostate.edu/technical_proofs,
        TP A-14), for the ball-ball friction fit;
        R. Kolbe, "Billiards physics" notes / Alciatore, "The Illustrated Principles of Pool and
        Billiards" (2004) for the typical 0.2 / 0.01 friction and 0.95 restitution values.
    """

    mu_slide: float = 0.2
    mu_roll: float = 0.01
    mu_spin: float | None = None
    e_ball: float = 0.95
    e_cushion: float = 0.85
    mu_cushion: float = 0.2
    g: float = 9.81
    ball_friction: bool = False
    settle_speed: float = 1e-3
    max_events: int = 20_000

    def __post_init__(self) -> None:
        for name in ("mu_slide", "mu_roll", "g", "settle_speed"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"PhysicsParams.{name} must be a positive number, got {value!r}")
        if self.mu_spin is not None and not (math.isfinite(self.mu_spin) and self.mu_spin > 0):
            raise ValueError(f"PhysicsParams.mu_spin must be positive or None, got {self.mu_spin!r}")
        if self.mu_cushion < 0 or not math.isfinite(self.mu_cushion):
            raise ValueError(f"PhysicsParams.mu_cushion must be >= 0, got {self.mu_cushion!r}")
        for name in ("e_ball", "e_cushion"):
            value = getattr(self, name)
            if not 0.0 <= value <= 1.0:
                raise ValueError(f"PhysicsParams.{name} must be in [0, 1], got {value!r}")
        if not isinstance(self.ball_friction, bool):
            raise ValueError(f"PhysicsParams.ball_friction must be True or False, got {self.ball_friction!r}")
        if int(self.max_events) != self.max_events or self.max_events < 10:
            raise ValueError(f"PhysicsParams.max_events must be an integer >= 10, got {self.max_events!r}")

    def spin_friction(self, ball_radius: float) -> float:
        """The spinning friction coefficient for balls of ``ball_radius`` [m]."""
        return SPIN_FRICTION_PER_METRE * ball_radius if self.mu_spin is None else self.mu_spin

    def packed(self, ball_radius: float, cushion_height: float | None = None) -> np.ndarray:
        """The parameters as the float array the compiled kernels read (``P_*`` indices).

        Args:
            ball_radius: ball radius ``R`` [m].
            cushion_height: height of the cushion nose above the cloth [m]; the contact normal then
                tilts down by ``asin((h - R) / R)``. ``None`` puts the contact on the ball's equator.
        """
        out = np.empty(N_PARAMS)
        out[P_MU_SLIDE] = self.mu_slide
        out[P_MU_ROLL] = self.mu_roll
        out[P_MU_SPIN] = self.spin_friction(ball_radius)
        out[P_E_BALL] = self.e_ball
        out[P_E_CUSHION] = self.e_cushion
        out[P_MU_CUSHION] = self.mu_cushion
        out[P_G] = self.g
        out[P_R] = ball_radius
        out[P_V_SETTLE] = self.settle_speed
        out[P_CUSHION_SIN] = cushion_sine(ball_radius, cushion_height)
        out[P_BALL_FRICTION] = 1.0 if self.ball_friction else 0.0
        return out

    def packed_balls(
        self, ball_radius: float, cushion_height: float | None, radii: np.ndarray, masses: np.ndarray
    ) -> np.ndarray:
        """:meth:`packed` followed by the per-ball block: ball ``i``'s radius ``radii[i]`` [m] and mass ``masses[i]``
        relative to an object ball, for balls of different sizes (a UK set's smaller cue ball)."""
        radii = np.asarray(radii, dtype=float).reshape(-1)
        masses = np.asarray(masses, dtype=float).reshape(-1)
        if radii.shape != masses.shape or not (np.all(radii > 0) and np.all(masses > 0)):
            raise ValueError("radii and masses must be positive, one of each per ball")
        block = np.column_stack([radii, masses, [cushion_sine(r, cushion_height) for r in radii]])
        return np.concatenate([self.packed(ball_radius, cushion_height), block.reshape(-1)])


def cushion_sine(ball_radius: float, cushion_height: float | None) -> float:
    """Sine of the downward tilt of the cushion contact normal for a ball of ``ball_radius`` [m]: the nose at
    ``cushion_height`` [m] touches it ``asin((h - R) / R)`` above its equator (0 for ``None``)."""
    sin_tilt = 0.0 if cushion_height is None else (cushion_height - ball_radius) / ball_radius
    if not -1.0 < sin_tilt < 1.0:
        raise ValueError(f"cushion height {cushion_height} m must be between 0 and 2 R = {2 * ball_radius} m")
    return sin_tilt

"""Parameters of the ``paper`` simulator: the seed paper's pymunk world, in SI units."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pix2pockets.geometry.raster import PAPER_LAYOUT
from pix2pockets.physics.paper._kernel import (
    N_PARAMS,
    P_CLOCK,
    P_DT,
    P_E_BALL,
    P_E_CUSHION,
    P_K,
    P_MAX_STEPS,
    P_MU_BALL,
    P_MU_CUSHION,
    P_R,
    P_SLEEP2,
    P_SPIN,
    P_SURFACE_BAND,
)

PAPER_PX = PAPER_LAYOUT.metres_per_px
"""Metres per pixel of the paper's world at zoom 2 (1.942 mm)."""


@dataclass(frozen=True, slots=True)
class PaperParams:
    """Constants of the paper's environment (its pymunk settings), converted to SI units.

    Attributes:
        damping: fraction of velocity (and disc spin) kept after one second (pymunk ``Space.damping``,
            the paper's 0.9: 10% lost per second, its only rolling loss).
        substep: physics step [s] (the paper: 30 pymunk steps of 1/300 s per 0.1 s frame). Contacts are
            found at the end of a step, as pymunk does, so a collision is resolved with the balls up to
            one step of travel into each other.
        sleep_speed: a ball falls asleep (stops) at the first step it starts slower than this [m/s]
            (pymunk ``idle_speed_threshold`` of 5 px/s, ``sleep_time_threshold`` ~0). With ``disc_spin``
            the disc's spin counts as pymunk counts it: ``v^2 + (R^2 / 2) w^2``.
        cushion_restitution: normal restitution of the cushion impulse (the paper's 0.95 x 0.8: pymunk
            multiplies the two shapes' elasticities). It sets only the rebound speed: the paper's code
            then turns the velocity into the mirror image of the incoming one.
        cushion_friction: friction of the cushion impulse (0.9 x 0.5).
        ball_restitution: normal restitution of pymunk's ball-ball impulse (0.95 x 0.95); the linear
            velocities are then replaced by the ideal elastic exchange, as the paper's code does, so it
            only bounds the friction impulse that spins the discs.
        ball_friction: friction of the ball-ball impulse (0.9 x 0.9).
        disc_spin: track the discs' spin as pymunk does (balls are discs with ``I = m R^2 / 2`` there):
            friction at contacts spins them, spin changes the cushion rebound speed and keeps a ball
            awake. ``False``: balls never spin.
        max_time: simulated-time cap [s]; a shot still moving then fails (``RuntimeError`` from
            ``simulate``, status 1 in batches). The paper's loop gave up after 1000 s.
        max_events: event budget per shot (contacts, drops, sleeps).
        surface_band: a ball at rest up to this far past a cushion-nose line is moved back onto the
            surface (a contact it fell asleep in); further out it rests in a pocket mouth and drops [m].
    """

    damping: float = 0.9
    substep: float = 1.0 / 300.0
    sleep_speed: float = 5.0 * PAPER_PX
    cushion_restitution: float = 0.95 * 0.8
    cushion_friction: float = 0.9 * 0.5
    ball_restitution: float = 0.95 * 0.95
    ball_friction: float = 0.9 * 0.9
    disc_spin: bool = True
    max_time: float = 1000.0
    max_events: int = 20_000
    surface_band: float = PAPER_PX

    def __post_init__(self) -> None:
        if not 0.0 < self.damping < 1.0:
            raise ValueError(f"PaperParams.damping must be in (0, 1), got {self.damping!r}")
        for name in ("substep", "sleep_speed", "max_time", "surface_band"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"PaperParams.{name} must be a positive number, got {value!r}")
        for name in ("cushion_restitution", "ball_restitution"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"PaperParams.{name} must be in [0, 1], got {getattr(self, name)!r}")
        for name in ("cushion_friction", "ball_friction"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"PaperParams.{name} must be >= 0, got {value!r}")
        if int(self.max_events) != self.max_events or self.max_events < 10:
            raise ValueError(f"PaperParams.max_events must be an integer >= 10, got {self.max_events!r}")

    @property
    def decay_rate(self) -> float:
        """Exponential decay rate of every velocity [1/s]: ``-ln(damping)``."""
        return -math.log(self.damping)

    def packed(self, ball_radius: float) -> np.ndarray:
        """The parameters as the float array the compiled kernel reads (``P_*`` indices)."""
        k, dt = self.decay_rate, self.substep
        out = np.empty(N_PARAMS)
        out[P_K] = k
        out[P_DT] = dt
        # pymunk moves a ball by v dt per step and then damps v: scaling the continuous clock by this
        # factor puts the closed-form positions exactly on pymunk's at every step.
        out[P_CLOCK] = k * dt / -math.expm1(-k * dt)
        out[P_R] = ball_radius
        out[P_SLEEP2] = self.sleep_speed**2
        out[P_E_CUSHION] = self.cushion_restitution
        out[P_MU_CUSHION] = self.cushion_friction
        out[P_E_BALL] = self.ball_restitution
        out[P_MU_BALL] = self.ball_friction
        out[P_SPIN] = 1.0 if self.disc_spin else 0.0
        out[P_MAX_STEPS] = math.ceil(self.max_time / dt)
        out[P_SURFACE_BAND] = self.surface_band
        return out

"""Each ball's radius, mass and cushion tilt from the packed parameters (numba helpers).

The packed array holds the shared parameters (``params.P_*``) and, for balls of different sizes, a block of
``BALL_FIELDS`` entries per ball after them (:meth:`~pix2pockets.physics.event.params.PhysicsParams.packed_balls`).
Without the block every ball is an object ball: radius ``P_R``, mass 1, tilt ``P_CUSHION_SIN``.
"""

from __future__ import annotations

from numba import njit

from pix2pockets.physics.event.params import (
    B_CUSHION_SIN,
    B_MASS,
    B_RADIUS,
    BALL_FIELDS,
    N_PARAMS,
    P_CUSHION_SIN,
    P_R,
)


@njit(cache=True, inline="always")
def radius_of(prm, i) -> float:
    """Ball ``i``'s radius [m]."""
    k = N_PARAMS + BALL_FIELDS * i + B_RADIUS
    return prm[k] if k < prm.shape[0] else prm[P_R]


@njit(cache=True, inline="always")
def mass_of(prm, i) -> float:
    """Ball ``i``'s mass relative to an object ball [-]."""
    k = N_PARAMS + BALL_FIELDS * i + B_MASS
    return prm[k] if k < prm.shape[0] else 1.0


@njit(cache=True, inline="always")
def cushion_sin_of(prm, i) -> float:
    """Sine of ball ``i``'s cushion contact tilt below its equator [-]."""
    k = N_PARAMS + BALL_FIELDS * i + B_CUSHION_SIN
    return prm[k] if k < prm.shape[0] else prm[P_CUSHION_SIN]

"""Geometric shot difficulty and the value of a cue-ball position (one shot of look-ahead).

A cue-direction error ``dphi`` moves the cue ball sideways by ``D dphi`` at the ghost ball (``D`` the cue
path length); that changes the cut and turns the object ball by about ``D dphi / (2 r cos(cut))``. The
shot pots while the object-ball direction stays inside the pocket's clear window, so with Gaussian aim
noise ``sigma`` the pot probability is ``erf(half_window / (sigma_obj sqrt 2))``.

References:
    D. G. Alciatore, "The Illustrated Principles of Pool and Billiards" (2004): ghost-ball aiming and
    margin-for-error analysis (TP 3.4-3.6).
"""

from __future__ import annotations

import math

from pix2pockets.planner.base import legal_targets
from pix2pockets.planner.hitpoints import Hitpoint, ShotKind, find_hitpoints
from pix2pockets.rules import GameState
from pix2pockets.state import TableLayout

KIND_FACTOR: dict[ShotKind, float] = {ShotKind.DIRECT: 1.0, ShotKind.BANK: 0.6, ShotKind.KICK: 0.5}
"""Extra discount for cushion shots: the ideal-reflection model is only approximate."""


def pot_probability(hp: Hitpoint, radius: float, sigma: float, distance_sigma: float = 0.0) -> float:
    """Geometric probability that aim noise ``sigma`` [rad] still pots hitpoint ``hp``.

    Args:
        hp: the hitpoint.
        radius: ball radius [m].
        sigma: cue-direction standard deviation [rad] (> 0).
        distance_sigma: extra object-ball direction noise per metre of object path [rad / m], a crude
            stand-in for cloth and speed errors.
    """
    if sigma <= 0:
        raise ValueError(f"sigma must be positive, got {sigma}")
    cos_cut = max(math.cos(hp.cut_angle), 0.05)
    s_obj = hp.cue_distance * sigma / (2.0 * radius * cos_cut)
    s_obj = math.hypot(s_obj, sigma, distance_sigma * hp.object_distance)
    p = math.erf(0.5 * hp.clear_window / (s_obj * math.sqrt(2.0)))
    return p * KIND_FACTOR[hp.kind]


def position_value(
    layout: TableLayout,
    state: GameState,
    sigma: float,
    kinds: tuple[ShotKind, ...] = (ShotKind.DIRECT,),
) -> float:
    """Best next-shot pot probability from ``layout`` (1 when nothing is left to pot, 0 without a cue ball)."""
    if layout.cue_index is None:
        return 0.0
    targets = legal_targets(layout, state)
    if not targets:
        return 1.0
    r = layout.spec.ball_radius
    best = 0.0
    for hp in find_hitpoints(layout, targets, kinds=kinds):
        best = max(best, pot_probability(hp, r, sigma))
    return best

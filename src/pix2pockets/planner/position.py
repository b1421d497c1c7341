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

import numpy as np
from numba import njit

import pix2pockets.physics.event  # noqa: F401  (numba's cache folder is chosen there)
from pix2pockets.geometry.table import TableSpec
from pix2pockets.planner.hitpoints import Hitpoint, ShotKind

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


def direct_pot_probabilities(
    positions: np.ndarray,
    cue: int,
    targets: list[int] | np.ndarray,
    spec: TableSpec,
    sigma: float,
    max_cut: float = math.radians(80.0),
) -> np.ndarray:
    """Vectorised :func:`pot_probability` of every direct (target, pocket) pair, 0 where no hitpoint.

    Same geometry as :func:`~pix2pockets.planner.hitpoints.find_hitpoints` with direct shots and default
    clearance, compiled by numba; used for the look-ahead on many simulated outcomes.

    Args:
        positions: all ball centres [m], shape (n, 2).
        cue: index of the cue ball.
        targets: indices of the legal object balls.
        spec: the table.
        sigma: cue-direction standard deviation [rad].
        max_cut: largest cut angle [rad].

    Returns:
        Probabilities, shape (len(targets), 6).
    """
    targets = np.asarray(targets, dtype=np.int64)
    if len(targets) == 0:
        return np.zeros((0, 6))
    jaws = np.array([p.jaws for p in spec.pockets], dtype=float)  # (6, 2, 2)
    pos = np.ascontiguousarray(positions, dtype=float)
    r, contact = spec.ball_radius, spec.cue_contact_distance
    return _direct_pots(pos, int(cue), targets, jaws, r, contact, spec.length, spec.width, sigma, max_cut)


@njit(cache=True)
def _segment_blocked(sx, sy, ex, ey, pos, cue, target, clearance):  # pragma: no cover - compiled
    """Whether a ball other than ``cue`` and ``target`` lies within ``clearance`` of segment s-e."""
    dx, dy = ex - sx, ey - sy
    l2 = max(dx * dx + dy * dy, 1e-18)
    c2 = clearance * clearance
    for j in range(pos.shape[0]):
        if j in (cue, target):
            continue
        rx, ry = pos[j, 0] - sx, pos[j, 1] - sy
        t = min(max((rx * dx + ry * dy) / l2, 0.0), 1.0)
        qx, qy = rx - t * dx, ry - t * dy
        if qx * qx + qy * qy < c2:
            return True
    return False


@njit(cache=True)
def _direct_pots(pos, cue, targets, jaws, r, contact, length, width, sigma, max_cut):  # pragma: no cover - compiled
    """The loops of :func:`direct_pot_probabilities`: (len(targets), 6) probabilities; ``r`` the object balls' radius,
    ``contact`` the cue and object centres' distance at impact [m]."""
    out = np.zeros((len(targets), 6))
    cos_max = math.cos(max_cut)
    margin = r - 1e-9
    cx, cy = pos[cue, 0], pos[cue, 1]
    for i in range(len(targets)):
        t = targets[i]
        bx, by = pos[t, 0], pos[t, 1]
        for k in range(6):
            j1x, j1y, j2x, j2y = jaws[k, 0, 0], jaws[k, 0, 1], jaws[k, 1, 0], jaws[k, 1, 1]
            v1x, v1y, v2x, v2y = j1x - bx, j1y - by, j2x - bx, j2y - by
            d1, d2 = math.hypot(v1x, v1y), math.hypot(v2x, v2y)
            a1, a2 = math.atan2(v1y, v1x), math.atan2(v2y, v2x)
            window = math.atan2(math.sin(a2 - a1), math.cos(a2 - a1))
            if window < 0:
                a1, d1, d2 = a2, d2, d1
            window = abs(window)
            if not (d1 > r and d2 > r):
                continue
            lo = a1 + math.asin(min(r / max(d1, r), 1.0))
            hi = a1 + window - math.asin(min(r / max(d2, r), 1.0))
            clear = hi - lo
            if not clear > 0:
                continue
            aim = 0.5 * (lo + hi)
            ux, uy = math.cos(aim), math.sin(aim)
            # the object path ends where the ray crosses the jaw line
            ex, ey = j2x - j1x, j2y - j1y
            den = ux * ey - uy * ex
            s = 0.0
            if abs(den) > 1e-12:
                s = max(((j1x - bx) * ey - (j1y - by) * ex) / den, 0.0)
            mx, my = bx + s * ux, by + s * uy
            gx, gy = bx - contact * ux, by - contact * uy
            cue_dist = math.hypot(gx - cx, gy - cy)
            if not cue_dist > 1e-9:
                continue
            cos_cut = min(max(((gx - cx) * ux + (gy - cy) * uy) / max(cue_dist, 1e-12), -1.0), 1.0)
            if cos_cut < cos_max:
                continue
            if not (margin <= gx <= length - margin and margin <= gy <= width - margin):
                continue
            if _segment_blocked(bx, by, mx, my, pos, cue, t, 2 * r):
                continue
            if _segment_blocked(cx, cy, gx, gy, pos, cue, t, 2 * r):
                continue
            s_obj = cue_dist * sigma / (contact * max(cos_cut, 0.05))
            s_obj = math.sqrt(s_obj * s_obj + sigma * sigma)
            out[i, k] = math.erf(0.5 * clear / (s_obj * math.sqrt(2.0)))
    return out


OPTION_WEIGHTS: tuple[float, ...] = (1.0, 0.33, 0.15)
"""Weights of the best, second and third next shot (at different balls) in a position's value: a position
with several good shots keeps the run going when the best one's own position play goes wrong."""


def fast_position_value(
    positions: np.ndarray,
    cue: int,
    targets: list[int],
    spec: TableSpec,
    sigma: float,
    weights: tuple[float, ...] = OPTION_WEIGHTS,
) -> float:
    """Value of a cue-ball position: weighted best direct pot probabilities at distinct balls, in [0, 1].

    ``sum(w_i p_i) / sum(w_i)`` over the best shot at each of the ``len(weights)`` best balls (fewer when
    fewer balls are left); 1 when no target is left.
    """
    if len(targets) == 0:
        return 1.0
    p = direct_pot_probabilities(positions, cue, targets, spec, sigma)
    best = np.sort(p.max(axis=1))[::-1][: len(weights)]
    w = np.asarray(weights[: len(best)], dtype=float)
    return float(best @ w / w.sum())

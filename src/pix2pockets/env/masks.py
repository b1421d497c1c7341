"""Action masks for sb3-contrib's MaskablePPO: direction bins that lead to the planner's hitpoints.

The mask of ``MultiDiscrete([n_angles, n_powers])`` is one flat boolean vector of length
``n_angles + n_powers``: the direction bins first, then the power levels. A direction bin is allowed when
it is the nearest bin (within ``width`` bins) to a hitpoint's cue direction; every power level is allowed.
When no hitpoint exists every direction is allowed (a mask is never empty).

Kinds (``MaskKind``):
    * ``direct``: straight shots only (the paper's "direct" hitpoints);
    * ``mirror``: direct, bank and kick shots from the mirror table (the paper's "direct, mirror").

Targets are the environment's target balls. In the 1-ball variant the target is the cue ball itself:
its hitpoints are the directions to each pocket's mouth (``mirror`` adds one-cushion banks).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from enum import StrEnum

import numpy as np

from pix2pockets.state import TableLayout

HitpointFinder = Callable[..., Sequence]
"""``find_hitpoints(layout, targets, kinds) -> list[Hitpoint]`` (``Hitpoint.cue_angle`` [rad] is used)."""


class MaskKind(StrEnum):
    """Which hitpoints open direction bins."""

    DIRECT = "direct"
    MIRROR = "mirror"


def _planner_kinds(kind: MaskKind) -> tuple[str, ...]:
    return ("direct",) if kind is MaskKind.DIRECT else ("direct", "bank", "kick")


def default_finder() -> HitpointFinder:
    """The planner's :func:`~pix2pockets.planner.hitpoints.find_hitpoints` (imported on first use)."""
    from pix2pockets.planner.hitpoints import find_hitpoints

    return find_hitpoints


def hitpoint_angles(
    layout: TableLayout,
    targets: Sequence[int],
    kind: MaskKind,
    finder: HitpointFinder | None = None,
) -> np.ndarray:
    """Cue directions [rad] of the hitpoints for ``targets`` (object-ball indices)."""
    if not targets:
        return np.zeros(0)
    finder = finder or default_finder()
    hits = finder(layout, list(targets), kinds=_planner_kinds(MaskKind(kind)))
    return np.array([float(h.cue_angle) for h in hits], dtype=float)


def cue_pocket_angles(layout: TableLayout, kind: MaskKind) -> np.ndarray:
    """Directions [rad] that send the lone cue ball into a pocket (straight, or off one cushion)."""
    cue = layout.cue_index
    if cue is None:
        return np.zeros(0)
    spec = layout.spec
    c = layout.positions[cue]
    aims = spec.pocket_aims
    points = [aims]
    if MaskKind(kind) is MaskKind.MIRROR:
        r = spec.ball_radius
        for axis, line in ((1, r), (0, spec.length - r), (1, spec.width - r), (0, r)):
            mirrored = aims.copy()
            mirrored[:, axis] = 2 * line - mirrored[:, axis]
            points.append(mirrored)
    d = np.vstack(points) - c
    return np.arctan2(d[:, 1], d[:, 0])


def direction_mask(angles: np.ndarray, n_angles: int, width: int = 0) -> np.ndarray:
    """Boolean mask over ``n_angles`` direction bins (bin ``a`` = ``a * 360 / n_angles - 180`` deg).

    Args:
        angles: allowed directions [rad].
        n_angles: number of bins.
        width: also allow this many neighbouring bins on each side.
    """
    mask = np.zeros(n_angles, dtype=bool)
    if len(angles) == 0:
        mask[:] = True
        return mask
    deg = np.degrees(np.asarray(angles, dtype=float)) + 180.0
    bins = np.rint(deg * n_angles / 360.0).astype(np.int64)
    for k in range(-width, width + 1):
        mask[(bins + k) % n_angles] = True
    return mask


def full_mask(direction: np.ndarray, n_powers: int) -> np.ndarray:
    """The flat MultiDiscrete mask: direction bins then all power levels."""
    return np.concatenate([direction, np.ones(n_powers, dtype=bool)])

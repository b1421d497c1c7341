"""Mirror table: reflect balls and pockets across the cushion lines for bank and kick shots.

A ball bounces off a cushion when its *centre* reaches the line one ball radius inside the cushion nose.
Reflecting a point across that line (the "mirror table" on that side) turns a one-cushion path into a
straight line: aiming at the mirror image of a pocket banks the object ball into the real pocket, aiming the
cue ball at the mirror image of a ghost ball kicks it into the real one. The model assumes an ideal
reflection (angle in = angle out); real cushions shorten the rebound angle, which the search planner's
physics check corrects for.

Penalty per cushion:
    The paper's text applies a multiplier of **0.33 per cushion** to the Oracle score (our default,
    ``PenaltyScheme.PAPER_TEXT``). The paper's released code instead multiplies bank shots by **1/2** and
    kick shots by **3/4** (``PenaltyScheme.PAPER_CODE``), which is what its measured Table 3 numbers used.

References:
    Schiøtt et al., pix2pockets, section "Introduce Mirror table" (Fig. "Mirror table").
"""

from __future__ import annotations

from enum import StrEnum

import numpy as np

from pix2pockets.geometry.table import Rail, TableSpec

RAILS: tuple[Rail, ...] = (Rail.BOTTOM, Rail.FOOT, Rail.TOP, Rail.HEAD)
"""Rails in the order used for mirror tables."""

PAPER_TEXT_PENALTY = 0.33
"""Score multiplier per cushion given in the paper's text."""

# cushion segment indices (TableSpec.cushion_segments order) and pocket indices (TableSpec.pockets order)
_RAIL_CUSHIONS: dict[Rail, tuple[int, ...]] = {
    Rail.BOTTOM: (0, 1),
    Rail.FOOT: (2,),
    Rail.TOP: (3, 4),
    Rail.HEAD: (5,),
}
_RAIL_POCKETS: dict[Rail, tuple[int, ...]] = {
    Rail.BOTTOM: (0, 1, 2),
    Rail.FOOT: (2, 3),
    Rail.TOP: (3, 4, 5),
    Rail.HEAD: (5, 0),
}


class PenaltyScheme(StrEnum):
    """How cushions lower the Oracle score."""

    PAPER_TEXT = "paper-text"  # multiplier ** n_cushions (0.33 in the paper)
    PAPER_CODE = "paper-code"  # bank 1/2, kick 3/4 (the paper's released code)


def rail_axis(rail: Rail) -> int:
    """0 when the rail's cushion line is ``x = const`` (head, foot), 1 for ``y = const`` (bottom, top)."""
    return 0 if rail in (Rail.HEAD, Rail.FOOT) else 1


def rail_line(spec: TableSpec, rail: Rail) -> float:
    """The coordinate of the line a ball centre touches the rail's cushion on [m].

    Example:
        >>> rail_line(TableSpec(), Rail.BOTTOM) == TableSpec().ball_radius
        True
    """
    r = spec.ball_radius
    return {Rail.BOTTOM: r, Rail.HEAD: r, Rail.TOP: spec.width - r, Rail.FOOT: spec.length - r}[rail]


def reflect(points: np.ndarray, spec: TableSpec, rail: Rail) -> np.ndarray:
    """Mirror points [m], shape (..., 2), across the ball-centre line of ``rail``."""
    out = np.array(points, dtype=float, copy=True)
    axis = rail_axis(rail)
    out[..., axis] = 2.0 * rail_line(spec, rail) - out[..., axis]
    return out


def bounce_point(start: np.ndarray, mirrored_end: np.ndarray, spec: TableSpec, rail: Rail) -> np.ndarray | None:
    """Where a centre moving from ``start`` toward ``mirrored_end`` meets the rail's ball-centre line [m].

    Returns ``None`` when the straight line does not cross the line between the two points (the end is not
    on the mirror side, or the start is).
    """
    axis = rail_axis(rail)
    c = rail_line(spec, rail)
    a, b = float(start[axis]) - c, float(mirrored_end[axis]) - c
    if a == b or a * b >= 0:
        return None
    t = a / (a - b)
    return np.asarray(start, dtype=float) + t * (np.asarray(mirrored_end, dtype=float) - np.asarray(start, dtype=float))


def cushion_at(point: np.ndarray, spec: TableSpec, rail: Rail, margin: float = 0.0) -> int | None:
    """Index of the cushion segment of ``rail`` a ball touching the rail at ``point`` hits, or ``None``.

    Args:
        point: a ball centre on the rail's ball-centre line [m].
        margin: required distance [m] of the contact point from the segment ends (the jaw points).
    """
    along = 1 - rail_axis(rail)
    s = float(point[along])
    segs = spec.cushion_segments
    for k in _RAIL_CUSHIONS[rail]:
        lo, hi = sorted((float(segs[k, 0, along]), float(segs[k, 1, along])))
        if lo + margin <= s <= hi - margin:
            return k
    return None


def rail_pockets(rail: Rail) -> tuple[int, ...]:
    """Pockets lying on ``rail`` (a bank off a rail cannot go into these)."""
    return _RAIL_POCKETS[rail]


def rail_of_cushion(cushion: int) -> Rail:
    """The rail a cushion segment belongs to."""
    for rail, cushions in _RAIL_CUSHIONS.items():
        if cushion in cushions:
            return rail
    raise ValueError(f"cushion index must be 0-5, got {cushion}")


def cushion_multiplier(
    kind: str,
    n_cushions: int,
    scheme: PenaltyScheme = PenaltyScheme.PAPER_TEXT,
    penalty: float = PAPER_TEXT_PENALTY,
) -> float:
    """Oracle score multiplier for a shot with ``n_cushions`` cushion contacts.

    Args:
        kind: ``"direct"``, ``"bank"`` or ``"kick"`` (a :class:`~pix2pockets.planner.hitpoints.ShotKind`).
        n_cushions: planned cushion contacts.
        scheme: ``PAPER_TEXT`` gives ``penalty ** n_cushions``; ``PAPER_CODE`` gives 1, 1/2 (bank), 3/4 (kick).
        penalty: per-cushion multiplier for ``PAPER_TEXT``, in (0, 1].
    """
    if not 0.0 < penalty <= 1.0:
        raise ValueError(f"cushion penalty must be in (0, 1], got {penalty}")
    if n_cushions < 0:
        raise ValueError(f"n_cushions must be >= 0, got {n_cushions}")
    if scheme is PenaltyScheme.PAPER_CODE:
        if n_cushions == 0:
            return 1.0
        return {"bank": 0.5, "kick": 0.75}.get(str(kind), 0.5**n_cushions)
    return penalty**n_cushions

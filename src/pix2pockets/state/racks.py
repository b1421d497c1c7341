"""Standard starting layouts: the 8-ball rack and seeded random layouts."""

from __future__ import annotations

import math

import numpy as np

from pix2pockets.geometry.table import TableSpec
from pix2pockets.state.ball import Ball, BallClass
from pix2pockets.state.layout import TableLayout

RACK_GAP = 2e-6  # [m] tiny gap between racked balls so they start exactly non-overlapping


def rack_positions(spec: TableSpec) -> np.ndarray:
    """Centres of a 15-ball triangle, apex on the foot spot, rows toward the foot rail [m], (15, 2).

    Row-major from the apex: row k (0-4) holds k + 1 balls ordered by increasing y.
    """
    d = 2 * spec.ball_radius + RACK_GAP
    apex = spec.foot_spot
    pts = []
    for row in range(5):
        x = apex[0] + row * d * math.sqrt(3) / 2
        for k in range(row + 1):
            pts.append((x, apex[1] + (k - row / 2) * d))
    return np.array(pts)


def eight_ball_rack(spec: TableSpec | None = None, rng: np.random.Generator | None = None) -> TableLayout:
    """A legal 8-ball rack plus the cue ball on the head spot.

    The 8 sits in the middle of the third row, a solid and a stripe in the two back corners; the other
    balls are shuffled with ``rng`` (fixed order without one). Ball 0 of the layout is the cue ball.
    """
    spec = spec or TableSpec()
    others = [n for n in range(1, 16) if n not in (8, 1, 9)]
    if rng is not None:
        rng.shuffle(others)
    corner_a, corner_b = (1, 9) if rng is None or rng.random() < 0.5 else (9, 1)
    order = [0] * 15
    order[4] = 8  # middle of row 3 (indices 3, 4, 5)
    order[10], order[14] = corner_a, corner_b  # back row ends
    fill = iter(others)
    for i in range(15):
        if i not in (4, 10, 14):
            order[i] = next(fill)
    balls = (Ball(BallClass.CUE, 0), *tuple(Ball.numbered(n) for n in order))
    positions = np.vstack([spec.head_spot, rack_positions(spec)])
    return TableLayout(balls, positions, spec)


def random_layout(
    rng: np.random.Generator,
    numbers: list[int] | tuple[int, ...],
    spec: TableSpec | None = None,
    pocket_clearance: float | None = None,
    max_tries: int = 10_000,
) -> TableLayout:
    """Balls with the given numbers at uniform random non-overlapping spots (seeded by ``rng``).

    Centres keep one ball radius from the cushions and ``pocket_clearance`` [m] (default one ball
    diameter) from every pocket's capture circle, so no ball starts in or touching a pocket.
    """
    spec = spec or TableSpec()
    r = spec.ball_radius
    clearance = 2 * r if pocket_clearance is None else pocket_clearance
    centres = spec.pocket_centres
    radii = np.array([p.capture_radius for p in spec.pockets])
    lo = np.array([r, r])
    span = spec.size - r - lo
    pocket_lim2 = (radii + clearance) ** 2  # squared distances: same decisions, no sqrt
    ball_lim2 = (2 * r + 1e-6) ** 2
    placed = np.empty((len(numbers), 2))
    tries = 0
    for n in range(len(numbers)):
        while True:
            tries += 1
            if tries > max_tries:
                raise ValueError(f"could not place {len(numbers)} balls without overlap in {max_tries} tries")
            p = lo + rng.random(2) * span
            d = centres - p
            if np.any(np.einsum("ij,ij->i", d, d) < pocket_lim2):
                continue
            if n:
                d = placed[:n] - p
                if np.einsum("ij,ij->i", d, d).min() < ball_lim2:
                    continue
            placed[n] = p
            break
    balls = tuple(Ball.numbered(n) for n in numbers)
    return TableLayout(balls, placed, spec)

"""Cloth candidates in a shrunk photo: regions of one colour that four straight lines could bound.

Seed colours come from where the cloth must be (around the detected balls) and from the uniform cells of a grid over
the photo. For each, the photo is thresholded in CIE Lab at a ladder of tolerances (lightness looser than chroma:
lamps light a cloth unevenly) and flood-filled step by step from the pixels nearest the colour (a fill follows a
lamp's gradient across the cloth, a threshold does not). Each large, nearly convex region is scored by how well the
quadrilateral enclosing it fits it (:func:`score_region`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from pix2pockets.vision.table.quad_geometry import enclosing_quad, quad_mask

SEED_GRID = 12
"""The photo is cut into this many cells across and down; the colours of uniform cells seed the cloth."""
SEED_MODES = 5
"""Most colours of grid cells tried as the cloth's."""
TOLERANCES = (1.0, 1.5, 2.2, 3.2)
"""Ladder of colour tolerances (multiples of the seed's spread) tried for each seed colour."""
TOLERANCE_DECAY = 0.9
"""Score factor per step up the tolerance ladder."""
FLOOD_STEPS = (1.0, 1.6, 2.5)
"""Ladder of the largest colour step between neighbouring pixels a flood fill crosses (multiples of
:data:`FLOOD_L_STEP` and :data:`FLOOD_C_STEP`)."""
FLOOD_L_STEP, FLOOD_C_STEP = 2.0, 1.5
"""Neighbour step in lightness and in each chroma axis (Lab units) at the first rung of :data:`FLOOD_STEPS`."""
GOOD_ENOUGH = 0.45
"""A candidate scoring this much ends the search over further seed colours."""
FLOOD_LIMIT = 3.0
"""A flood fill never leaves the pixels within this many tolerance steps of the seed colour."""
L_SPREAD, C_SPREAD = 9.0, 5.0
"""Least spread of the cloth colour in lightness and in chroma (Lab units): the tolerance at step 1."""
MIN_STRAIGHT = 0.4
"""Least share of a region's boundary (off the frame edge) on the sides of its enclosing quadrilateral."""
BALL_AREAS = 12.0
"""Smallest cloth region as a multiple of the largest ball box's area."""
MIN_AREA_FRACTION = 0.012
"""Smallest cloth region, as a fraction of the photo."""
BORDER_PX = 1.5
"""Boundary points this close to the frame edge [work px] are the frame's, not the cloth's."""


def lab_of(rgb: np.ndarray) -> np.ndarray:
    """CIE Lab of an RGB uint8 image, float32 (L 0-100, a and b about -128-127)."""
    return cv2.cvtColor(rgb.astype(np.float32) * (1 / 255), cv2.COLOR_RGB2Lab)


def _ring_pixels(lab: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """Lab pixels (n, 3) of a ring around each box (from 1.4 to 2.2 box radii): the cloth next to each ball."""
    h, w = lab.shape[:2]
    out = []
    for x0, y0, x1, y1 in boxes:
        cx, cy, r = (x0 + x1) / 2, (y0 + y1) / 2, max(x1 - x0, y1 - y0) / 2
        r = max(r, 1.0)
        lo_x, hi_x = int(max(cx - 2.2 * r, 0)), int(min(cx + 2.2 * r + 1, w))
        lo_y, hi_y = int(max(cy - 2.2 * r, 0)), int(min(cy + 2.2 * r + 1, h))
        if hi_x - lo_x < 2 or hi_y - lo_y < 2:
            continue
        yy, xx = np.mgrid[lo_y:hi_y, lo_x:hi_x]
        d = np.hypot(xx - cx, yy - cy) / r
        ring = (d >= 1.4) & (d <= 2.2)
        out.append(lab[lo_y:hi_y, lo_x:hi_x][ring])
    return np.concatenate(out) if out else np.zeros((0, 3), np.float32)


def _dominant_colour(pixels: np.ndarray) -> np.ndarray:
    """The most common colour of Lab pixels (n, 3): the median of those in the fullest coarse colour bin and its
    neighbours (the cloth around a ball by the rail is mixed with rail pixels; their plain median is neither)."""
    q = np.floor(pixels / np.array([8.0, 6.0, 6.0])).astype(int)
    bins, counts = np.unique(q, axis=0, return_counts=True)
    # each bin's count with its 26 neighbours'
    near = np.abs(bins[:, None, :] - bins[None, :, :]).max(axis=2) <= 1
    best = bins[int(np.argmax(near.astype(int) @ counts))]
    members = np.abs(q - best).max(axis=1) <= 1
    return np.median(pixels[members], axis=0)


def _seed_colours(lab: np.ndarray, ball_boxes: np.ndarray) -> list[np.ndarray]:
    """Candidate cloth colours (Lab), most likely first: the cloth around the balls, then the colours of the
    uniform cells of a :data:`SEED_GRID` grid over the photo, the commonest first (cells low in the photo and
    coloured count more: that is where tables and cloths are)."""
    seeds: list[np.ndarray] = []
    if len(ball_boxes):
        ring = _ring_pixels(lab, ball_boxes)
        if len(ring) >= 20:
            seeds.append(_dominant_colour(ring))
    n = SEED_GRID
    mean = cv2.resize(lab, (n, n), interpolation=cv2.INTER_AREA).reshape(-1, 3)
    square = cv2.resize(lab * lab, (n, n), interpolation=cv2.INTER_AREA).reshape(-1, 3)
    std = np.sqrt(np.clip(square - mean * mean, 0.0, None))
    uniform = (std[:, 0] < 8.0) & (np.hypot(std[:, 1], std[:, 2]) < 6.0)
    row = np.repeat(np.arange(n), n) / (n - 1)
    weight = (1.0 + row) * np.where(np.hypot(mean[:, 1], mean[:, 2]) > 15.0, 1.5, 1.0)
    cells, weight = mean[uniform], weight[uniform]
    # group similar cells; the heaviest groups first
    left = np.ones(len(cells), dtype=bool)
    groups = []
    while left.any():
        i = int(np.flatnonzero(left)[0])
        l_spread, c_spread = spreads(cells[i])
        d = (
            np.abs(cells[:, 0] - cells[i, 0]) / l_spread
            + np.hypot(cells[:, 1] - cells[i, 1], cells[:, 2] - cells[i, 2]) / c_spread
        )
        member = left & (d < 1.5)
        groups.append((float(weight[member].sum()), np.median(cells[member], axis=0)))
        left &= ~member
    groups.sort(key=lambda g: -g[0])
    seeds += [g[1] for g in groups][:SEED_MODES]
    unique: list[np.ndarray] = []
    for seed in seeds:
        l_spread, c_spread = spreads(seed)
        if all(
            abs(seed[0] - u[0]) / l_spread + math.hypot(seed[1] - u[1], seed[2] - u[2]) / c_spread > 0.7 for u in unique
        ):
            unique.append(seed.astype(np.float32))
    return unique


@dataclass(frozen=True, slots=True, eq=False)
class Candidate:
    """One cloth candidate.

    Attributes:
        score: how table-like the region is (:func:`score_region`, lowered up the tolerance ladders).
        region: the region with its holes filled, uint8 (H, W) on the shrunk photo.
        quad: the quadrilateral enclosing it (4, 2) [work px].
        colour: the seed colour it was grown from (Lab).
        tolerance: the threshold tolerance, or minus the flood-fill step, it was grown with.
    """

    score: float
    region: np.ndarray
    quad: np.ndarray
    colour: np.ndarray
    tolerance: float


def filled_region(component: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The component (uint8 mask) with its holes filled, and its largest external contour (n, 2)."""
    contours, _ = cv2.findContours(component, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    contour = max(contours, key=cv2.contourArea)
    filled = np.zeros_like(component)
    cv2.drawContours(filled, [contour], -1, 1, thickness=cv2.FILLED)
    return filled, contour.reshape(-1, 2).astype(float)


def on_border(points: np.ndarray, frame: tuple[int, int, int, int], margin: float = BORDER_PX) -> np.ndarray:
    """Which points (n, 2) lie on the edge of the photo's content ``frame`` (first and last column and row)."""
    x0, y0, x1, y1 = frame
    return (
        (points[:, 0] <= x0 + margin)
        | (points[:, 1] <= y0 + margin)
        | (points[:, 0] >= x1 - margin)
        | (points[:, 1] >= y1 - margin)
    )


def content_frame(gray: np.ndarray, dark: float = 24.0, flat: float = 4.0) -> tuple[int, int, int, int]:
    """The photo's content without the dark, flat bands of a letterbox: (first column, first row, last column, last
    row) of a grey image (H, W) [0-255]."""
    h, w = gray.shape
    rows_dark = (gray.mean(axis=1) < dark) & (gray.std(axis=1) < flat)
    cols_dark = (gray.mean(axis=0) < dark) & (gray.std(axis=0) < flat)

    def band(flags: np.ndarray) -> int:
        n = int(np.argmin(flags)) if not flags.all() else len(flags)
        return n if n <= len(flags) // 4 else 0

    return band(cols_dark), band(rows_dark), w - 1 - band(cols_dark[::-1]), h - 1 - band(rows_dark[::-1])


def score_region(
    filled: np.ndarray, contour: np.ndarray, balls: np.ndarray, frame: tuple[int, int, int, int]
) -> tuple[float, np.ndarray | None]:
    """How table-like a filled region is (0 = not at all, about 0.3-0.7 for a clear table) and its enclosing
    quadrilateral (work px).

    The product of: the fill of the quadrilateral (its part inside the photo) by the region; the share of the
    region's boundary (off the frame edge) that runs along the quadrilateral's sides (at least :data:`MIN_STRAIGHT`);
    the region's size; the sides its boundary follows (at least two); and the share of the balls ``balls`` (n, 2)
    [work px] inside the quadrilateral (at least half: the balls lie on the cloth).
    """
    h, w = filled.shape
    hull = cv2.convexHull(contour.astype(np.float32))
    hull = cv2.approxPolyDP(hull, max(1.0, 0.004 * cv2.arcLength(hull, True)), True).reshape(-1, 2).astype(float)
    quad = enclosing_quad(hull) if len(hull) >= 4 else None
    if quad is None or not np.all(np.isfinite(quad)) or np.abs(quad).max() > 20 * max(w, h):
        return 0.0, None
    area = float(filled.sum())
    qmask = quad_mask(quad, filled.shape)
    q_area = float(qmask.sum())
    if q_area <= 0:
        return 0.0, None
    fill = min(area / q_area, 1.0)
    real = contour[~on_border(contour, frame)]
    if len(real) < 20:
        return 0.0, None
    band = max(1.5, 0.025 * math.sqrt(q_area))
    a, b = quad, np.roll(quad, -1, axis=0)
    d = b - a
    length2 = np.sum(d * d, axis=1)
    if np.any(length2 <= 0):
        return 0.0, None
    normal = np.column_stack([-d[:, 1], d[:, 0]]) / np.sqrt(length2)[:, None]
    rel = real[:, None, :] - a[None]  # (n, 4, 2)
    dist = np.abs(np.sum(rel * normal[None], axis=2))
    t = np.sum(rel * d[None], axis=2) / length2[None]
    dist = np.where((t > -0.02) & (t < 1.02), dist, np.inf)
    near = dist < band
    seen = 0
    for k in range(4):
        bins = np.zeros(20, dtype=bool)
        bins[np.clip((t[near[:, k], k] * 20).astype(int), 0, 19)] = True
        seen += int(bins.sum() >= 7)
    dist = dist.min(axis=1)
    if seen < 2:
        return 0.0, quad
    straight = float(np.mean(dist < band))
    if straight < MIN_STRAIGHT:  # a ball, a lamp, a face: round, not four straight sides
        return 0.0, quad
    frac = area / (w * h)
    score = fill**2 * straight**2 * min(frac / 0.15, 1.0) ** 0.5 * (0.4 + 0.15 * seen)
    if len(balls):
        rows, cols = np.clip(balls[:, 1].astype(int), 0, h - 1), np.clip(balls[:, 0].astype(int), 0, w - 1)
        inside = float(np.mean(qmask[rows, cols]))
        if inside < 0.5:  # the balls lie on the cloth
            return 0.0, quad
        score *= 0.25 + 0.75 * inside
    return score, quad


def spreads(colour: np.ndarray) -> tuple[float, float]:
    """Tolerance step in lightness and in chroma for a cloth colour (Lab): brighter and more saturated cloths
    vary more under uneven light."""
    chroma = math.hypot(float(colour[1]), float(colour[2]))
    return L_SPREAD + 0.1 * float(colour[0]), C_SPREAD + 0.1 * chroma


def plain_distance(lab: np.ndarray, colour: np.ndarray) -> np.ndarray:
    """Distance (...) of Lab pixels (..., 3) from ``colour`` in its tolerance steps (:func:`spreads`), every channel
    alike: an edge shows where any channel changes."""
    l_spread, c_spread = spreads(colour)
    return np.sqrt(
        ((lab[..., 0] - colour[0]) / l_spread) ** 2
        + ((lab[..., 1] - colour[1]) / c_spread) ** 2
        + ((lab[..., 2] - colour[2]) / c_spread) ** 2
    )


def colour_distance2(lab: np.ndarray, colour: np.ndarray) -> np.ndarray:
    """Squared distance (H, W) of each pixel from ``colour`` in units of its tolerance step (:func:`_spreads`)."""
    chroma = math.hypot(float(colour[1]), float(colour[2]))
    l_spread, c_spread = spreads(colour)
    dl = (lab[:, :, 0] - colour[0]) * (1.0 / l_spread)
    da = (lab[:, :, 1] - colour[1]) * (1.0 / c_spread)
    db = (lab[:, :, 2] - colour[2]) * (1.0 / c_spread)
    if chroma <= 8:
        return dl * dl + da * da + db * db
    # darker cloth keeps its hue but loses chroma: let chroma shrink along the seed's own direction
    ua, ub = colour[1] / chroma, colour[2] / chroma
    along = da * ua + db * ub
    across = -da * ub + db * ua
    along = np.where(along < 0, along * 0.5, along)
    return dl * dl + along * along + across * across


def _flood_seeds(near: np.ndarray, dist2: np.ndarray, min_area: float) -> list[tuple[int, int]]:
    """Seed points (x, y) for flood fills: in each of the two largest regions of pixels ``near`` the seed colour,
    its pixel closest in colour and its pixel closest to its centroid."""
    _, labels, stats, centroids = cv2.connectedComponentsWithStats(near.astype(np.uint8), connectivity=4)
    seeds = []
    for lab_id in np.argsort(-stats[1:, cv2.CC_STAT_AREA])[:2] + 1:
        if stats[lab_id, cv2.CC_STAT_AREA] < min_area:
            continue
        ys, xs = np.nonzero(labels == lab_id)
        k = int(np.argmin(dist2[ys, xs]))
        seeds.append((int(xs[k]), int(ys[k])))
        k = int(np.argmin(np.hypot(xs - centroids[lab_id, 0], ys - centroids[lab_id, 1])))
        seeds.append((int(xs[k]), int(ys[k])))
    return seeds


def find_candidates(lab: np.ndarray, ball_boxes: np.ndarray, frame: tuple[int, int, int, int]) -> list[Candidate]:
    """Cloth candidates: for each seed colour, the regions within a ladder of colour tolerances of it, and the
    regions flood-filled from it step by step (which follow a lamp's gradient across the cloth)."""
    h, w = lab.shape[:2]
    x0, y0, x1, y1 = frame
    outside = np.ones((h, w), dtype=bool)
    outside[y0 : y1 + 1, x0 : x1 + 1] = False
    balls = (ball_boxes[:, :2] + ball_boxes[:, 2:]) / 2 if len(ball_boxes) else np.zeros((0, 2))
    out: list[Candidate] = []
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (3, 3))
    min_area = MIN_AREA_FRACTION * w * h
    if len(ball_boxes):  # a cloth holds many balls: a region a few balls big is a ball, a lamp or a face
        sides = ball_boxes[:, 2:] - ball_boxes[:, :2]
        min_area = max(min_area, BALL_AREAS * float(np.max(sides[:, 0] * sides[:, 1])))
    scaled = np.dstack([lab[:, :, 0] * 2.55, lab[:, :, 1] + 128.0, lab[:, :, 2] + 128.0])
    image8 = np.clip(scaled, 0, 255).astype(np.uint8)

    seen: set[tuple[int, ...]] = set()

    def consider(mask: np.ndarray, colour: np.ndarray, tol: float, factor: float) -> None:
        mask = cv2.morphologyEx(mask.astype(np.uint8), cv2.MORPH_OPEN, kernel)
        _, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=4)
        for lab_id in np.argsort(-stats[1:, cv2.CC_STAT_AREA])[:2] + 1:
            if stats[lab_id, cv2.CC_STAT_AREA] < min_area:
                continue
            key = (*(int(v) for v in stats[lab_id, :4]), int(stats[lab_id, cv2.CC_STAT_AREA]) * 500 // (w * h))
            if key in seen:  # the same region from another seed or tolerance
                continue
            seen.add(key)
            filled, contour = filled_region((labels == lab_id).astype(np.uint8))
            hull_area = cv2.contourArea(cv2.convexHull(contour.astype(np.float32)))
            if filled.sum() < 0.7 * hull_area:  # far from convex: not a cloth seen whole
                continue
            score, quad = score_region(filled, contour, balls, frame)
            if score > 0 and quad is not None:
                out.append(Candidate(score * factor, filled, quad, colour, tol))

    for colour in _seed_colours(lab, ball_boxes):
        dist2 = colour_distance2(lab, colour)
        dist2[outside] = np.inf
        for step, tol in enumerate(TOLERANCES):
            # the tightest tolerance that outlines the table wins: a looser one may take in a rail of a similar
            # colour, whose outer edge is as straight
            consider(dist2 <= tol * tol, colour, tol, TOLERANCE_DECAY**step)
        seeds = _flood_seeds(dist2 <= 1.0, dist2, 0.002 * w * h)
        if not seeds:
            continue
        barrier = np.pad((dist2 > FLOOD_LIMIT**2).astype(np.uint8), 1, constant_values=1)
        for step, diff in enumerate(FLOOD_STEPS):
            mask = barrier.copy()
            lo = (diff * 2.55 * FLOOD_L_STEP, diff * FLOOD_C_STEP, diff * FLOOD_C_STEP)
            for seed in seeds:
                if mask[seed[1] + 1, seed[0] + 1] == 0:
                    flags = 4 | cv2.FLOODFILL_MASK_ONLY | (2 << 8)
                    cv2.floodFill(image8, mask, seed, 0, lo, lo, flags)
            consider(mask[1:-1, 1:-1] == 2, colour, -diff, TOLERANCE_DECAY**step)
        if out and max(c.score for c in out) >= GOOD_ENOUGH:
            break  # the likeliest colours come first: a clear table ends the search
    return out

"""The playing cloth in an RGB photo: its region, its four cushion lines and where its pockets are.

A person finds a pool table at a glance from its cloth: one large, fairly uniform region of one colour bounded by
four straight cushions. This module does the same with classical image processing, no training:

1. **Seed colours.** The cloth colour is read where it must be: around the detected balls, and in the middle
   of the photo; the largest chroma modes of the whole photo are tried as well.
2. **Region.** For each seed colour the photo (shrunk to :data:`WORK_SIDE` pixels) is thresholded in CIE Lab at a
   ladder of tolerances (lightness looser than chroma: lamps light the cloth unevenly), opened to cut thin
   bridges, and each large component is filled (balls, chalk and shadows leave holes).
3. **Outline.** A component is scored by how well four lines explain it: the smallest quadrilateral enclosing
   its convex hull must be filled by the region, its sides must lie on the region's boundary rather than on the
   frame edge, and the balls should lie inside it. The best component's boundary points are split among the
   quadrilateral's sides and a robust line is fitted to each (pockets, players and cues cut the boundary, so
   only the straight runs count), then refined on the full-resolution photo along each line's normal.

The lines found are the outer edge of the cloth-coloured region: the back of the cushion tops, where the rail
begins (the cushions are covered with the same cloth). :mod:`pix2pockets.vision.table.outline_fit` models them as
such.

Example:
    >>> cloth = find_cloth(rgb, ball_boxes)  # doctest: +SKIP
    >>> cloth.corners_px  # the four corners of the cloth outline [px]  # doctest: +SKIP
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from pix2pockets.vision.table.errors import TableFitError

WORK_SIDE = 192
"""Longer side of the shrunk photo the region is found on [px]."""
SEED_GRID = 12
"""The photo is cut into this many cells across and down; the colours of uniform cells seed the cloth."""
SEED_MODES = 5
"""Most colours of grid cells tried as the cloth's."""
TOLERANCES = (1.0, 1.5, 2.2, 3.2)
"""Ladder of colour tolerances (multiples of the seed's spread) tried for each seed colour."""
L_SPREAD, C_SPREAD = 9.0, 5.0
"""Least spread of the cloth colour in lightness and in chroma (Lab units): the tolerance at step 1."""
MIN_AREA_FRACTION = 0.04
"""Smallest cloth region, as a fraction of the photo."""
MIN_SIDES = 3
"""Cushion lines that must be seen (not cut by the frame) for an outline."""
BORDER_PX = 1.5
"""Boundary points this close to the frame edge [work px] are the frame's, not the cloth's."""


@dataclass(frozen=True, slots=True, eq=False)
class ClothOutline:
    """The cloth found in a photo.

    Attributes:
        corners_px: the four corners of the cloth outline [px], (4, 2), in order around the quadrilateral
            (clockwise on screen, i.e. counter-clockwise in the table frame seen from above); a corner may lie
            outside the photo.
        lines: the four sides as lines ``a u + b v + c = 0`` with ``a^2 + b^2 = 1`` [px], (4, 3); side ``k`` runs
            from corner ``k`` to corner ``k + 1``.
        support: for each side, the fraction of its length inside the photo that the region's boundary follows
            (0: the side was not seen, it lies outside the photo or was inferred).
        inside_fraction: for each side, the fraction of its length that lies inside the photo.
        mask: the cloth region (H, W) bool, at the photo's resolution.
        colour_lab: the cloth's median colour in CIE Lab (L 0-100).
        confidence: how table-like the region is, 0-1 (fill of its quadrilateral, lines seen, balls inside).
        pocket_darkness: for each side, how much darker the photo is just outside its middle than along the rest of
            the side (lightness units); a side pocket makes a long cushion's middle dark.
    """

    corners_px: np.ndarray
    lines: np.ndarray
    support: np.ndarray
    inside_fraction: np.ndarray
    mask: np.ndarray
    colour_lab: np.ndarray
    confidence: float
    pocket_darkness: np.ndarray

    @property
    def seen_sides(self) -> int:
        """Number of sides the region's boundary follows over at least a third of their in-photo length."""
        return int(np.sum(self.support >= 1 / 3))


# ----------------------------------------------------------------------------- small geometry
def _line_through(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    d = q - p
    n = math.hypot(d[0], d[1]) or 1.0
    normal = np.array([-d[1], d[0]]) / n
    return np.array([normal[0], normal[1], -normal @ p])


def _intersect(l1: np.ndarray, l2: np.ndarray) -> np.ndarray:
    p = np.cross(l1, l2)
    if abs(p[2]) < 1e-12:
        return np.array([np.nan, np.nan])
    return p[:2] / p[2]


def _signed_area(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def enclosing_quad(hull: np.ndarray) -> np.ndarray | None:
    """The quadrilateral enclosing a convex polygon (n, 2) found by merging edges: the edge whose removal (its
    two neighbours extended to meet) adds the least area goes first. Returns (4, 2) in the hull's order, or
    None when the hull has fewer than four vertices or cannot be reduced."""
    pts = np.asarray(hull, dtype=float).reshape(-1, 2)
    while len(pts) > 4:
        a, b = np.roll(pts, 1, axis=0), pts
        c, d = np.roll(pts, -1, axis=0), np.roll(pts, -2, axis=0)
        # edges a-b and c-d extended past b and c meet at p, replacing edge b-c
        u, v, w = b - a, d - c, c - a
        den = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            s = (w[:, 0] * v[:, 1] - w[:, 1] * v[:, 0]) / den
            r = (w[:, 0] * u[:, 1] - w[:, 1] * u[:, 0]) / den
            p = a + s[:, None] * u
            area = 0.5 * np.abs((p[:, 0] - b[:, 0]) * (c[:, 1] - b[:, 1]) - (p[:, 1] - b[:, 1]) * (c[:, 0] - b[:, 0]))
        # lines meeting behind the edge (or parallel) cannot enclose it
        area = np.where((np.abs(den) > 1e-12) & (s >= 1.0) & (r <= 0.0), area, np.inf)
        i = int(np.argmin(area))
        if not np.isfinite(area[i]):
            return None
        pts[i] = p[i]
        pts = np.delete(pts, (i + 1) % len(pts), axis=0)
    return pts if len(pts) == 4 else None


def tls_fit(points: np.ndarray) -> np.ndarray:
    """Total-least-squares line ``(a, b, c)``, ``a^2 + b^2 = 1``, through points (n, 2)."""
    mean = points.mean(axis=0)
    d = points - mean
    cov = d.T @ d
    _, vecs = np.linalg.eigh(cov)
    normal = vecs[:, 0]
    return np.array([normal[0], normal[1], -normal @ mean])


# ----------------------------------------------------------------------------- colour
def _lab(rgb: np.ndarray) -> np.ndarray:
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


def _histogram_modes(values: np.ndarray, lo: float, hi: float, bins: int, count: int, min_share: float) -> list[float]:
    """Up to ``count`` modes of a 1-D histogram of ``values``, each holding at least ``min_share`` of them."""
    hist, edges = np.histogram(values, bins=bins, range=(lo, hi))
    hist = np.convolve(hist.astype(float), [0.25, 0.5, 0.25], mode="same")
    out = []
    for _ in range(count):
        i = int(np.argmax(hist))
        if hist[i] < min_share * len(values):
            break
        out.append(float(edges[i] + edges[i + 1]) / 2)
        hist[max(i - 2, 0) : i + 3] = 0
    return out


def _seed_colours(lab: np.ndarray, ball_boxes: np.ndarray) -> list[np.ndarray]:
    """Candidate cloth colours (Lab), most likely first: the cloth around the balls, then the colours of the
    uniform cells of a :data:`SEED_GRID` grid over the photo, most common first."""
    h, w = lab.shape[:2]
    seeds: list[np.ndarray] = []
    if len(ball_boxes) >= 2:
        ring = _ring_pixels(lab, ball_boxes)
        if len(ring) >= 20:
            seeds.append(np.median(ring, axis=0))
    n = SEED_GRID
    mean = cv2.resize(lab, (n, n), interpolation=cv2.INTER_AREA).reshape(-1, 3)
    square = cv2.resize(lab * lab, (n, n), interpolation=cv2.INTER_AREA).reshape(-1, 3)
    std = np.sqrt(np.clip(square - mean * mean, 0.0, None))
    uniform = (std[:, 0] < 8.0) & (np.hypot(std[:, 1], std[:, 2]) < 6.0)
    cells_arr = mean[uniform]
    # group similar cells; the biggest groups first
    left = np.ones(len(cells_arr), dtype=bool)
    groups = []
    while left.any():
        i = int(np.flatnonzero(left)[0])
        l_spread, c_spread = _spreads(cells_arr[i])
        d = np.abs(cells_arr[:, 0] - cells_arr[i, 0]) / l_spread + np.hypot(
            cells_arr[:, 1] - cells_arr[i, 1], cells_arr[:, 2] - cells_arr[i, 2]
        ) / c_spread
        member = left & (d < 1.5)
        groups.append((int(member.sum()), np.median(cells_arr[member], axis=0)))
        left &= ~member
    groups.sort(key=lambda g: -g[0])
    seeds += [g[1] for g in groups][:SEED_MODES]
    unique: list[np.ndarray] = []
    for seed in seeds:
        l_spread, c_spread = _spreads(seed)
        if all(
            abs(seed[0] - u[0]) / l_spread + math.hypot(seed[1] - u[1], seed[2] - u[2]) / c_spread > 0.7
            for u in unique
        ):
            unique.append(seed.astype(np.float32))
    return unique


# ----------------------------------------------------------------------------- candidate regions
@dataclass(slots=True)
class _Candidate:
    score: float
    region: np.ndarray  # uint8 work-resolution mask, holes filled
    quad: np.ndarray  # (4, 2) work px
    colour: np.ndarray
    tolerance: float


def _filled(component: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The component (uint8 mask) with its holes filled, and its largest external contour (n, 2)."""
    contours, _ = cv2.findContours(component, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    contour = max(contours, key=cv2.contourArea)
    filled = np.zeros_like(component)
    cv2.drawContours(filled, [contour], -1, 1, thickness=cv2.FILLED)
    return filled, contour.reshape(-1, 2).astype(float)


def _on_border(points: np.ndarray, size: tuple[int, int], margin: float = BORDER_PX) -> np.ndarray:
    w, h = size
    return (
        (points[:, 0] <= margin)
        | (points[:, 1] <= margin)
        | (points[:, 0] >= w - 1 - margin)
        | (points[:, 1] >= h - 1 - margin)
    )


def _score_component(
    filled: np.ndarray, contour: np.ndarray, balls: np.ndarray, size: tuple[int, int]
) -> tuple[float, np.ndarray | None]:
    """How table-like a filled region is (0 = not at all) and its enclosing quadrilateral (work px).

    The product of: the fill of the quadrilateral (its part inside the photo) by the region; the share of the
    region's boundary (off the frame edge) that runs along the quadrilateral's sides; the region's size; and the
    share of the balls inside the quadrilateral.
    """
    w, h = size
    hull = cv2.convexHull(contour.astype(np.float32))
    hull = cv2.approxPolyDP(hull, 1.0, True).reshape(-1, 2).astype(float)
    quad = enclosing_quad(hull) if len(hull) >= 4 else None
    if quad is None or not np.all(np.isfinite(quad)) or np.abs(quad).max() > 20 * max(w, h):
        return 0.0, None
    area = float(filled.sum())
    qmask = np.zeros_like(filled)
    cv2.fillConvexPoly(qmask, np.round(quad * 16).astype(np.int32), 1, shift=4)
    q_area = float(qmask.sum())
    if q_area <= 0:
        return 0.0, None
    fill = min(area / q_area, 1.0)
    real = contour[~_on_border(contour, size)]
    if len(real) < 20:
        return 0.0, None
    band = max(1.5, 0.025 * math.sqrt(q_area))
    dist = np.full(len(real), np.inf)
    seen = 0
    for k in range(4):
        a, b = quad[k], quad[(k + 1) % 4]
        length = float(np.linalg.norm(b - a))
        if length <= 0:
            continue
        line = _line_through(a, b)
        d = np.abs(real @ line[:2] + line[2])
        t = (real - a) @ (b - a) / length**2
        d = np.where((t > -0.02) & (t < 1.02), d, np.inf)
        dist = np.minimum(dist, d)
        near = t[d < band]
        seen += int(len(np.unique(np.clip((near * 20).astype(int), 0, 19))) >= 7)
    if seen < 2:
        return 0.0, quad
    straight = float(np.mean(dist < band))
    frac = area / (w * h)
    score = fill**2 * straight**2 * min(frac / 0.15, 1.0) ** 0.5 * (0.4 + 0.15 * seen)
    if len(balls) >= 2:
        inside = qmask[np.clip(balls[:, 1].astype(int), 0, h - 1), np.clip(balls[:, 0].astype(int), 0, w - 1)]
        score *= 0.25 + 0.75 * float(np.mean(inside))
    return score, quad


def _spreads(colour: np.ndarray) -> tuple[float, float]:
    """Tolerance step in lightness and in chroma for a cloth colour (Lab): brighter and more saturated cloths
    vary more under uneven light."""
    chroma = math.hypot(float(colour[1]), float(colour[2]))
    return L_SPREAD + 0.1 * float(colour[0]), C_SPREAD + 0.1 * chroma


def _candidates(lab: np.ndarray, ball_boxes: np.ndarray) -> list[_Candidate]:
    h, w = lab.shape[:2]
    balls = (ball_boxes[:, :2] + ball_boxes[:, 2:]) / 2 if len(ball_boxes) else np.zeros((0, 2))
    out: list[_Candidate] = []
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (3, 3))
    min_area = MIN_AREA_FRACTION * w * h
    for colour in _seed_colours(lab, ball_boxes):
        chroma = math.hypot(float(colour[1]), float(colour[2]))
        l_spread, c_spread = _spreads(colour)
        dl = (lab[:, :, 0] - colour[0]) * (1.0 / l_spread)
        da = (lab[:, :, 1] - colour[1]) * (1.0 / c_spread)
        db = (lab[:, :, 2] - colour[2]) * (1.0 / c_spread)
        # darker cloth keeps its hue but loses chroma: let chroma shrink along the seed's own direction
        if chroma > 8:
            ua, ub = colour[1] / chroma, colour[2] / chroma
            along = da * ua + db * ub
            across = -da * ub + db * ua
            along = np.where(along < 0, along * 0.5, along)
            dist2 = dl * dl + along * along + across * across
        else:
            dist2 = dl * dl + da * da + db * db
        for tol in TOLERANCES:
            mask = (dist2 <= tol * tol).astype(np.uint8)
            mask = cv2.morphologyEx(mask, cv2.MORPH_OPEN, kernel)
            n, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=4)
            order = np.argsort(-stats[1:, cv2.CC_STAT_AREA])[:2] + 1
            for lab_id in order:
                if stats[lab_id, cv2.CC_STAT_AREA] < min_area:
                    continue
                comp = (labels == lab_id).astype(np.uint8)
                filled, contour = _filled(comp)
                hull_area = cv2.contourArea(cv2.convexHull(contour.astype(np.float32)))
                if filled.sum() < 0.7 * hull_area:  # far from convex: not a cloth seen whole
                    continue
                score, quad = _score_component(filled, contour, balls, (w, h))
                if score > 0 and quad is not None:
                    out.append(_Candidate(score, filled, quad, colour, tol))
    return out


# ----------------------------------------------------------------------------- lines
def _robust_line(
    points: np.ndarray,
    tol: float,
    bound: np.ndarray | None = None,
    inner: np.ndarray | None = None,
    iterations: int = 3,
) -> tuple[np.ndarray, np.ndarray] | None:
    """A line through the longest straight run of ``points`` (n, 2): deterministic RANSAC over pairs of points
    spread along the set, then least squares on the inliers. Returns (line, inlier mask) or None.

    With ``bound`` (m, 2) and ``inner`` (2,), the line must bound the region: each point of ``bound`` beyond the
    line (on the side away from ``inner``) costs three inliers, so a line along a player's arm that crosses the
    cloth loses to the cushion's shorter runs.
    """
    n = len(points)
    if n < 6:
        return None
    k = min(n, 24)
    picks = points[np.linspace(0, n - 1, k).astype(int)]
    i, j = np.triu_indices(k, 1)
    d = picks[j] - picks[i]
    length = np.hypot(d[:, 0], d[:, 1])
    keep = length >= 4 * tol
    if not keep.any():
        return None
    i, d, length = i[keep], d[keep], length[keep]
    normals = np.column_stack([-d[:, 1], d[:, 0]]) / length[:, None]
    offsets = -np.sum(normals * picks[i], axis=1)
    score = np.sum(np.abs(points @ normals.T + offsets) < tol, axis=0).astype(float)
    if bound is not None and inner is not None and len(bound):
        side = np.sign(inner @ normals.T + offsets)  # the inner side's sign for each line
        beyond = (bound @ normals.T + offsets) * -side > 2 * tol
        score -= 3.0 * beyond.sum(axis=0)
    best = int(np.argmax(score))
    line = np.array([normals[best, 0], normals[best, 1], offsets[best]])
    inliers = np.abs(points @ line[:2] + line[2]) < tol
    for _ in range(iterations):
        if inliers.sum() < 4:
            return None
        line = tls_fit(points[inliers])
        inliers = np.abs(points @ line[:2] + line[2]) < tol
    return line, inliers


def _side_lines(contour: np.ndarray, quad: np.ndarray, size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Lines (4, 3) fitted to the boundary points near each quadrilateral side, and each side's support."""
    real = contour[~_on_border(contour, size)]
    scale = math.sqrt(abs(_signed_area(quad)))
    lines = np.zeros((4, 3))
    support = np.zeros(4)
    band = 0.05 * scale
    tol = max(1.0, 0.006 * scale)
    for k in range(4):
        a, b = quad[k], quad[(k + 1) % 4]
        line = _line_through(a, b)
        lines[k] = line
        length = float(np.linalg.norm(b - a))
        if length <= 0 or not len(real):
            continue
        d = np.abs(real @ line[:2] + line[2])
        t = (real - a) @ (b - a) / length**2
        near = real[(d < band) & (t > 0.03) & (t < 0.97)]
        fitted = _robust_line(near, tol, contour, quad.mean(axis=0))
        if fitted is None:
            continue
        new, inliers = fitted
        if abs(new[:2] @ line[:2]) < math.cos(math.radians(12)):
            continue
        lines[k] = new if new[:2] @ line[:2] > 0 else -new
        tin = (near[inliers] - a) @ (b - a) / length**2
        bins = np.unique(np.clip((tin * 40).astype(int), 0, 39))
        support[k] = len(bins) / 40
    return lines, support


def _quad_of_lines(lines: np.ndarray) -> np.ndarray:
    return np.array([_intersect(lines[k - 1], lines[k]) for k in range(4)])


def _inside_fraction(a: np.ndarray, b: np.ndarray, size: tuple[int, int]) -> float:
    t = np.linspace(0, 1, 41)[:, None]
    p = a + t * (b - a)
    w, h = size
    return float(np.mean((p[:, 0] >= 0) & (p[:, 0] <= w) & (p[:, 1] >= 0) & (p[:, 1] <= h)))


# ----------------------------------------------------------------------------- full-resolution refinement
def _refine_lines(
    rgb: np.ndarray, lines: np.ndarray, quad: np.ndarray, support: np.ndarray, colour: np.ndarray, reach: float
) -> np.ndarray:
    """Lines moved onto the cloth's edge in the full-resolution photo: along each seen side, the point where the
    colour leaves the cloth's is searched along the side's normal within ``reach`` [px]; a line is refitted to
    those points."""
    h, w = rgb.shape[:2]
    out = lines.copy()
    centre = quad.mean(axis=0)
    offsets = np.linspace(-reach, reach, int(2 * reach) + 1, dtype=np.float32)
    for k in range(4):
        if support[k] < 0.2:
            continue
        a, b = quad[k], quad[(k + 1) % 4]
        line = lines[k]
        normal = line[:2] * (1.0 if (centre @ line[:2] + line[2]) < 0 else -1.0)  # pointing out of the cloth
        t = np.linspace(0.08, 0.92, 48, dtype=np.float32)
        base = a[None] + t[:, None] * (b - a)[None]
        base = base - (base @ line[:2] + line[2])[:, None] * line[:2][None]  # onto the line
        pts = base[:, None, :] + offsets[None, :, None] * normal[None, None, :]
        ok = np.all((pts[:, :, 0] >= 0) & (pts[:, :, 0] <= w - 1) & (pts[:, :, 1] >= 0) & (pts[:, :, 1] <= h - 1), 1)
        if ok.sum() < 8:
            continue
        pts = pts[ok].astype(np.float32)
        samples = cv2.remap(rgb, pts[:, :, 0], pts[:, :, 1], cv2.INTER_LINEAR)
        lab = _lab(samples)
        l_spread, c_spread = _spreads(colour)
        dist = np.sqrt(
            ((lab[:, :, 0] - colour[0]) / l_spread) ** 2
            + ((lab[:, :, 1] - colour[1]) / c_spread) ** 2
            + ((lab[:, :, 2] - colour[2]) / c_spread) ** 2
        )
        # the edge: the steepest rise of the colour distance along the outward normal
        grad = np.diff(cv2.GaussianBlur(dist, (1, 5), 0), axis=1)
        j = np.argmax(grad, axis=1)
        strong = grad[np.arange(len(j)), j] > 0.25
        if strong.sum() < 8:
            continue
        edge = pts[np.arange(len(j)), j] + 0.5 * (pts[np.arange(len(j)), j + 1] - pts[np.arange(len(j)), j])
        fitted = _robust_line(edge[strong].astype(float), 1.5)
        if fitted is None:
            continue
        new, inliers = fitted
        if inliers.sum() < 8 or abs(new[:2] @ line[:2]) < math.cos(math.radians(3)):
            continue
        out[k] = new if new[:2] @ line[:2] > 0 else -new
    return out


def _pocket_darkness(lab: np.ndarray, quad: np.ndarray, scale: float) -> np.ndarray:
    """For each side (work px), lightness just outside the side's middle minus the median along the side,
    negated: positive where the middle is darker (a side pocket)."""
    h, w = lab.shape[:2]
    centre = quad.mean(axis=0)
    out = np.zeros(4)
    for k in range(4):
        a, b = quad[k], quad[(k + 1) % 4]
        line = _line_through(a, b)
        normal = line[:2] * (1.0 if (centre @ line[:2] + line[2]) < 0 else -1.0)
        t = np.linspace(0.15, 0.85, 29)
        pts = a[None] + t[:, None] * (b - a)[None] + 0.02 * scale * normal[None]
        ok = (pts[:, 0] >= 0) & (pts[:, 0] <= w - 1) & (pts[:, 1] >= 0) & (pts[:, 1] <= h - 1)
        if ok.sum() < 20:
            continue
        light = lab[pts[ok, 1].astype(int), pts[ok, 0].astype(int), 0]
        mid = np.abs(t[ok] - 0.5) < 0.06
        if not mid.any():
            continue
        out[k] = float(np.median(light) - light[mid].min())
    return out


# ----------------------------------------------------------------------------- entry point
def find_cloth(rgb: np.ndarray, ball_boxes: np.ndarray | None = None) -> ClothOutline:
    """Find the cloth and its four cushion lines in an RGB photo.

    Args:
        rgb: the photo, RGB uint8 (H, W, 3).
        ball_boxes: detected ball boxes ``x1, y1, x2, y2`` [px] (n, 4); the cloth around them seeds its colour.

    Returns:
        The cloth outline (corners, lines, mask, confidence), in the photo's pixels.

    Raises:
        TableFitError: no region of the photo looks like a table's cloth.
    """
    rgb = np.asarray(rgb)
    if rgb.ndim != 3 or rgb.shape[2] < 3 or rgb.dtype != np.uint8:
        raise ValueError(f"expected an RGB uint8 image (H, W, 3), got {rgb.dtype} {rgb.shape}")
    rgb = rgb[:, :, :3]
    h, w = rgb.shape[:2]
    s = WORK_SIDE / max(w, h)
    ws, hs = max(round(w * s), 8), max(round(h * s), 8)
    sx, sy = ws / w, hs / h
    small = cv2.resize(rgb, (ws, hs), interpolation=cv2.INTER_AREA)
    small = cv2.GaussianBlur(small, (5, 5), 1.0)
    lab = _lab(small)
    boxes = np.zeros((0, 4)) if ball_boxes is None else np.asarray(ball_boxes, dtype=float).reshape(-1, 4)
    boxes = boxes * np.array([sx, sy, sx, sy])
    candidates = _candidates(lab, boxes)
    if not candidates:
        raise TableFitError(
            "no table found: no cloth region with at least three straight cushions (show the whole table, "
            "its cloth and at least three cushions)"
        )
    best = max(candidates, key=lambda c: c.score)
    filled, contour = _filled(best.region)
    lines, support = _side_lines(contour, best.quad, (ws, hs))
    quad = _quad_of_lines(lines)
    if not np.all(np.isfinite(quad)):
        quad = best.quad
        lines = np.array([_line_through(quad[k], quad[(k + 1) % 4]) for k in range(4)])
    # to full resolution: u = u_work / sx
    S = np.diag([sx, sy, 1.0])
    full_lines = lines @ S
    full_lines /= np.linalg.norm(full_lines[:, :2], axis=1, keepdims=True)
    full_quad = quad / np.array([sx, sy])
    full_lines = _refine_lines(rgb, full_lines, full_quad, support, best.colour, reach=2.5 / min(sx, sy))
    full_quad = _quad_of_lines(full_lines)
    if _signed_area(full_quad) > 0:  # clockwise on screen (v down): reverse
        full_quad = full_quad[::-1].copy()
        full_lines = full_lines[[2, 1, 0, 3]]
        support = support[[2, 1, 0, 3]]
    # order: side k from corner k to k + 1
    full_lines = np.array([_line_through(full_quad[k], full_quad[(k + 1) % 4]) for k in range(4)])
    inside = np.array([_inside_fraction(full_quad[k], full_quad[(k + 1) % 4], (w, h)) for k in range(4)])
    darkness = _pocket_darkness(lab, full_quad * np.array([sx, sy]), math.sqrt(abs(_signed_area(quad))))
    mask = cv2.resize(filled, (w, h), interpolation=cv2.INTER_NEAREST).astype(bool)
    return ClothOutline(
        full_quad, full_lines, support, inside, mask, best.colour.astype(float), float(min(best.score, 1.0)), darkness
    )

"""The playing surface's outline from the table model: four cushion lines, their corners and the side pockets.

The table model (:mod:`pix2pockets.vision.table.keypoints`) marks the playing surface cell by cell. Its largest
region is the table; the region's boundary runs along the cushion noses except where the frame cuts it. The
smallest quadrilateral enclosing the region's hull splits the boundary among four sides, and a robust line through
each side's boundary points is a cushion line. A side the boundary does not follow (the frame edge cuts it) is
kept from the quadrilateral and marked unseen. Where the frame cuts the region so that its edges take sides of that
quadrilateral (fewer than three cushions left), the cushions are read from the region's edge off the frame instead,
one straight run after another, and the frame closes a fourth side only where none is in view. Those runs win too
where they find more cushions than the quadrilateral and agree with the surface at least as well (a short far
cushion the quadrilateral merged into the long ones, a near corner being out of the photo); the quadrilateral's
outline then stays as a second hypothesis, for runs that make no rectangle a camera sees. Side-pocket peaks
near the middle of a side mark it as a long rail.

The model's corner peaks give a second hypothesis: four of them round a convex quadrilateral. Where the surface
region leaks past the table (a wall or a floor of the cloth's colour joins it), the region's quadrilateral takes in
far more than the table; the corner peaks do not. Of the two, the outline that agrees better with the model's
surface chances (:func:`surface_agreement`: the chance less one half, summed over the cells inside), by a clear
margin, counting the balls it leaves out against it, wins.

Example:
    >>> outline = surface_outline(model.read(rgb))  # doctest: +SKIP
    >>> outline.corners_px, outline.seen, outline.side_pocket  # doctest: +SKIP
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field, replace

import cv2
import numpy as np

from pix2pockets.vision.table.errors import TableFitError
from pix2pockets.vision.table.keypoints import TableCues, cell_of_pixel, pixel_of_cell
from pix2pockets.vision.table.quad_geometry import (
    corner_gap,
    enclosing_quad,
    quad_length,
    quad_mask,
    robust_line,
    tls_fit,
)
from pix2pockets.vision.table.two_cushions import CushionMark

SURFACE_THRESHOLD = 0.5
UPSAMPLE = 4
"""The surface chances are interpolated this many times finer before their 0.5 level is traced."""
MIN_AREA_FRACTION = 0.02
"""Smallest surface region, as a fraction of the photo."""
FRAME_CELLS = 1.5
"""Boundary cells this close to the photo's edge belong to the frame, not to a cushion."""
LINE_TOL_CELLS = 1.5
"""Boundary points within this many cells of a side's line support it."""
SEEN_SUPPORT = 0.3
"""Share of a side's in-photo length the boundary must follow for the side to count as seen."""
CORNER_REACH = 0.12
"""A corner peak replaces the corner of the region's lines when it lies within this share of the shortest side."""
CORNER_MIN_SCORE = 0.4
MIN_CUT_LINE = 0.06
"""A cushion line of a region the frame cuts must run along its edge for this share of the image diagonal."""
MAX_CUT_LINES = 4
MAX_CUT_REGION_SHARE = 0.8
"""A region the frame cuts that fills more of the photo than this shows too little of its edge to read cushions from
(a blank wall or a close-up the model takes for cloth)."""
PEAK_QUAD_MIN_SCORE = 0.25
"""Corner peaks at least this sure may make a four-peak outline."""
PEAK_QUAD_GAIN = 0.15
"""A four-peak outline replaces the region's when it agrees with the surface by this share more (a peak a few
pixels off a corner the region's edge reads well must not win by a hair) ..."""
PEAK_QUAD_BALL_COST = 0.02
"""... counting against it this share of the region's agreement for each ball inside the region's outline that it
leaves out (a ball is no proof: ball returns and players' hands hold balls too)."""
ALTERNATIVE_GAP = 0.03
"""A four-peak outline that lost is kept as a second hypothesis when a corner lies this share of the table's length
away from the region's outline (closer, it would give the same fit)."""
MARK_REACH = 0.02
"""A corner or side-pocket peak marks a cushion line when it lies within this share of the image diagonal of it."""
MARK_MIN_SCORE = 0.5
"""Least score of a peak that marks a cushion line for a fit from two cushions."""
SIDE_POCKET_REACH = 0.2
"""A side-pocket peak counts for a side when it lies within this share of the side's length of its middle and
within this share of the side's length of its line."""


@dataclass(frozen=True, slots=True, eq=False)
class SurfaceOutline:
    """The playing surface seen in a photo.

    Attributes:
        corners_px: (4, 2) its corners [px], in order around it; side ``k`` runs from corner ``k`` to ``k + 1``.
        seen: (4,) whether the photo shows each side (the frame edge does not cut it away).
        from_peak: (4,) whether each corner is the model's corner peak (read to about a pixel) rather than the
            meeting point of two lines through the region's edge (a few pixels).
        side_pocket: (4,) the best side-pocket peak score near each side's middle (0: none).
        mask: (H, W) bool, the surface region at the photo's resolution.
        confidence: mean surface chance inside the region, times the share of the quadrilateral it fills.
        alternative: a second hypothesis for a fit the outline cannot give: the four corner peaks' own outline
            where it lost to the region's (e.g. a region that leaks onto a player's shirt), else the enclosing
            quadrilateral's where the cushions read off the frame replaced it; None without one.
        cushion_lines: (k, 3) the straight runs of the region's edge off the frame, longest first (lines
            ``a u + b v + c = 0`` [px], normals out of the region; empty when the frame does not cut the region).
        cues: the table model's reading the outline came from (its corner and side-pocket peaks); None where the
            outline was scaled from a copy of the photo stretched one way more than the other.
    """

    corners_px: np.ndarray
    seen: np.ndarray
    from_peak: np.ndarray
    side_pocket: np.ndarray
    mask: np.ndarray
    confidence: float
    alternative: SurfaceOutline | None = None
    cushion_lines: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    cues: TableCues | None = None

    def scaled(self, sx: float, sy: float, image_size: tuple[int, int]) -> SurfaceOutline:
        """The same outline in the photo resized by ``sx`` across and ``sy`` down to ``image_size`` [px]; its ``cues``
        are dropped where the photo is stretched more one way than the other (the model read it at one scale)."""
        lines = self.cushion_lines.reshape(-1, 3) * np.array([1 / sx, 1 / sy, 1.0])  # the old u is the new one / sx
        norms = np.linalg.norm(lines[:, :2], axis=1, keepdims=True)
        mask = cv2.resize(
            self.mask.astype(np.uint8), (int(image_size[0]), int(image_size[1])), interpolation=cv2.INTER_NEAREST
        )
        return replace(
            self,
            corners_px=self.corners_px * np.array([sx, sy]),
            mask=mask.astype(bool),
            alternative=None if self.alternative is None else self.alternative.scaled(sx, sy, image_size),
            cushion_lines=lines / np.where(norms > 0, norms, 1.0),
            cues=None if self.cues is None or not _alike(sx, sy) else self.cues.scaled(sx, sy, image_size),
        )


def _alike(sx: float, sy: float) -> bool:
    """Whether two scales differ by no more than rounding a photo's size does (1 %)."""
    return abs(sx - sy) <= 0.01 * max(abs(sx), abs(sy))


def _table_region(surface: np.ndarray, threshold: float, marks: np.ndarray, min_cells: float) -> np.ndarray:
    """The surface region that is the table: of the regions of at least ``min_cells`` cells, the one holding the most
    ``marks`` (ball centres and corner peaks, in cells), then the largest; holes filled."""
    on = (surface >= threshold).astype(np.uint8)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(on, connectivity=8)
    if n <= 1:
        return np.zeros_like(on)
    h, w = on.shape
    ij = np.round(marks).astype(int).reshape(-1, 2)
    ij = ij[(ij[:, 0] >= 0) & (ij[:, 0] < w) & (ij[:, 1] >= 0) & (ij[:, 1] < h)]
    held = np.bincount(labels[ij[:, 1], ij[:, 0]], minlength=n) if len(ij) else np.zeros(n, dtype=int)
    areas = stats[:, cv2.CC_STAT_AREA]
    rank = [(held[k], areas[k]) if areas[k] >= min_cells else (-1, areas[k]) for k in range(1, n)]
    k = 1 + max(range(n - 1), key=lambda i: rank[i])
    region = (labels == k).astype(np.uint8)
    contours, _ = cv2.findContours(region, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    cv2.drawContours(region, contours, -1, 1, thickness=cv2.FILLED)  # balls and players leave no holes
    return region


def _side_lines(points: np.ndarray, quad: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Lines (4, 3) through the boundary points nearest each side of ``quad``, and each side's support (share of
    its length covered by them); a side with too few points keeps the quadrilateral's line."""
    lines, support = np.zeros((4, 3)), np.zeros(4)
    for k in range(4):
        a, b = quad[k], quad[(k + 1) % 4]
        d = b - a
        length = float(np.hypot(*d))
        normal = np.array([-d[1], d[0]]) / max(length, 1e-9)
        line = np.array([normal[0], normal[1], -normal @ a])
        for _ in range(3):  # refit on the points near the current line
            t = (points - a) @ d / max(length**2, 1e-9)
            near = (np.abs(points @ line[:2] + line[2]) <= tol) & (t > -0.05) & (t < 1.05)
            if near.sum() < 6:
                break
            line = tls_fit(points[near])
        t = (points - a) @ d / max(length**2, 1e-9)
        near = (np.abs(points @ line[:2] + line[2]) <= tol) & (t > 0) & (t < 1)
        if near.sum() >= 6:
            covered = np.unique(np.floor(t[near] * 50)).size / 50
            support[k] = covered
        lines[k] = line if near.sum() >= 6 else np.array([normal[0], normal[1], -normal @ a])
    return lines, support


def _cushion_runs(
    points: np.ndarray, on_frame: np.ndarray, tol: float, image_size: tuple[int, int]
) -> tuple[np.ndarray, np.ndarray]:
    """The cushion lines (k, 3) of a region the frame cuts, in order round the region, normals out of it, and the
    angles (k,) of their runs' middles round the region's centre: taken one after another from the edge points off
    the frame (``points[~on_frame]``, the longest straight run first, each line bounding the region), while they are
    at least :data:`MIN_CUT_LINE` of the image diagonal long."""
    diag = float(np.hypot(*image_size))
    centre = points.mean(axis=0)
    left = points[~on_frame]
    found: list[tuple[np.ndarray, float]] = []
    while len(found) < MAX_CUT_LINES and len(left) >= 6:
        fitted = robust_line(left, tol, bound=points, inner=centre)
        if fitted is None:
            break
        line, inliers = fitted
        along = left[inliers] @ np.array([line[1], -line[0]])
        if float(along.max() - along.min()) < MIN_CUT_LINE * diag:
            break
        found.append((line, float(np.arctan2(*(left[inliers].mean(axis=0) - centre)[::-1]))))
        left = left[~inliers]
    found.sort(key=lambda item: item[1])
    out = np.array([line for line, _ in found]).reshape(-1, 3)
    for k in range(len(out)):  # normals out of the region
        if centre @ out[k, :2] + out[k, 2] > 0:
            out[k] = -out[k]
    return out, np.array([angle for _, angle in found])


def _cut_region_sides(
    runs: tuple[np.ndarray, np.ndarray], points: np.ndarray, on_frame: np.ndarray, image_size: tuple[int, int]
) -> tuple[np.ndarray, np.ndarray] | None:
    """The sides of a region the frame cuts, read from its edge alone: lines (4, 3) in order round the region and
    which of them are cushions (the others run along the frame).

    The cushion lines are the region's runs and their middles' angles (:func:`_cushion_runs`). Sorted by those
    angles round the region's centre, three lines leave one gap, which the frame closes: the line through the frame
    points there. Returns None without three cushion lines or when they do not make a convex quadrilateral.
    """
    diag = float(np.hypot(*image_size))
    centre = points.mean(axis=0)
    runs_lines, angles = runs
    if len(runs_lines) < 3:
        return None
    lines = list(runs_lines)
    seen = [True] * len(lines)
    if len(lines) == 3:
        gaps = np.diff(np.append(angles, angles[0] + 2 * np.pi))
        k = int(np.argmax(gaps))  # the frame closes the region between line k and the next one
        frame = points[on_frame]
        frame_angles = np.arctan2(frame[:, 1] - centre[1], frame[:, 0] - centre[0])
        within = np.mod(frame_angles - angles[k], 2 * np.pi) < gaps[k]
        if within.sum() < 2:
            return None
        lines.insert(k + 1, tls_fit(frame[within]))
        seen.insert(k + 1, False)
    out = np.array(lines)
    for k in range(4):  # normals out of the region
        if centre @ out[k, :2] + out[k, 2] > 0:
            out[k] = -out[k]
    corners = _corners_of(out)
    if not np.all(np.isfinite(corners)) or np.abs(corners).max() > 5 * diag:
        return None
    hull = cv2.convexHull(corners.astype(np.float32), returnPoints=False)
    if len(hull) < 4 or cv2.contourArea(corners.astype(np.float32)) <= 0:
        return None
    return out, np.array(seen)


def surface_agreement(cues: TableCues, quad_px: np.ndarray) -> float:
    """How well an outline ``quad_px`` (4, 2) [px] matches the model's surface: the sum over the output cells inside
    it of the surface chance less one half (cells of cloth add, cells off it take away)."""
    cells = cell_of_pixel(np.asarray(quad_px, dtype=float) * cues.letterbox.scale)
    if not np.all(np.abs(cells) < 1e5):
        return -np.inf
    inside = np.zeros(cues.surface.shape, dtype=np.uint8)
    cv2.fillPoly(inside, [np.round(cells * 8).astype(np.int32)], 1, shift=3)
    return float((cues.surface[inside > 0] - 0.5).sum())


def _inside(quad_px: np.ndarray, points_px: np.ndarray) -> np.ndarray:
    """Which points (n, 2) [px] lie inside or on the quadrilateral ``quad_px`` (4, 2) [px]."""
    contour = np.asarray(quad_px, dtype=np.float32).reshape(-1, 1, 2)
    return np.array([cv2.pointPolygonTest(contour, (float(x), float(y)), False) >= 0 for x, y in points_px], dtype=bool)


def peak_quad(cues: TableCues, ball_centres_px: np.ndarray, ball_cost: float = 0.0) -> tuple[np.ndarray, float] | None:
    """The four corner peaks (of those at least :data:`PEAK_QUAD_MIN_SCORE`) round the convex quadrilateral that
    scores best: its agreement with the surface (:func:`surface_agreement`) less ``ball_cost`` for each of the
    balls ``ball_centres_px`` (n, 2) [px] it leaves out. Its corners (4, 2) [px] in order round it and its score;
    None when no four peaks make one."""
    peaks_px = cues.corners_px[cues.corner_scores >= PEAK_QUAD_MIN_SCORE]
    best: tuple[np.ndarray, float] | None = None
    for idx in itertools.combinations(range(len(peaks_px)), 4):
        quad = peaks_px[list(idx)]
        centre = quad.mean(axis=0)
        quad = quad[np.argsort(np.arctan2(quad[:, 1] - centre[1], quad[:, 0] - centre[0]))]
        if not cv2.isContourConvex(quad.astype(np.float32).reshape(-1, 1, 2)):
            continue
        left_out = int((~_inside(quad, ball_centres_px)).sum())
        score = surface_agreement(cues, quad) - ball_cost * left_out
        if best is None or score > best[1]:
            best = (quad, score)
    return best


def _corners_of(lines: np.ndarray) -> np.ndarray:
    out = np.full((4, 2), np.nan)
    for k in range(4):
        p = np.cross(lines[k - 1], lines[k])
        if abs(p[2]) > 1e-12:
            out[k] = p[:2] / p[2]
    return out


def _snap_to_peaks(corners: np.ndarray, cues: TableCues) -> tuple[np.ndarray, np.ndarray]:
    """Corners moved to the model's corner peaks where one is near (the peaks are read to about a pixel, the region's
    edge to a few); and which corners moved."""
    sides = np.linalg.norm(np.roll(corners, -1, axis=0) - corners, axis=1)
    reach = CORNER_REACH * float(np.min(sides))
    out, moved = corners.copy(), np.zeros(4, dtype=bool)
    used: set[int] = set()
    for k in range(4):
        if not len(cues.corners_px):
            break
        d = np.linalg.norm(cues.corners_px - corners[k], axis=1)
        j = int(np.argmin(d))
        if d[j] <= reach and cues.corner_scores[j] >= CORNER_MIN_SCORE and j not in used:
            out[k], moved[k] = cues.corners_px[j], True
            used.add(j)
    return out, moved


def surface_outline(
    cues: TableCues, ball_centres_px: np.ndarray | None = None, threshold: float = SURFACE_THRESHOLD
) -> SurfaceOutline:
    """The playing surface's four sides from the table model's cues; ``ball_centres_px`` (n, 2) [px] tell the
    table's region from other surface-like regions (a wall, a bar top).

    Raises:
        TableFitError: no surface region large enough, or none a quadrilateral encloses.
    """
    box = cues.letterbox
    w, h = cues.image_size
    cell_area = (4.0 / box.scale) ** 2
    balls = np.zeros((0, 2)) if ball_centres_px is None else np.asarray(ball_centres_px, dtype=float).reshape(-1, 2)
    marks = cell_of_pixel(np.concatenate([balls, cues.corners_px]) * box.scale)
    region = _table_region(cues.surface, threshold, marks, MIN_AREA_FRACTION * w * h / cell_area)
    if region.sum() * cell_area < MIN_AREA_FRACTION * w * h:
        raise TableFitError(
            "no table found: no playing surface in the photo (show the table's cloth and at least three cushions)"
        )
    # the region's edge at sub-cell precision: the 0.5 level of the chances, interpolated between cell centres
    fine = cv2.resize(
        cues.surface.astype(np.float32) * region, None, fx=UPSAMPLE, fy=UPSAMPLE, interpolation=cv2.INTER_LINEAR
    )
    contours, _ = cv2.findContours((fine >= threshold).astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    cells = (max(contours, key=len).reshape(-1, 2).astype(float) + 0.5) / UPSAMPLE - 0.5
    # the photo's edge in cells: boundary there is the frame's
    w_cells, h_cells = (w * box.scale - 1.5) / 4, (h * box.scale - 1.5) / 4
    on_frame = (
        (cells[:, 0] <= FRAME_CELLS)
        | (cells[:, 1] <= FRAME_CELLS)
        | (cells[:, 0] >= w_cells - FRAME_CELLS)
        | (cells[:, 1] >= h_cells - FRAME_CELLS)
    )
    points = box.to_image(pixel_of_cell(cells))
    hull = cv2.convexHull(points.astype(np.float32)).reshape(-1, 2).astype(float)
    quad = enclosing_quad(hull)
    if quad is None:
        raise TableFitError("no table found: the playing surface has no four sides")
    tol = LINE_TOL_CELLS * 4.0 / box.scale
    lines, support = _side_lines(points[~on_frame], quad, tol)
    corners = _corners_of(lines)
    if not np.all(np.isfinite(corners)):
        corners = quad
    seen = support >= SEEN_SUPPORT
    replaced = None  # the quadrilateral's own outline, where the cushions read off the frame take its place
    share = region.sum() * cell_area / (w * h)
    runs = _cushion_runs(points, on_frame, tol, (w, h)) if on_frame.any() else (np.zeros((0, 3)), np.zeros(0))
    if on_frame.any() and share <= MAX_CUT_REGION_SHARE:  # frame edges may have taken sides: read cushions
        cut = _cut_region_sides(runs, points, on_frame, (w, h))
        if cut is not None and cut[1].sum() > seen.sum():
            cut_corners = _corners_of(cut[0])
            # with three cushions or more, a short one merged into its neighbours must show: more cushions, and an
            # outline that agrees with the surface at least as well
            if seen.sum() < 3 or surface_agreement(cues, cut_corners) >= surface_agreement(cues, corners):
                replaced = (corners, seen) if seen.sum() >= 3 else None
                corners, seen = cut_corners, cut[1]
    corners, from_peak = _snap_to_peaks(corners, cues)
    alternative = None  # the four peaks' corners, where they lose but would give another fit
    all_peaks = np.ones(4, dtype=bool)
    if np.all(np.isfinite(corners)):  # the corner peaks' own outline, where it fits the surface better
        region_agreement = surface_agreement(cues, corners)
        held = balls[_inside(corners, balls)]
        peaks_only = peak_quad(cues, held, PEAK_QUAD_BALL_COST * abs(region_agreement))
        if peaks_only is not None:
            if peaks_only[1] > region_agreement + PEAK_QUAD_GAIN * abs(region_agreement):
                corners, seen, from_peak, replaced = peaks_only[0], all_peaks, all_peaks, None
            elif corner_gap(peaks_only[0], corners) > ALTERNATIVE_GAP * quad_length(corners):
                alternative = peaks_only[0]
    mask = cv2.resize(region, (cues.surface.shape[1] * 4, cues.surface.shape[0] * 4), interpolation=cv2.INTER_NEAREST)
    M = np.array([[1 / box.scale, 0, 0], [0, 1 / box.scale, 0]], dtype=np.float64)
    mask = cv2.warpAffine(mask, M, (w, h), flags=cv2.INTER_NEAREST).astype(bool)
    chance = float(cues.surface[region > 0].mean())
    second = None
    if alternative is not None:
        second = _outline(cues, alternative, all_peaks, all_peaks, mask, chance)
    elif replaced is not None:  # the cushions read off the frame may make no rectangle a camera sees
        quad_corners, quad_peaks = _snap_to_peaks(replaced[0], cues)
        second = _outline(cues, quad_corners, replaced[1], quad_peaks, mask, chance)
    return replace(_outline(cues, corners, seen, from_peak, mask, chance), alternative=second, cushion_lines=runs[0])


def _outline(
    cues: TableCues, corners: np.ndarray, seen: np.ndarray, from_peak: np.ndarray, mask: np.ndarray, chance: float
) -> SurfaceOutline:
    """The outline with these corners: its side pockets, and its confidence (``chance`` times the share of the
    quadrilateral the surface ``mask`` fills)."""
    side_pocket = np.zeros(4)
    for k in range(4):
        a, b = corners[k], corners[(k + 1) % 4]
        length = float(np.hypot(*(b - a)))
        for p, score in zip(cues.sides_px, cues.side_scores, strict=True):
            off_middle = np.hypot(*(p - 0.5 * (a + b)))
            if off_middle <= SIDE_POCKET_REACH * length:
                side_pocket[k] = max(side_pocket[k], float(score))
    inside = quad_mask(corners, mask.shape)
    fill = float((mask & inside).sum()) / max(float(inside.sum()), 1.0)
    return SurfaceOutline(corners, seen, from_peak, side_pocket, mask, chance * min(fill, 1.0), cues=cues)


def long_cushion_pair(outline: SurfaceOutline) -> tuple[np.ndarray, list[CushionMark]] | None:
    """Two of the outline's cushion lines that look like the table's two long cushions, and the marks on them.

    Of the pairs of :attr:`~SurfaceOutline.cushion_lines` that do not meet within the photo (two cushions meeting
    at a corner in view are a long and a short one), the one with the most marks: the model's side-pocket and corner
    peaks (at least :data:`MARK_MIN_SCORE`) within :data:`MARK_REACH` of a line and in the photo. It must have a side
    pocket and two marks in all (:func:`~pix2pockets.vision.table.outline_fit.fit_two_cushions`). None without one.
    """
    cues = outline.cues
    if cues is None or len(outline.cushion_lines) < 2:
        return None
    w, h = cues.image_size
    reach = MARK_REACH * float(np.hypot(w, h))
    peaks = [
        (p, "pocket") for p, score in zip(cues.sides_px, cues.side_scores, strict=True) if score >= MARK_MIN_SCORE
    ] + [(p, "corner") for p, score in zip(cues.corners_px, cues.corner_scores, strict=True) if score >= MARK_MIN_SCORE]
    peaks = [(p, kind) for p, kind in peaks if 0 <= p[0] <= w and 0 <= p[1] <= h]
    best: tuple[int, np.ndarray, list[CushionMark]] | None = None
    for i, j in itertools.combinations(range(len(outline.cushion_lines)), 2):
        pair = outline.cushion_lines[[i, j]]
        meet = np.cross(pair[0], pair[1])
        if abs(meet[2]) > 1e-12 and 0 <= meet[0] / meet[2] <= w and 0 <= meet[1] / meet[2] <= h:
            continue
        marks = []
        for p, kind in peaks:
            d = np.abs(pair[:, :2] @ p + pair[:, 2]) / np.hypot(pair[:, 0], pair[:, 1])
            k = int(np.argmin(d))
            if d[k] <= reach:
                marks.append(CushionMark(np.asarray(p, dtype=float), k, kind))
        if not any(m.kind == "pocket" for m in marks) or len(marks) < 2:
            continue
        if best is None or len(marks) > best[0]:
            best = (len(marks), pair, marks)
    return None if best is None else (best[1], best[2])

"""Table fitting from diamond (dot) detections: rails, point ordering, homography and camera.

The method follows the paper (section 5.1) and makes it robust to missing dots:

1. **Rail lines.** Iterative RANSAC line fits split the dot centres into rails: the line through the
   most dots wins, its inliers are removed, and so on, up to four lines.
2. **Labelling.** Pairs of rail lines are hypothesised to be particular rails of the table (bottom, foot,
   top, head), with the dots on them in either direction and at any run of consecutive diamond positions.
   Each hypothesis gives a homography from which all 18 diamonds are projected; the hypothesis matching
   the most dots (then the smallest residual, measured in table metres) wins. A short rail has 3 dots and
   a long rail 6, split by the side pocket, so the spacing pattern tells the long rails from the short
   ones even when dots are hidden. Reflected hypotheses are rejected: a camera above the table sees the
   table frame with its handedness reversed in pixel coordinates (``v`` down).
3. **Corners.** Where two adjacent rails each have at least two dots, their lines intersect in a corner of
   the diamond rectangle, ``(-s, -s)`` ... ``(L + s, W + s)`` for the diamond setback ``s``, on the rail
   cap at ``cushion_height`` (not at the cushion nose corners). The corners are validated (convex,
   in a plausible region around the image, consistent with the fitted table) and added to the points.
4. **Homography and camera.** A robust homography (``cv2.USAC_MAGSAC``) from all matched points, then
   the camera (focal length, pose) from it, refined on the points at their true height
   (:func:`pix2pockets.geometry.homography.camera_from_homography`).

Convention for the inherent 180-degree ambiguity (the diamond pattern is symmetric): the head rail
(``x = 0``) is the short rail whose midpoint lies further left and lower in the image, i.e. the one that
minimises ``(u_head - u_foot) - (v_head - v_foot)``. For a top view with the long axis horizontal this
puts the head on the left; for a view along the table it puts the head rail nearest the camera.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import cv2
import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.homography import apply_homography, camera_from_homography, fit_homography
from pix2pockets.geometry.table import TableSpec
from pix2pockets.vision.detections import Detections

RAIL_DIAMONDS: tuple[tuple[int, ...], ...] = ((0, 1, 2, 3, 4, 5), (6, 7, 8), (9, 10, 11, 12, 13, 14), (15, 16, 17))
"""Diamond indices of each rail in ``TableSpec.diamonds`` order: bottom, foot, top, head."""

MIN_DOTS = 4
MAX_DOTS = 40  # more candidates than this are cut by confidence (false positives)


class TableFitError(ValueError):
    """The table could not be found in the image; the message says why."""


@dataclass(frozen=True, slots=True, eq=False)
class TableFit:
    """A fitted table.

    Attributes:
        spec: the table.
        camera: the recovered camera (table frame -> pixels).
        dot_index: for each input dot, the diamond index it was matched to (0-17), or -1 (outlier).
        diamond_corners_px: image positions of the diamond-rectangle corners (rail-cap height), (4, 2);
            NaN for corners whose two rails lacked the dots to intersect.
        rms_px: root-mean-square reprojection error of the matched points [px].
        n_matched: number of matched dots.
    """

    spec: TableSpec
    camera: PinholeCamera
    dot_index: np.ndarray
    diamond_corners_px: np.ndarray
    rms_px: float
    n_matched: int

    @property
    def homography(self) -> np.ndarray:
        """Image pixels -> table metres on the cloth (``z = 0``), (3, 3), normalised to ``H[2, 2] = 1``."""
        H = np.linalg.inv(self.camera.table_homography(0.0))
        return H / H[2, 2]

    @property
    def corners_px(self) -> np.ndarray:
        """The 4 playing-surface corners (cushion nose lines, on the cloth) in pixels, (4, 2), in
        ``TableSpec.corners`` order."""
        return self.camera.project_table(self.spec.corners, 0.0)

    def image_to_table(self, uv: np.ndarray, z: float = 0.0) -> np.ndarray:
        """Pixels (..., 2) -> table points [m] on the plane at height ``z`` [m]."""
        return apply_homography(np.linalg.inv(self.camera.table_homography(z)), uv)

    def table_to_image(self, xy: np.ndarray, z: float = 0.0) -> np.ndarray:
        """Table points [m] (..., 2) at height ``z`` -> pixels (..., 2)."""
        return self.camera.project_table(xy, z)


# ----------------------------------------------------------------------------- rail lines
def _line_through(p: np.ndarray, q: np.ndarray) -> np.ndarray | None:
    d = q - p
    n = math.hypot(*d)
    if n < 1e-9:
        return None
    normal = np.array([-d[1], d[0]]) / n
    return np.array([normal[0], normal[1], -normal @ p])


def _tls_line(points: np.ndarray) -> np.ndarray:
    """Total-least-squares line ``(a, b, c)`` with ``a^2 + b^2 = 1`` through points (n, 2)."""
    mean = points.mean(axis=0)
    _, _, vt = np.linalg.svd(points - mean)
    normal = vt[-1]
    return np.array([normal[0], normal[1], -normal @ mean])


def fit_rail_lines(points: np.ndarray, tol_px: float, max_lines: int = 4) -> list[np.ndarray]:
    """Split points into collinear groups by iterative RANSAC (exhaustive over point pairs).

    Args:
        points: dot centres (n, 2) [px].
        tol_px: inlier distance to a line [px].
        max_lines: most lines to extract.

    Returns:
        Index arrays into ``points``, one per line (each with >= 2 points), sorted along the line.
    """
    remaining = np.arange(len(points))
    lines: list[np.ndarray] = []
    while len(lines) < max_lines and len(remaining) >= 2:
        pts = points[remaining]
        best: tuple[int, float, np.ndarray] | None = None
        for i, j in itertools.combinations(range(len(pts)), 2):
            line = _line_through(pts[i], pts[j])
            if line is None:
                continue
            dist = np.abs(pts @ line[:2] + line[2])
            inl = dist < tol_px
            key = (int(inl.sum()), -float(np.sum(dist[inl] ** 2)))
            if best is None or key > best[:2]:
                best = (key[0], key[1], inl)
        if best is None or best[0] < 2:
            break
        inl = best[2]
        if inl.sum() >= 3:  # refine on the inliers, then take the inliers of the refined line
            line = _tls_line(pts[inl])
            refined = np.abs(pts @ line[:2] + line[2]) < tol_px
            if refined.sum() >= inl.sum():
                inl = refined
        idx = remaining[inl]
        direction = points[idx[-1]] - points[idx[0]]
        order = np.argsort(points[idx] @ direction)
        lines.append(idx[order])
        remaining = remaining[~inl]
    return lines


# ----------------------------------------------------------------------------- labelling
def _signed_area(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _match_dots(
    H_img_to_table: np.ndarray, dots: np.ndarray, diamonds: np.ndarray, tol_m: float
) -> tuple[np.ndarray, float]:
    """Match dots to diamonds (one-to-one, nearest in table metres). Returns (index per dot, cost)."""
    xy = apply_homography(H_img_to_table, dots)
    d = np.linalg.norm(xy[:, None, :] - diamonds[None, :, :], axis=-1)
    d = np.where(np.isfinite(d), d, np.inf)
    index = np.full(len(dots), -1)
    cost = 0.0
    order = np.argsort(d.min(axis=1))
    used: set[int] = set()
    for i in order:
        j = int(np.argmin(d[i]))
        if d[i, j] < tol_m and j not in used:
            index[i] = j
            used.add(j)
            cost += d[i, j] ** 2
    return index, cost


def _hypotheses(line_a: np.ndarray, line_b: np.ndarray):
    """Yield (dot indices, diamond indices) for pairs of lines assigned to two different rails."""
    for ra, rb in itertools.permutations(range(4), 2):
        da, db = RAIL_DIAMONDS[ra], RAIL_DIAMONDS[rb]
        if len(line_a) > len(da) or len(line_b) > len(db):
            continue
        for sa, sb in itertools.product(range(len(da) - len(line_a) + 1), range(len(db) - len(line_b) + 1)):
            for fa, fb in itertools.product((1, -1), (1, -1)):
                dots = np.concatenate([line_a[::fa], line_b[::fb]])
                diam = np.array(da[sa : sa + len(line_a)] + db[sb : sb + len(line_b)])
                yield dots, diam


def label_dots(dots: np.ndarray, lines: list[np.ndarray], spec: TableSpec, tol_m: float | None = None) -> np.ndarray:
    """Assign each dot a diamond index (0-17) or -1, from hypotheses on pairs of rail lines.

    Raises:
        TableFitError: when no hypothesis matches at least ``MIN_DOTS`` dots on two rails.
    """
    diamonds = spec.diamonds
    tol_m = tol_m if tol_m is not None else 0.25 * spec.length / 8
    usable = [ln for ln in lines if len(ln) >= 2]
    best: tuple[int, float] | None = None
    best_index: np.ndarray | None = None
    table_rect = np.array([[0.0, 0.0], [spec.length, 0.0], [spec.length, spec.width], [0.0, spec.width]], dtype=float)
    seen: set[tuple] = set()
    for a, b in itertools.combinations(range(len(usable)), 2):
        for dot_idx, diam_idx in _hypotheses(usable[a], usable[b]):
            if len(dot_idx) < 4:
                continue
            try:
                H = fit_homography(diamonds[diam_idx], dots[dot_idx])  # table -> image
            except ValueError:
                continue
            rect_px = apply_homography(H, table_rect)
            if not np.all(np.isfinite(rect_px)) or _signed_area(rect_px) >= 0:
                continue  # reflected (or the table behind the camera)
            # the table must stay on one side of the horizon: no projective wrap between the corners
            w = np.column_stack([table_rect, np.ones(4)]) @ H[2]
            if not (np.all(w > 0) or np.all(w < 0)):
                continue
            Hinv = np.linalg.inv(H)
            index, cost = _match_dots(Hinv, dots, diamonds, tol_m)
            for _ in range(2):  # refit on all matched dots
                m = index >= 0
                if m.sum() < 4:
                    break
                try:
                    H = fit_homography(diamonds[index[m]], dots[m])
                except ValueError:
                    break
                index, cost = _match_dots(np.linalg.inv(H), dots, diamonds, tol_m)
            key_t = tuple(index)
            if key_t in seen:
                continue
            seen.add(key_t)
            score = (int((index >= 0).sum()), -cost)
            if best is None or score > best:
                best, best_index = score, index
    if best_index is None or best is None or best[0] < MIN_DOTS:
        n = 0 if best is None else best[0]
        raise TableFitError(
            f"too few table points: {n} diamonds could be matched (need {MIN_DOTS} on at least two rails)"
        )
    rails = {_rail_of(int(j)) for j in best_index[best_index >= 0]}
    if len(rails) < 2:
        raise TableFitError("too few table points: the matched diamonds lie on one rail only")
    return best_index


def _rail_of(diamond: int) -> int:
    for r, ids in enumerate(RAIL_DIAMONDS):
        if diamond in ids:
            return r
    raise ValueError(diamond)


# ----------------------------------------------------------------------------- corners
def diamond_rectangle(spec: TableSpec) -> np.ndarray:
    """Corners of the rectangle through the diamond centres [m], (4, 2), in ``TableSpec.corners`` order."""
    s = spec.diamond_setback
    L, W = spec.length, spec.width
    return np.array([[-s, -s], [L + s, -s], [L + s, W + s], [-s, W + s]])


def _rail_corners(dots: np.ndarray, index: np.ndarray, image_size: tuple[int, int]) -> np.ndarray:
    """Intersections of adjacent rail lines (rails with >= 2 matched dots), (4, 2), NaN where missing.

    Corner ``k`` is the meeting point of rails ``k - 1`` and ``k`` (bottom/head, bottom/foot, foot/top,
    top/head).
    """
    lines: list[np.ndarray | None] = []
    for r in range(4):
        m = np.isin(index, RAIL_DIAMONDS[r])
        lines.append(_tls_line(dots[m]) if m.sum() >= 2 else None)
    # rails in order bottom(0), foot(1), top(2), head(3); corner 0 = head/bottom, 1 = bottom/foot, ...
    pairs = [(3, 0), (0, 1), (1, 2), (2, 3)]
    out = np.full((4, 2), np.nan)
    for k, (ra, rb) in enumerate(pairs):
        la, lb = lines[ra], lines[rb]
        if la is None or lb is None:
            continue
        p = np.cross(la, lb)
        if abs(p[2]) < 1e-9 * (abs(p[0]) + abs(p[1]) + 1e-12):
            continue
        out[k] = p[:2] / p[2]
    return out


def _validate_corners(corners: np.ndarray, image_size: tuple[int, int]) -> None:
    w, h = image_size
    ok = np.all(np.isfinite(corners), axis=1)
    if ok.any():
        c = corners[ok]
        far = (c[:, 0] < -w) | (c[:, 0] > 2 * w) | (c[:, 1] < -h) | (c[:, 1] > 2 * h)
        if far.any():
            raise TableFitError("no table found: rail lines meet far outside the image")
    if ok.all():
        quad = corners
        cross = []
        for i in range(4):
            a, b, c = quad[i], quad[(i + 1) % 4], quad[(i + 2) % 4]
            u, v = b - a, c - b
            cross.append(u[0] * v[1] - u[1] * v[0])
        if not (all(x < 0 for x in cross) or all(x > 0 for x in cross)):
            raise TableFitError("no table found: the rail lines do not form a convex quadrilateral")


# ----------------------------------------------------------------------------- main entry
def _tolerance_px(dots: np.ndarray, image_size: tuple[int, int]) -> float:
    diag = math.hypot(*image_size)
    if len(dots) >= 2:
        d = np.linalg.norm(dots[:, None] - dots[None], axis=-1)
        d[np.diag_indices(len(dots))] = np.inf
        nn = float(np.median(d.min(axis=1)))
    else:
        nn = diag
    return float(np.clip(0.15 * nn, 1.5, 0.005 * diag))


def fit_table(
    dots: np.ndarray | Detections,
    image_size: tuple[int, int],
    spec: TableSpec | None = None,
    tol_px: float | None = None,
    focal_prior_px: float | None = None,
) -> TableFit:
    """Fit the table from dot detections.

    Args:
        dots: dot centres (n, 2) [px], or :class:`Detections` (its dots are used, best first).
        image_size: (width, height) [px].
        spec: the table (default 9-foot).
        tol_px: line inlier tolerance [px] (default: from the dot spacing and image size).
        focal_prior_px: prior focal length [px] for near-top views (default: the larger image side).

    Raises:
        TableFitError: too few dots, no consistent rails, or an implausible table.
    """
    spec = spec or TableSpec()
    if isinstance(dots, Detections):
        d = dots[dots.is_dot]
        order = np.argsort(-d.confidence)
        pts = d.centres[order][:MAX_DOTS]
        back = order[:MAX_DOTS]
        n_total = len(d)
    else:
        pts = np.asarray(dots, dtype=float).reshape(-1, 2)
        back = np.arange(len(pts))
        n_total = len(pts)
    if not np.all(np.isfinite(pts)):
        raise TableFitError("dot positions must be finite")
    if len(pts) < MIN_DOTS:
        raise TableFitError(f"too few table points: {len(pts)} diamonds detected, need at least {MIN_DOTS}")
    tol = tol_px if tol_px is not None else _tolerance_px(pts, image_size)
    lines = fit_rail_lines(pts, tol)
    if sum(len(x) >= 2 for x in lines) < 2:
        raise TableFitError("too few table points: diamonds on at least two rails are needed")
    index = label_dots(pts, lines, spec)
    corners = _rail_corners(pts, index, image_size)
    _validate_corners(corners, image_size)

    h = spec.cushion_height
    m = index >= 0
    world = spec.diamonds[index[m]]
    image = pts[m]
    rect = diamond_rectangle(spec)
    has = np.all(np.isfinite(corners), axis=1)
    world_all = np.vstack([world, rect[has]])
    image_all = np.vstack([image, corners[has]])
    thresh = max(3.0, 2 * tol)
    H, mask = cv2.findHomography(world_all, image_all, cv2.USAC_MAGSAC, thresh)
    if H is None:
        H = fit_homography(world_all, image_all)
        mask = np.ones(len(world_all), dtype=bool)
    mask = np.asarray(mask).reshape(-1).astype(bool)
    if mask.sum() < 4:
        raise TableFitError("no table found: the diamonds do not fit a table (homography failed)")
    world3 = np.column_stack([world_all[mask], np.full(mask.sum(), h)])
    camera = camera_from_homography(
        H, image_size, z=h, world_points=world3, image_points=image_all[mask], focal_prior_px=focal_prior_px
    )
    proj = camera.project(world3)
    err = np.linalg.norm(proj - image_all[mask], axis=1)
    rms = float(np.sqrt(np.mean(err**2)))
    if not np.isfinite(rms) or rms > max(8.0, 4 * tol):
        raise TableFitError(f"no table found: the diamonds do not fit a {spec.name} table (error {rms:.1f} px)")

    # the 180-degree convention: head rail further left / lower in the image than the foot rail
    head_mid = camera.project_table(np.array([0.0, spec.width / 2]), h)
    foot_mid = camera.project_table(np.array([spec.length, spec.width / 2]), h)
    metric = (head_mid[0] - foot_mid[0]) - (head_mid[1] - foot_mid[1])
    if metric > 0:
        camera, index, corners = _rotate_half_turn(camera, index, corners, spec)

    dot_index_full = np.full(n_total, -1)
    dot_index_full[back] = index
    return TableFit(spec, camera, dot_index_full, corners, rms, int(m.sum()))


def _rotate_half_turn(
    camera: PinholeCamera, index: np.ndarray, corners: np.ndarray, spec: TableSpec
) -> tuple[PinholeCamera, np.ndarray, np.ndarray]:
    """Relabel the table turned by 180 degrees: ``(x, y) -> (L - x, W - y)``."""
    D = np.diag([-1.0, -1.0, 1.0])
    c = np.array([spec.length, spec.width, 0.0])
    R = camera.R @ D
    t = camera.R @ c + camera.t
    new_index = np.where(index >= 0, (index + 9) % 18, -1)
    return PinholeCamera(camera.K, R, t, camera.image_size), new_index, np.roll(corners, 2, axis=0)

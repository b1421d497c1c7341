"""Lines and quadrilaterals in the image: the geometry of a table's outline.

Lines are ``(a, b, c)`` with ``a u + b v + c = 0`` and ``a^2 + b^2 = 1`` [px]. A quadrilateral is its corners (4, 2),
side ``k`` running from corner ``k`` to corner ``k + 1``.
"""

from __future__ import annotations

import math

import cv2
import numpy as np


def line_through(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The line ``a u + b v + c = 0`` (``a^2 + b^2 = 1``) through points ``p`` and ``q`` (2,)."""
    d = q - p
    n = math.hypot(d[0], d[1]) or 1.0
    normal = np.array([-d[1], d[0]]) / n
    return np.array([normal[0], normal[1], -normal @ p])


def intersect(l1: np.ndarray, l2: np.ndarray) -> np.ndarray:
    """Where two lines (3,) meet (2,); NaN for parallel lines."""
    p = np.cross(l1, l2)
    if abs(p[2]) < 1e-12:
        return np.array([np.nan, np.nan])
    return p[:2] / p[2]


def signed_area(poly: np.ndarray) -> float:
    """Signed area of a polygon (n, 2): positive for counter-clockwise vertices in a y-up frame (a camera above the
    table shows the table frame's corners with a negative area in pixel coordinates, v down)."""
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def enclosing_quad(hull: np.ndarray) -> np.ndarray | None:
    """The quadrilateral enclosing a convex polygon (n, 2) found by merging edges: the edge whose removal (its
    two neighbours extended to meet) adds the least area goes first. Returns (4, 2) in the hull's order, or
    None when the hull has fewer than four vertices or cannot be reduced."""
    pts = [(float(x), float(y)) for x, y in np.asarray(hull, dtype=float).reshape(-1, 2)]
    while len(pts) > 4:
        n = len(pts)
        best, best_area, best_point = -1, math.inf, (0.0, 0.0)
        for i in range(n):
            (ax, ay), (bx, by) = pts[i - 1], pts[i]
            (cx, cy), (dx, dy) = pts[(i + 1) % n], pts[(i + 2) % n]
            # edges a-b and c-d extended past b and c meet at p, replacing edge b-c
            ux, uy, vx, vy, wx, wy = bx - ax, by - ay, dx - cx, dy - cy, cx - ax, cy - ay
            den = ux * vy - uy * vx
            if abs(den) < 1e-12:
                continue
            s = (wx * vy - wy * vx) / den
            r = (wx * uy - wy * ux) / den
            if s < 1.0 or r > 0.0:  # the lines meet behind the edge: removing it does not enclose
                continue
            px, py = ax + s * ux, ay + s * uy
            area = 0.5 * abs((px - bx) * (cy - by) - (py - by) * (cx - bx))
            if area < best_area:
                best, best_area, best_point = i, area, (px, py)
        if best < 0:
            return None
        pts[best] = best_point
        del pts[(best + 1) % n]
    return np.array(pts) if len(pts) == 4 else None


def tls_fit(points: np.ndarray) -> np.ndarray:
    """Total-least-squares line ``(a, b, c)``, ``a^2 + b^2 = 1``, through points (n, 2)."""
    mean = points.mean(axis=0)
    d = points - mean
    cov = d.T @ d
    _, vecs = np.linalg.eigh(cov)
    normal = vecs[:, 0]
    return np.array([normal[0], normal[1], -normal @ mean])


def robust_line(
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


def quad_of_lines(lines: np.ndarray) -> np.ndarray:
    """Corners (4, 2) of the quadrilateral with sides ``lines`` (4, 3): corner ``k`` where sides ``k - 1`` and ``k``
    meet."""
    return np.array([intersect(lines[k - 1], lines[k]) for k in range(4)])


def quad_of_point_sets(sides: list) -> np.ndarray:
    """Corners (4, 2) of the quadrilateral whose four sides, in order round it, each run through a set of points
    (n >= 2, 2): a total-least-squares line per side, crossed as in :func:`quad_of_lines`."""
    return quad_of_lines(np.array([tls_fit(np.asarray(points, dtype=float)) for points in sides]))


def quad_length(quad: np.ndarray) -> float:
    """A quadrilateral's length [px]: the larger mean length of its two pairs of opposite sides (a table's length
    as the photo shows it, whichever way it lies)."""
    sides = np.linalg.norm(np.roll(quad, -1, axis=0) - quad, axis=1)
    return float(max(sides[0] + sides[2], sides[1] + sides[3]) / 2)


def side_midpoint(quad: np.ndarray, k: int) -> np.ndarray:
    """The image of the midpoint of side ``k`` of a rectangle seen as ``quad`` (4, 2) [px]: where the line from the
    diagonals' crossing to the vanishing point of the other two sides meets the side."""
    h = np.column_stack([quad, np.ones(4)])
    centre = np.cross(np.cross(h[0], h[2]), np.cross(h[1], h[3]))
    vanish = np.cross(np.cross(h[(k + 1) % 4], h[(k + 2) % 4]), np.cross(h[(k + 3) % 4], h[k]))
    p = np.cross(np.cross(centre, vanish), np.cross(h[k], h[(k + 1) % 4]))
    if abs(p[2]) < 1e-12:
        return (quad[k] + quad[(k + 1) % 4]) / 2
    return p[:2] / p[2]


def corner_gap(a: np.ndarray, b: np.ndarray) -> float:
    """Largest distance [px] between the corners of two quadrilaterals (4, 2), matched round either way from any
    corner; inf when a corner is not finite."""
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        return float("inf")
    return min(float(np.max(np.linalg.norm(a - np.roll(o, k, axis=0), axis=1))) for o in (b, b[::-1]) for k in range(4))


def quad_mask(quad_px: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """The pixels (H, W) bool of an array of ``shape`` inside the convex quadrilateral ``quad_px`` (4, 2) [pixel
    indices, read to 1/16 px]; none for a quadrilateral with a corner not finite or far off the array."""
    mask = np.zeros(shape[:2], dtype=np.uint8)
    quad = np.asarray(quad_px, dtype=float).reshape(-1, 2)
    if np.all(np.isfinite(quad)) and np.abs(quad).max() <= 1e5:
        cv2.fillConvexPoly(mask, np.round(quad * 16).astype(np.int32), 1, shift=4)
    return mask.astype(bool)


def share_in_frame(quad: np.ndarray, image_size: tuple[int, int]) -> float:
    """Share of a convex quadrilateral's area (4, 2) [px] inside the image ``(width, height)``; 0 for a quadrilateral
    with a corner that does not project (NaN: behind the camera) or no area."""
    quad = np.asarray(quad, dtype=np.float32).reshape(4, 2)
    if not np.all(np.isfinite(quad)):
        return 0.0
    area = abs(float(cv2.contourArea(quad)))
    if area <= 0.0:
        return 0.0
    w, h = image_size
    frame = np.array([[0, 0], [w, 0], [w, h], [0, h]], dtype=np.float32)
    inside, _ = cv2.intersectConvexConvex(quad, frame)
    return float(min(max(inside / area, 0.0), 1.0))

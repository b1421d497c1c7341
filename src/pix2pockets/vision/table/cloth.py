"""The playing cloth in an RGB photo: its region, its four cushion lines and where its side pockets are.

A person finds a pool table at a glance from its cloth: one large, fairly uniform region of one colour bounded by
four straight cushions. :func:`find_cloth` does the same with classical image processing, no training:

1. **Region.** Candidate regions of one colour are found in the photo shrunk to :data:`WORK_SIDE` pixels and scored
   by how well four lines bound them (:mod:`pix2pockets.vision.table.cloth_region`); the balls must lie on the cloth.
2. **Lines.** The best region's boundary points are split among the sides of the quadrilateral enclosing it and a
   robust line is fitted to each (pockets, players and cues cut the boundary: only straight runs count, and a line
   must bound the region, not cross it). A side whose boundary runs along the frame edge is not seen.
3. **Refinement.** Each seen line is moved onto the colour edge in the full-resolution photo, searched along its
   normal.
4. **Pockets.** A side pocket is a dark notch in the middle of a long cushion (:func:`side_midpoint`).

The lines found are the outer edge of the cloth-coloured region: the back of the cushion tops, where the rail begins
(the cushions are covered with the same cloth). :mod:`pix2pockets.vision.table.outline_fit` models them as such.

Example:
    >>> cloth = find_cloth(rgb, ball_boxes)  # doctest: +SKIP
    >>> cloth.corners_px, cloth.seen  # the outline's corners [px], which sides the photo shows  # doctest: +SKIP
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from pix2pockets.vision.table.cloth_region import (
    content_frame,
    filled_region,
    find_candidates,
    lab_of,
    on_border,
    plain_distance,
)
from pix2pockets.vision.table.errors import TableFitError
from pix2pockets.vision.table.quad_geometry import enclosing_quad as enclosing_quad  # re-exported
from pix2pockets.vision.table.quad_geometry import (
    line_through,
    quad_of_lines,
    robust_line,
    side_midpoint,
    signed_area,
)
from pix2pockets.vision.table.quad_geometry import tls_fit as tls_fit  # re-exported

WORK_SIDE = 192
"""Longer side of the shrunk photo the region is found on [px]."""
SEEN_SUPPORT = 0.25
"""Share of a side's length the cloth's boundary must follow for the side to count as seen."""
REFINE_REACH = 2.5
"""The full-resolution edge is searched this many work pixels either side of each line."""


@dataclass(frozen=True, slots=True, eq=False)
class ClothOutline:
    """The cloth found in a photo.

    Attributes:
        corners_px: the four corners of the cloth outline [px], (4, 2), in order around the quadrilateral
            (counter-clockwise as seen on screen, a negative signed area in pixel coordinates, as the table frame's
            corners appear to a camera above the table); a corner may lie outside the photo.
        lines: the four sides as lines ``a u + b v + c = 0`` with ``a^2 + b^2 = 1`` [px], (4, 3); side ``k`` runs
            from corner ``k`` to corner ``k + 1``.
        support: for each side, the share of its length that the region's boundary follows (0: not seen; the side
            runs along the frame edge or was inferred from the other three).
        mask: the cloth region (H, W) bool, at the photo's resolution (found on a coarse grid: edges to a few px).
        colour_lab: the cloth colour the region was grown from, CIE Lab (L 0-100).
        confidence: how table-like the region is, 0-1: the fill of its quadrilateral, the share of its boundary on
            the quadrilateral's sides, its size, the sides seen, the balls inside.
        pocket_darkness: for each side, how much darker a band across the side is at the side's middle than near
            its quarters (Lab lightness); a side pocket's hole makes a long cushion's middle dark.
    """

    corners_px: np.ndarray
    lines: np.ndarray
    support: np.ndarray
    mask: np.ndarray
    colour_lab: np.ndarray
    confidence: float
    pocket_darkness: np.ndarray

    @property
    def seen(self) -> np.ndarray:
        """For each side, whether the region's boundary follows it over at least :data:`SEEN_SUPPORT` of its length."""
        return self.support >= SEEN_SUPPORT


# ----------------------------------------------------------------------------- lines
def _side_lines(
    contour: np.ndarray, quad: np.ndarray, frame: tuple[int, int, int, int]
) -> tuple[np.ndarray, np.ndarray]:
    """Lines (4, 3) fitted to the boundary points near each quadrilateral side, and each side's support."""
    real = contour[~on_border(contour, frame)]
    scale = math.sqrt(abs(signed_area(quad)))
    lines = np.zeros((4, 3))
    support = np.zeros(4)
    band = 0.05 * scale
    tol = max(1.0, 0.006 * scale)
    for k in range(4):
        a, b = quad[k], quad[(k + 1) % 4]
        line = line_through(a, b)
        lines[k] = line
        length = float(np.linalg.norm(b - a))
        if length <= 0 or not len(real):
            continue
        d = np.abs(real @ line[:2] + line[2])
        t = (real - a) @ (b - a) / length**2
        near = real[(d < band) & (t > 0.03) & (t < 0.97)]
        fitted = robust_line(near, tol, contour, quad.mean(axis=0))
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
        if support[k] < SEEN_SUPPORT:
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
        dist = plain_distance(lab_of(samples), colour)  # the edge is where any channel changes
        # the edge: the steepest rise of the colour distance along the outward normal
        grad = np.diff(cv2.GaussianBlur(dist, (1, 5), 0), axis=1)
        j = np.argmax(grad, axis=1)
        strong = grad[np.arange(len(j)), j] > 0.25
        if strong.sum() < 8:
            continue
        edge = pts[np.arange(len(j)), j] + 0.5 * (pts[np.arange(len(j)), j + 1] - pts[np.arange(len(j)), j])
        fitted = robust_line(edge[strong].astype(float), 1.5)
        if fitted is None:
            continue
        new, inliers = fitted
        if inliers.sum() < 8 or abs(new[:2] @ line[:2]) < math.cos(math.radians(3)):
            continue
        out[k] = new if new[:2] @ line[:2] > 0 else -new
    return out


def _pocket_darkness(rgb: np.ndarray, quad: np.ndarray) -> np.ndarray:
    """For each side of ``quad`` (4, 2) [px], how much darker a band across the side (from just inside to 3 % of the
    side's length outside) is at the side's middle than near its quarters (Lab lightness): a side pocket's hole.
    Sampled in the full-resolution photo."""
    h, w = rgb.shape[:2]
    centre = quad.mean(axis=0)
    out = np.zeros(4)
    for k in range(4):
        a, b = quad[k], quad[(k + 1) % 4]
        length = float(np.linalg.norm(b - a))
        if not np.isfinite(length) or length < 20:
            continue
        along = (b - a) / length
        normal = np.array([-along[1], along[0]])
        if normal @ (centre - a) > 0:
            normal = -normal
        mid = side_midpoint(quad, k)
        depth = np.linspace(-0.005, 0.03, 8) * length
        t = np.concatenate([np.linspace(-0.05, 0.05, 7), np.linspace(-0.3, -0.15, 6), np.linspace(0.15, 0.3, 6)])
        pts = mid[None, None] + (t * length)[:, None, None] * along + depth[None, :, None] * normal
        samples = cv2.remap(rgb, pts[..., 0].astype(np.float32) - 0.5, pts[..., 1].astype(np.float32) - 0.5,
                            cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=(-1, -1, -1))  # fmt: skip
        ok = (pts[..., 0] >= 0) & (pts[..., 0] <= w) & (pts[..., 1] >= 0) & (pts[..., 1] <= h)
        light = np.where(ok, lab_of(samples)[..., 0], np.inf).min(axis=1)  # darkest across the band, per position
        middle, rest = light[:7][np.isfinite(light[:7])], light[7:][np.isfinite(light[7:])]
        if len(middle) < 3 or len(rest) < 6:
            continue
        out[k] = float(np.median(rest) - np.median(np.sort(middle)[:2]))
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
    lab = lab_of(small)
    frame = content_frame(cv2.cvtColor(small, cv2.COLOR_RGB2GRAY).astype(np.float32))
    boxes = np.zeros((0, 4)) if ball_boxes is None else np.asarray(ball_boxes, dtype=float).reshape(-1, 4)
    boxes = boxes * np.array([sx, sy, sx, sy])
    candidates = find_candidates(lab, boxes, frame)
    if not candidates:
        raise TableFitError("no table found: no region of one colour bounded by straight cushions")
    best = max(candidates, key=lambda c: c.score)
    filled, contour = filled_region(best.region)
    lines, support = _side_lines(contour, best.quad, frame)
    quad = quad_of_lines(lines)
    if not np.all(np.isfinite(quad)):
        quad = best.quad
        lines = np.array([line_through(quad[k], quad[(k + 1) % 4]) for k in range(4)])
    # to full-resolution pixel indices: work pixel i covers photo pixels (i + 0.5) / s - 0.5 around its centre
    A = np.array([[sx, 0.0, 0.5 * sx - 0.5], [0.0, sy, 0.5 * sy - 0.5], [0.0, 0.0, 1.0]])
    full_lines = lines @ A
    full_lines /= np.linalg.norm(full_lines[:, :2], axis=1, keepdims=True)
    full_quad = quad_of_lines(full_lines)
    full_lines = _refine_lines(rgb, full_lines, full_quad, support, best.colour, reach=REFINE_REACH / min(sx, sy))
    # pixel indices -> image coordinates (origin at the top-left pixel's corner, as the cameras use)
    full_quad = quad_of_lines(full_lines) + 0.5
    if signed_area(full_quad) > 0:  # the table frame's order as a camera above sees it: negative area in (u, v)
        full_quad = full_quad[::-1].copy()
        support = support[[2, 1, 0, 3]]
    full_lines = np.array([line_through(full_quad[k], full_quad[(k + 1) % 4]) for k in range(4)])
    darkness = _pocket_darkness(rgb, full_quad)
    mask = cv2.resize(filled, (w, h), interpolation=cv2.INTER_NEAREST).astype(bool)
    return ClothOutline(
        full_quad, full_lines, support, mask, best.colour.astype(float), float(min(best.score, 1.0)), darkness
    )

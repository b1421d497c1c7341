"""Move a fitted table's cloth outline onto the cloth's edge in the photo.

The table model reads the playing surface on a coarse grid and was trained on renders; on real photos its corners can
be several pixels off. The cloth's outer edge, where the cushion cloth meets the rail, is usually the sharpest line
around a table. :func:`snap_to_cloth_edge` searches each side of an outline along its normal for the steepest change
away from the cloth's colour, fits a robust line to the edge points and keeps the new line only where it separates
cloth from non-cloth better than the old one (a player's arm, a ball or the rail's outer edge do not).

A light rail beside a light cloth (white laminate, silver trim) differs less from the cloth than the dark floor or
table body beyond it, so the steepest change can be the rail's outer edge. Each profile's innermost clear rise, where
the colour leaves the cloth for one that is not the cloth in shadow (a cushion's dark face), gives a second line; of
the two, the one nearer the side as it was is kept.

Example:
    >>> colour = cloth_colour(rgb, surface.mask, ball_boxes)  # doctest: +SKIP
    >>> snapped = snap_to_cloth_edge(rgb, outline_px, colour, reach=12.0)  # doctest: +SKIP
    >>> snapped.corners_px, snapped.moved  # doctest: +SKIP
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import cv2
import numpy as np
from scipy.optimize import least_squares

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.table import TableSpec
from pix2pockets.vision.table.cloth_region import lab_of, plain_distance
from pix2pockets.vision.table.fit import TableFit
from pix2pockets.vision.table.outline_camera import (
    CUSHION_WIDTH,
    MIN_CAMERA_CLEARANCE,
    camera_through_outline,
    head_rail_convention,
    outline_rectangle,
)
from pix2pockets.vision.table.quad_geometry import line_through, quad_length, quad_mask, quad_of_lines, robust_line

SAMPLES = 96
"""Profiles searched along each side."""
MIN_INLIER_SHARE = 0.35
"""Share of a side's profiles whose edge must lie on the new line."""
MAX_TURN_DEG = 12.0
"""Largest turn of a side [deg] (the table model's cushion lines can be this far off a near corner)."""
INNER_RISE_SHARE = 0.3
"""A rise of the colour distance along a profile counts for the innermost-rise line when it reaches this share of the
profile's steepest rise ..."""
OFF_CLOTH = 1.5
"""... and the colour two samples past it lies this far from the cloth's (colour-distance units) ..."""
SHADOW_HUE_DEG = 30.0
"""... and is not the cloth in shadow: darker than the cloth with its hue within this many degrees, or darker and
greyer (less than half its chroma) ..."""
GREY_CHROMA = 8.0
"""A cloth with less Lab chroma than this is grey: its hue says nothing."""
SHADOW_DARKER = 5.0
"""... where darker means at least this much lower in Lab lightness (a grey or silver rail as light as the cloth is no
shadow)."""
CONTRAST_STEP = 1.5
"""Contrast across a line is read this many pixels either side of it."""
MIN_GAIN = 0.15
"""A new line must separate cloth from rail by this much more than the old (colour-distance units)."""
RAIL_BAND_SHARE = 0.8
"""Share of a band inside a side's edge that must be off the cloth (and not the cloth in other light) for it to be a
rail, whose inner edge is then the cloth's edge."""
RAIL_MIN_PX = 3.0
"""Narrowest band [px] tested as a rail."""
FIRST_REACH = 0.05
"""The first search reaches this share of the table's length in the photo either side of each side ..."""
MIN_REACH_PX = 6.0
"""... and at least this far [px]; a second search reaches :data:`SECOND_REACH_PX`."""
SECOND_REACH_PX = 4.0
MAX_REACH = 0.05
"""The search never reaches further than this share of the image diagonal."""
PULL_BAND_PX = (1, 5)
"""Band just inside a side, from and to this many pixels in, that must be mostly cloth (:func:`pull_in_sides`)."""
MIN_CLOTH_INSIDE = 0.5
"""Share of that band's samples that must be the cloth (its colour or its hue in other light) for the side to stay."""
REMAP_WIDTH = 4096
"""Samples per row of the map the photo is sampled through (OpenCV's maps hold fewer than 2^15 rows and columns)."""
DARK_CLOTH_L = 25.0
"""A cloth darker than this (CIE L*, black and the darkest cloths in dim light) shows its edge faintly: a rail as dark
beside it changes little from the cloth, and the steepest change near a side can be the rail's outer edge, beyond
which the floor is lighter ..."""
DARK_CLOTH_OUTWARD = 0.5
"""... so there a side moves out by at most this share of the cushion's width in the photo (the table model's outline
lies within about half a cushion of the cloth's edge; the rail's outer edge lies two or more widths out)."""
PULL_REACH = 0.12
"""How far in a side off the cloth looks for the cloth [share of the outline's length; at most twice
:data:`MAX_REACH` of the image diagonal]."""
CLOTH_RUN = 3
"""Pixels in a row of the cloth along a profile where the cloth starts."""
CENTRE_SIGMA = 0.1
"""Spread of the principal point about the image centre, as a share of the image size, when a camera is moved onto
snapped corners."""
MIN_FOCAL = 0.5
"""Shortest believable focal length, as a share of the image's long side (a 90-degree field of view). A table seen
from nearly straight above fixes the focal length only weakly; a much shorter one puts the camera too near, and the
parallax between the cushion tops and the cloth then shrinks the playing surface by several percent."""
FOCAL_FLOOR_SIGMA = 0.05
"""Spread of the log focal length below :data:`MIN_FOCAL` allowed when a camera is moved onto the corners."""


MIN_REGION_SHARE = 0.5
"""The surface region must cover this share of a fit's playing surface for the cloth's colour to be read from it."""
COLOUR_PIXELS = 20_000
"""Most cloth pixels the cloth's colour is read from (every k-th of the region)."""


@dataclass(frozen=True, slots=True)
class SnappedOutline:
    """An outline moved onto the cloth's edge.

    Attributes:
        corners_px: (4, 2) the new corners [px], in the order given; side ``k`` runs from corner ``k`` to ``k + 1``.
        moved: (4,) whether each side was moved onto an edge.
        contrast: (4,) the colour contrast across each final side (distance from the cloth's colour outside minus
            inside, median along the side).
    """

    corners_px: np.ndarray
    moved: np.ndarray
    contrast: np.ndarray


def cloth_colour(rgb: np.ndarray, mask: np.ndarray, ball_boxes: np.ndarray | None = None) -> np.ndarray:
    """The cloth's colour, CIE Lab: the median over ``mask`` (H, W) bool shrunk by 2 px, balls left out (at most
    :data:`COLOUR_PIXELS` pixels, evenly spread)."""
    inside = cv2.erode(mask.astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)
    h, w = inside.shape
    for x1, y1, x2, y2 in np.asarray(ball_boxes if ball_boxes is not None else np.zeros((0, 4))).reshape(-1, 4):
        inside[max(int(y1), 0) : min(math.ceil(y2), h), max(int(x1), 0) : min(math.ceil(x2), w)] = False
    if inside.sum() < 20:
        inside = mask.astype(bool)
    pixels = rgb[inside]
    step = max(1, math.ceil(len(pixels) / COLOUR_PIXELS))  # an even spread of the cloth is enough for a median
    return np.median(lab_of(pixels[::step][None]).reshape(-1, 3), axis=0)


def _distance(rgb: np.ndarray, pts: np.ndarray, colour: np.ndarray) -> np.ndarray:
    """Distance from the cloth's colour (in its tolerance steps) of the photo sampled at ``pts`` (..., 2) [pixel
    indices]; points off the photo read as far."""
    h, w = rgb.shape[:2]
    d = plain_distance(_lab_at(rgb, pts).reshape(-1, 3), colour).reshape(pts.shape[:-1])
    off = (pts[..., 0] < 0) | (pts[..., 0] > w - 1) | (pts[..., 1] < 0) | (pts[..., 1] > h - 1)
    return np.where(off, np.nan, d)


def _along(a: np.ndarray, b: np.ndarray, line: np.ndarray) -> np.ndarray:
    """Points (SAMPLES, 2) spread over the middle of side ``a``-``b``, on ``line``."""
    t = np.linspace(0.1, 0.9, SAMPLES)
    base = a[None] + t[:, None] * (b - a)[None]
    return base - (base @ line[:2] + line[2])[:, None] * line[:2][None]


def line_contrast(rgb: np.ndarray, line: np.ndarray, a: np.ndarray, b: np.ndarray, colour: np.ndarray) -> float:
    """How sharply ``line`` (a, b, c), normal pointing out of the cloth, separates cloth from non-cloth between
    ``a`` and ``b``: the median over the side of the colour distance just outside minus just inside."""
    base = _along(a, b, line)
    outside = _distance(rgb, base + CONTRAST_STEP * line[:2], colour)
    inside = _distance(rgb, base - CONTRAST_STEP * line[:2], colour)
    diff = outside - inside
    diff = diff[np.isfinite(diff)]
    return float(np.median(diff)) if len(diff) >= SAMPLES // 4 else -math.inf


def cloth_hued(lab: np.ndarray, colour: np.ndarray) -> np.ndarray:
    """Whether CIE Lab colours (..., 3) are the cloth ``colour`` in other light: its hue within
    :data:`SHADOW_HUE_DEG` and at least half its chroma (all False for a grey cloth, whose hue says nothing)."""
    chroma = math.hypot(float(colour[1]), float(colour[2]))
    if chroma < GREY_CHROMA:
        return np.zeros(lab.shape[:-1], dtype=bool)
    return _same_hue(lab, colour) & (np.hypot(lab[..., 1], lab[..., 2]) >= 0.5 * chroma)


def _same_hue(lab: np.ndarray, colour: np.ndarray) -> np.ndarray:
    """Whether CIE Lab colours (..., 3) lie within :data:`SHADOW_HUE_DEG` of the hue of ``colour``."""
    hue = math.atan2(float(colour[2]), float(colour[1]))
    turn = np.abs((np.arctan2(lab[..., 2], lab[..., 1]) - hue + math.pi) % (2 * math.pi) - math.pi)
    return turn < math.radians(SHADOW_HUE_DEG)


def rail_between(
    rgb: np.ndarray, inner: np.ndarray, outer: np.ndarray, a: np.ndarray, b: np.ndarray, colour: np.ndarray
) -> bool:
    """Whether the band from line ``inner`` out to line ``outer`` (normals out of the cloth) along side ``a``-``b`` is
    a rail, not cloth: ``inner`` lies at least :data:`RAIL_MIN_PX` inside ``outer``, and at least
    :data:`RAIL_BAND_SHARE` of the band's samples (a third and two thirds of the way across, on every profile) are
    off the cloth's colour (:data:`OFF_CLOTH`) and not the cloth in other light (:func:`cloth_hued`: a lit cushion
    top)."""
    base = _along(a, b, inner)
    gap = -(base @ outer[:2] + outer[2])  # how far inside ``outer`` each point of ``inner`` lies [px]
    if np.median(gap) < RAIL_MIN_PX:
        return False
    pts = np.stack([base + f * gap[:, None] * inner[:2][None] for f in (1 / 3, 2 / 3)], axis=1)
    off = _distance(rgb, pts, colour) >= OFF_CLOTH
    off &= ~cloth_hued(_lab_at(rgb, pts), colour)
    return float(np.mean(off)) >= RAIL_BAND_SHARE


def _lab_at(rgb: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """CIE Lab (..., 3) of the photo sampled at ``pts`` (..., 2) [pixel indices]."""
    flat = pts.reshape(-1, 2).astype(np.float32)
    n = len(flat)
    width = min(max(n, 1), REMAP_WIDTH)
    grid = np.zeros((-(-n // width) * width, 2), dtype=np.float32)
    grid[:n] = flat
    grid = grid.reshape(-1, width, 2)
    samples = cv2.remap(rgb, grid[..., 0], grid[..., 1], cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    return lab_of(samples).reshape(-1, 3)[:n].reshape(*pts.shape[:-1], 3)


def _edge_line(points: np.ndarray, line: np.ndarray) -> np.ndarray | None:
    """A robust line through edge points (n, 2), its normal the way of ``line``'s; None unless enough profiles lie on
    it (:data:`MIN_INLIER_SHARE`) and it turns less than :data:`MAX_TURN_DEG` from ``line``."""
    fitted = robust_line(points, 1.5)
    if fitted is None:
        return None
    new, inliers = fitted
    if inliers.sum() < MIN_INLIER_SHARE * SAMPLES or abs(new[:2] @ line[:2]) < math.cos(math.radians(MAX_TURN_DEG)):
        return None
    return new if new[:2] @ line[:2] > 0 else -new


def _innermost_rises(
    rgb: np.ndarray, profiles: np.ndarray, dist: np.ndarray, grad: np.ndarray, colour: np.ndarray
) -> np.ndarray:
    """Each profile's innermost clear rise away from the cloth (see the module docstring): the profiles' points
    (n, m, 2) [pixel indices], their colour distances (n, m) and its rises (n, m - 1); returns the rises' points
    (k, 2) [pixel indices]."""
    lab = _lab_at(rgb, profiles)
    chroma = math.hypot(float(colour[1]), float(colour[2]))
    m = dist.shape[1]
    peak = np.zeros_like(grad, dtype=bool)  # local maxima of the rise
    peak[:, 1:-1] = (grad[:, 1:-1] >= grad[:, :-2]) & (grad[:, 1:-1] >= grad[:, 2:])
    peak[:, 0], peak[:, -1] = grad[:, 0] >= grad[:, 1], grad[:, -1] >= grad[:, -2]
    rises = peak & (grad >= INNER_RISE_SHARE * grad.max(axis=1, keepdims=True))
    past = np.minimum(np.arange(grad.shape[1]) + 2, m - 1)
    rises &= dist[:, past] >= OFF_CLOTH
    beyond = lab[:, past]
    darker = beyond[..., 0] < colour[0] - SHADOW_DARKER
    their_chroma = np.hypot(beyond[..., 1], beyond[..., 2])
    greyer_or_same_hue = (their_chroma < 0.5 * chroma) | _same_hue(beyond, colour)
    shadow = darker if chroma < GREY_CHROMA else darker & greyer_or_same_hue
    rises &= ~shadow
    found = rises.any(axis=1)
    first = np.argmax(rises, axis=1)[found]
    rows = np.flatnonzero(found)
    return profiles[rows, first] + 0.5 * (profiles[rows, first + 1] - profiles[rows, first])


def snap_to_cloth_edge(
    rgb: np.ndarray, corners_px: np.ndarray, colour: np.ndarray, reach: float, sides: np.ndarray | None = None
) -> SnappedOutline:
    """Move each side of an outline onto the cloth's edge.

    Args:
        rgb: the photo, RGB uint8 (H, W, 3).
        corners_px: (4, 2) the outline's corners [px, image coordinates: origin at the top-left pixel's corner], in
            order around it.
        colour: the cloth's colour, CIE Lab (:func:`cloth_colour`).
        reach: how far either side of each side the edge is searched [px] (at most :data:`MAX_REACH` of the
            image diagonal).
        sides: (4,) bool, the sides that may move (default all).

    Returns:
        The outline with each side that found a sharper edge moved onto it.
    """
    quad, lines = _outward_sides(corners_px)
    movable = np.ones(4, dtype=bool) if sides is None else np.asarray(sides, dtype=bool)
    reach = min(reach, MAX_REACH * math.hypot(rgb.shape[1], rgb.shape[0]))
    offsets = np.arange(-math.ceil(reach), math.ceil(reach) + 1, dtype=float)
    moved = np.zeros(4, dtype=bool)
    contrast = np.zeros(4)
    new_lines = lines.copy()
    for k in range(4):
        a, b = quad[k], quad[(k + 1) % 4]
        line = lines[k]
        contrast[k] = line_contrast(rgb, line, a, b, colour)
        if not movable[k]:
            continue
        base = _along(a, b, line)
        pts = base[:, None, :] + offsets[None, :, None] * line[:2][None, None, :]
        dist = _distance(rgb, pts, colour)
        usable = np.isfinite(dist).all(axis=1)
        if usable.sum() < SAMPLES // 4:
            continue
        dist = cv2.GaussianBlur(dist[usable].astype(np.float32), (3, 1), 0)  # smooth along each profile
        grad = np.diff(dist, axis=1)  # the edge: the steepest rise of the distance outward
        j = np.argmax(grad, axis=1)
        rows = np.arange(len(j))
        strong = grad[rows, j] > 0.25
        profiles = pts[usable]
        edge = profiles[rows, j] + 0.5 * (profiles[rows, j + 1] - profiles[rows, j])
        new = _edge_line(edge[strong], line)
        if new is None:
            continue
        inner = _innermost_rises(rgb, profiles[strong], dist[strong], grad[strong], colour)
        inner_line = _edge_line(inner, line) if len(inner) else None
        middle = 0.5 * (a + b)
        if inner_line is not None and (
            abs(middle @ inner_line[:2] + inner_line[2]) < abs(middle @ new[:2] + new[2])
            or rail_between(rgb, inner_line, new, a, b, colour)
        ):
            new = inner_line
        gained = line_contrast(rgb, new, a, b, colour)
        if gained >= contrast[k] + MIN_GAIN:
            new_lines[k], moved[k], contrast[k] = new, True, gained
    corners = quad_of_lines(np.array([new_lines[k] for k in range(4)])) + 0.5
    if not np.all(np.isfinite(corners)):
        return SnappedOutline(np.asarray(corners_px, dtype=float).reshape(4, 2), np.zeros(4, dtype=bool), contrast)
    return SnappedOutline(corners, moved, contrast)


def _outward_sides(corners_px: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """An outline's corners (4, 2) [px] as pixel indices and its sides' lines (4, 3), normals out of the cloth."""
    quad = np.asarray(corners_px, dtype=float).reshape(4, 2) - 0.5
    centre = quad.mean(axis=0)
    lines = np.array([line_through(quad[k], quad[(k + 1) % 4]) for k in range(4)])
    for k in range(4):
        if centre @ lines[k, :2] + lines[k, 2] > 0:
            lines[k] = -lines[k]
    return quad, lines


def _cloth_like(rgb: np.ndarray, pts: np.ndarray, colour: np.ndarray) -> np.ndarray:
    """Whether the photo at ``pts`` (..., 2) [pixel indices] is the cloth: near its colour (:data:`OFF_CLOTH`) or its
    hue in other light (:func:`cloth_hued`); points off the photo are not."""
    near = np.nan_to_num(_distance(rgb, pts, colour), nan=np.inf) < OFF_CLOTH
    return near | cloth_hued(_lab_at(rgb, pts), colour)


def pull_in_sides(
    rgb: np.ndarray, corners_px: np.ndarray, colour: np.ndarray, reach: float, sides: np.ndarray
) -> SnappedOutline:
    """Move in each side of an outline that does not have the cloth just inside it.

    The table model's outline can take in a whole rail (a dark coin-op rail beside a light cloth, seen from low),
    further than :func:`snap_to_cloth_edge` searches. A side whose band just inside (:data:`PULL_BAND_PX`) is mostly
    not the cloth (:data:`MIN_CLOTH_INSIDE`) is moved in to where each profile's cloth starts (:data:`CLOTH_RUN`
    pixels of it in a row, within ``reach``), along a robust line through those points, when the band between the
    two lines is a rail (:func:`rail_between`) and the new line separates cloth from rail at least as sharply.

    Args:
        rgb: the photo, RGB uint8 (H, W, 3).
        corners_px: (4, 2) the outline's corners [px], in order around it.
        colour: the cloth's colour, CIE Lab (:func:`cloth_colour`).
        reach: how far in the cloth is looked for [px].
        sides: (4,) bool, the sides that may move.
    """
    quad, lines = _outward_sides(corners_px)
    inward = np.arange(0, math.ceil(reach) + 1, dtype=float)
    moved = np.zeros(4, dtype=bool)
    contrast = np.array([line_contrast(rgb, lines[k], quad[k], quad[(k + 1) % 4], colour) for k in range(4)])
    for k in np.flatnonzero(sides):
        a, b = quad[k], quad[(k + 1) % 4]
        line = lines[k]
        base = _along(a, b, line)
        cloth = _cloth_like(rgb, base[:, None, :] - inward[None, :, None] * line[:2][None, None, :], colour)
        if cloth[:, PULL_BAND_PX[0] : PULL_BAND_PX[1]].mean() >= MIN_CLOTH_INSIDE:
            continue
        starts = np.lib.stride_tricks.sliding_window_view(cloth, CLOTH_RUN, axis=1).all(axis=2)
        found = starts.any(axis=1)
        if found.sum() < SAMPLES // 4:
            continue
        first = np.argmax(starts, axis=1)[found]
        new = _edge_line(base[found] - (first[:, None] - 0.5) * line[:2][None], line)
        if new is None or not rail_between(rgb, new, line, a, b, colour):
            continue
        gained = line_contrast(rgb, new, a, b, colour)
        if gained >= contrast[k]:
            lines[k], moved[k], contrast[k] = new, True, gained
    corners = quad_of_lines(lines) + 0.5
    if not moved.any() or not np.all(np.isfinite(corners)):
        return SnappedOutline(np.asarray(corners_px, dtype=float).reshape(4, 2), np.zeros(4, dtype=bool), contrast)
    return SnappedOutline(corners, moved, contrast)


def snap_fit(rgb: np.ndarray, fit: TableFit, mask: np.ndarray, ball_boxes: np.ndarray | None = None) -> TableFit:
    """A table fit moved onto the cloth's edge in the photo.

    The fit's cloth outline (the playing surface grown by :data:`CUSHION_WIDTH`, at cushion height) is snapped to
    the cloth's edge (:func:`snap_to_cloth_edge`, twice: a wide search, then a close one); sides cut by the frame
    stay. The camera is then the one that sees the snapped outline exactly
    (:func:`~pix2pockets.vision.table.outline_camera.camera_through_outline`), else the fit's camera moved to see
    it as closely as its pixel stretch allows (least squares on the four corners), else the fit is returned as it
    was.

    Args:
        rgb: the photo, RGB uint8 (H, W, 3).
        fit: the table fit to move (its cloth outline must lie in front of the camera).
        mask: the cloth region (H, W) bool the colour is read from (the table model's surface), within the fit's
            playing surface (:func:`colour_region`).
        ball_boxes: ball boxes (n, 4) [px], left out of the colour.
    """
    spec = fit.spec
    outline = fit.camera.project_table(outline_rectangle(spec, CUSHION_WIDTH), spec.cushion_height)
    if not np.all(np.isfinite(outline)):
        return fit
    w, h = fit.camera.image_size
    inside = (outline[:, 0] >= 0) & (outline[:, 0] <= w) & (outline[:, 1] >= 0) & (outline[:, 1] <= h)
    sides = inside & np.roll(inside, -1)  # side k runs from corner k to k + 1: both ends in the photo
    if not sides.any():
        return fit
    colour = cloth_colour(rgb, colour_region(mask, fit), ball_boxes)
    reach = min(max(MIN_REACH_PX, FIRST_REACH * quad_length(outline)), MAX_REACH * math.hypot(w, h))
    first = snap_to_cloth_edge(rgb, outline, colour, reach, sides)
    second = snap_to_cloth_edge(rgb, first.corners_px, colour, SECOND_REACH_PX, sides)
    pull_reach = min(PULL_REACH * quad_length(outline), 2 * MAX_REACH * math.hypot(w, h))
    pulled = pull_in_sides(rgb, second.corners_px, colour, pull_reach, sides)
    if pulled.moved.any():  # onto the steepest change near where the cloth starts
        again = snap_to_cloth_edge(rgb, pulled.corners_px, colour, SECOND_REACH_PX, pulled.moved)
        second = SnappedOutline(again.corners_px, second.moved | pulled.moved, again.contrast)
    second = SnappedOutline(second.corners_px, first.moved | second.moved, second.contrast)  # moved in either pass
    if colour[0] < DARK_CLOTH_L:  # a dark cloth's edge is faint: a dark rail's outer edge is no cloth edge
        second = _held_out(second, outline, fit)
    moved = int(second.moved.sum())
    floor = MIN_FOCAL * max(w, h)
    if not moved and fit.camera.K[1, 1] >= floor:
        return fit
    corners = second.corners_px if moved else outline
    camera = camera_through_outline(corners, (w, h), spec)
    if camera is None or camera.K[1, 1] < floor:  # none, or one too near: the nearest of a believable focal length
        camera = camera_onto_outline(camera or fit.camera, spec, corners, floor) or camera
    if camera is None:
        return fit
    return replace(fit, camera=head_rail_convention(camera, spec), cloth_edges=moved)


def side_contrasts(
    rgb: np.ndarray, fit: TableFit, mask: np.ndarray, ball_boxes: np.ndarray | None = None
) -> np.ndarray:
    """The colour contrast across each side of a fit's cloth outline in the photo (:func:`line_contrast`, the cloth's
    colour read as :func:`snap_fit` reads it); -inf for a side not wholly in the photo or behind the camera."""
    spec = fit.spec
    outline = fit.camera.project_table(outline_rectangle(spec, CUSHION_WIDTH), spec.cushion_height)
    out = np.full(4, -math.inf)
    if not np.all(np.isfinite(outline)):
        return out
    w, h = fit.camera.image_size
    inside = (outline[:, 0] >= 0) & (outline[:, 0] <= w) & (outline[:, 1] >= 0) & (outline[:, 1] <= h)
    colour = cloth_colour(rgb, colour_region(mask, fit), ball_boxes)
    quad, lines = _outward_sides(outline)
    for k in range(4):
        if inside[k] and inside[(k + 1) % 4]:
            out[k] = line_contrast(rgb, lines[k], quad[k], quad[(k + 1) % 4], colour)
    return out


def _held_out(snapped: SnappedOutline, outline: np.ndarray, fit: TableFit) -> SnappedOutline:
    """``snapped`` with each side that moved out of ``outline`` (4, 2) [px] by more than :data:`DARK_CLOTH_OUTWARD` of
    the cushion's width in the photo (between ``fit``'s playing surface and its cloth outline) put back."""
    spec = fit.spec
    surface = fit.camera.project_table(outline_rectangle(spec, 0.0), 0.0)
    _, old = _outward_sides(outline)
    quad, new = _outward_sides(snapped.corners_px)
    lines = new.copy()
    moved = snapped.moved.copy()
    for k in range(4):
        mid_new = 0.5 * (quad[k] + quad[(k + 1) % 4])
        out = mid_new @ old[k, :2] + old[k, 2]
        mid_surface = 0.5 * (surface[k] + surface[(k + 1) % 4]) - 0.5
        cushion = abs(mid_surface @ old[k, :2] + old[k, 2])
        if out > DARK_CLOTH_OUTWARD * cushion:
            lines[k], moved[k] = old[k], False
    if (lines == new).all():
        return snapped
    return SnappedOutline(quad_of_lines(lines) + 0.5, moved, snapped.contrast)


def colour_region(mask: np.ndarray, fit: TableFit) -> np.ndarray:
    """Where the cloth's colour is read for a fit: the surface region ``mask`` (H, W) bool within the fit's playing
    surface, or the playing surface alone where the region covers less than :data:`MIN_REGION_SHARE` of it (a region
    that found a wall or a shirt, beside a fit from the model's corner peaks)."""
    surface = fit.camera.project_table(outline_rectangle(fit.spec, 0.0), 0.0)
    inside = quad_mask(surface - 0.5, mask.shape)
    if not inside.any():
        return mask
    own = mask & inside
    return own if own.sum() >= MIN_REGION_SHARE * inside.sum() else inside


def camera_onto_outline(
    camera: PinholeCamera, spec: TableSpec, corners: np.ndarray, focal_floor: float = 0.0
) -> PinholeCamera | None:
    """``camera`` moved to see the cloth outline of ``spec`` at ``corners`` (4, 2) [px]: focal length, principal
    point, rotation and translation by least squares, its pixel stretch kept. The principal point is held near
    the image centre by a weak prior (:data:`CENTRE_SIGMA` of the image size), so the four corners are met where a
    camera with square-on optics cannot (lens distortion, a cropped photo); a focal length below ``focal_floor``
    [px] costs (:data:`FOCAL_FLOOR_SIGMA`), which settles the distance of a view from above."""
    world = np.column_stack([outline_rectangle(spec, CUSHION_WIDTH), np.full(4, spec.cushion_height)])
    K = camera.K
    stretch = K[0, 0] / K[1, 1]
    w, h = camera.image_size

    def residuals(p: np.ndarray) -> np.ndarray:
        cam = world @ cv2.Rodrigues(p[1:4])[0].T + p[4:7]
        f = math.exp(p[0])
        u = cam[:, 0] / cam[:, 2] * f * stretch + p[7]
        v = cam[:, 1] / cam[:, 2] * f + p[8]
        below = max(math.log(focal_floor) - p[0], 0.0) / FOCAL_FLOOR_SIGMA if focal_floor > 0 else 0.0
        prior = [(p[7] - K[0, 2]) / (CENTRE_SIGMA * w), (p[8] - K[1, 2]) / (CENTRE_SIGMA * h), below]
        return np.concatenate([u - corners[:, 0], v - corners[:, 1], prior])

    p0 = np.concatenate([[math.log(K[1, 1])], cv2.Rodrigues(camera.R)[0].ravel(), camera.t, K[:2, 2]])
    sol = least_squares(residuals, p0, method="lm", x_scale="jac", max_nfev=400)
    if not np.all(np.isfinite(sol.x)):
        return None
    f = math.exp(sol.x[0])
    new_K = np.array([[f * stretch, 0.0, sol.x[7]], [0.0, f, sol.x[8]], [0.0, 0.0, 1.0]])
    found = PinholeCamera(new_K, cv2.Rodrigues(sol.x[1:4])[0], sol.x[4:7].copy(), camera.image_size)
    misfit = np.abs(residuals(sol.x)[:8]).max()
    if found.position[2] < spec.cushion_height + MIN_CAMERA_CLEARANCE or misfit > 0.05 * quad_length(corners):
        return None
    return found

"""A camera from the cloth outline: the four cushion lines of a table as one quadrilateral.

The cloth-coloured region of a table ends at the back of the cushion tops, where the rails begin: a rectangle
:data:`CUSHION_WIDTH` outside the playing surface on every side, at the cushion-nose height
(:func:`outline_rectangle`). Its four image corners fix a homography, and with square pixels and the principal point
at the image centre, the camera (:func:`pix2pockets.geometry.homography.camera_from_homography`).

Four corners do not say which sides are the long rails. Both assignments are tried and scored by
:func:`rectangle_cost`: a camera must see the sides at right angles and in the table's proportions (the two rotation
constraints of a plane homography must agree for some plausible focal length). Side pockets (a dark notch in the
middle of a long cushion), diamonds, and the balls' apparent size against ``spec.ball_radius`` add evidence. The
inherent 180-degree ambiguity is settled by the head-rail convention of :mod:`pix2pockets.vision.table.fit`.

Without diamonds a photo fixes the table only up to scale. The scale comes from the balls (:func:`size_from_balls`):
57.15 mm balls that look this big stand this far away. The measured table is snapped to the nearest preset
(:data:`~pix2pockets.geometry.table.TABLE_PRESETS`) when close (:func:`spec_of_length`).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.homography import camera_from_homography, fit_homography
from pix2pockets.geometry.table import INCH, TABLE_PRESETS, TableSpec
from pix2pockets.vision.table.errors import TableFitError
from pix2pockets.vision.table.fit import TableFit, diamond_height, validate_corners

CUSHION_WIDTH = 0.05
"""Width of the cloth-covered cushion top, from the nose to the rail [m] (real tables about 4.5-5.5 cm)."""
FOCAL_RANGE = (0.3, 8.0)
"""Focal lengths tried, as multiples of the larger (unstretched) image side."""
COS_SIGMA = 0.03  # expected error of the cosine between the table's axes seen through the corners
RATIO_SIGMA = 0.04  # expected error of the log length ratio of the table's axes
FOCAL_SIGMA = 1.2  # weak log-normal prior on the focal length around the larger image side
MAX_RECTANGLE_COST = 12.0
"""Largest :func:`rectangle_cost` of an accepted outline (a quadrilateral no camera sees as a table: a window, a
picture, a wall)."""
POCKET_WEIGHT = 0.15  # cost per unit of side-pocket darkness difference (Lab lightness) between the two assignments
BALL_SIZE_SIGMA = 0.15  # expected error of the log table scale from the balls
SNAP_TOLERANCE = 0.12
"""A table measured from the balls within this log-ratio of a preset's length is taken as that preset."""
MIN_BALLS_FOR_SIZE = 2


def outline_rectangle(spec: TableSpec, offset: float = CUSHION_WIDTH) -> np.ndarray:
    """Corners of the cloth outline [m], (4, 2), in ``TableSpec.corners`` order: the playing surface grown by
    ``offset`` on every side."""
    L, W, c = spec.length, spec.width, offset
    return np.array([[-c, -c], [L + c, -c], [L + c, W + c], [-c, W + c]])


def _centred(H: np.ndarray, image_size: tuple[float, float]) -> np.ndarray:
    w, h = image_size
    T = np.array([[1.0, 0.0, -w / 2], [0.0, 1.0, -h / 2], [0.0, 0.0, 1.0]])
    return T @ H


def rectangle_cost(H: np.ndarray, image_size: tuple[float, float], focal_prior: float) -> tuple[float, float]:
    """How well a camera can see the plane rectangle behind homography ``H`` (plane metres -> pixels) as drawn.

    For focal lengths over :data:`FOCAL_RANGE`, the back-projected plane axes ``K^-1 h1`` and ``K^-1 h2`` must be
    orthogonal and of equal length (a rotation). Returns ``(cost, focal [px])`` at the best focal length; the cost
    is a sum of squared normalised errors, about 0-3 for a rectangle of the right proportions.
    """
    A = _centred(H, image_size)
    f = focal_prior * np.exp(np.linspace(math.log(FOCAL_RANGE[0]), math.log(FOCAL_RANGE[1]), 121))
    h1 = A[:, 0][None, :] * np.column_stack([1 / f, 1 / f, np.ones_like(f)])
    h2 = A[:, 1][None, :] * np.column_stack([1 / f, 1 / f, np.ones_like(f)])
    n1, n2 = np.linalg.norm(h1, axis=1), np.linalg.norm(h2, axis=1)
    cos = np.sum(h1 * h2, axis=1) / (n1 * n2)
    ratio = np.log(n1 / n2)
    cost = (cos / COS_SIGMA) ** 2 + (ratio / RATIO_SIGMA) ** 2 + (np.log(f / focal_prior) / FOCAL_SIGMA) ** 2
    k = int(np.argmin(cost))
    return float(cost[k]), float(f[k])


def _stretch(camera: PinholeCamera, aspect: float, image_size: tuple[int, int]) -> PinholeCamera:
    K = np.diag([aspect, 1.0, 1.0]) @ camera.K
    return PinholeCamera(K, camera.R, camera.t, (int(image_size[0]), int(image_size[1])))


def _half_turn(camera: PinholeCamera, spec: TableSpec) -> PinholeCamera:
    """The same camera with the table frame turned by 180 degrees: ``(x, y) -> (L - x, W - y)``."""
    D = np.diag([-1.0, -1.0, 1.0])
    c = np.array([spec.length, spec.width, 0.0])
    return PinholeCamera(camera.K, camera.R @ D, camera.R @ c + camera.t, camera.image_size)


def head_rail_convention(camera: PinholeCamera, spec: TableSpec) -> PinholeCamera:
    """The camera relabelled so the head rail is the short rail further left and lower in the image
    (the convention of :mod:`pix2pockets.vision.table.fit`)."""
    head = camera.project_table(np.array([0.0, spec.width / 2]), spec.cushion_height)
    foot = camera.project_table(np.array([spec.length, spec.width / 2]), spec.cushion_height)
    return _half_turn(camera, spec) if (head[0] - foot[0]) - (head[1] - foot[1]) > 0 else camera


def camera_from_outline(
    corners_px: np.ndarray,
    image_size: tuple[int, int],
    spec: TableSpec,
    pixel_aspect: float = 1.0,
    offset: float = CUSHION_WIDTH,
) -> tuple[PinholeCamera, float, float]:
    """The camera that sees the cloth outline of ``spec`` at ``corners_px`` (4, 2) [px], corner ``k`` being
    ``outline_rectangle(spec)[k]``. Returns ``(camera, rectangle cost, corner rms [px])``.

    Raises:
        TableFitError: the corners give no camera above the table.
    """
    aspect = float(pixel_aspect)
    corners = np.asarray(corners_px, dtype=float) / np.array([aspect, 1.0])
    size = (image_size[0] / aspect, image_size[1])
    world = outline_rectangle(spec, offset)
    try:
        H = fit_homography(world, corners)
    except ValueError as err:
        raise TableFitError(f"no table found: {err}") from None
    cost, focal = rectangle_cost(H, size, max(size))
    z = spec.cushion_height
    world3 = np.column_stack([world, np.full(4, z)])
    camera = camera_from_homography(H, size, z=z, world_points=world3, image_points=corners, focal_prior_px=focal)
    proj = camera.project(world3)
    rms = float(np.sqrt(np.mean(np.sum((proj - corners) ** 2, axis=1)) * 1.0))
    camera = _stretch(camera, aspect, image_size)
    return camera, cost, rms if np.isfinite(rms) else math.inf


# ----------------------------------------------------------------------------- table size
def _ball_sizes(boxes: np.ndarray, aspect: float) -> np.ndarray:
    """Apparent ball diameters [px of image height] from boxes (n, 4): the larger box side once unstretched (a
    ball cut by another or by the frame keeps its other side)."""
    w = (boxes[:, 2] - boxes[:, 0]) / aspect
    h = boxes[:, 3] - boxes[:, 1]
    return np.maximum(w, h)


def size_from_balls(camera: PinholeCamera, boxes: np.ndarray, spec: TableSpec, aspect: float = 1.0) -> float | None:
    """The factor by which the real table is larger than ``spec`` as fitted by ``camera``, read from the balls'
    apparent size (``spec.ball_radius`` balls), or None with fewer than :data:`MIN_BALLS_FOR_SIZE` balls on it.

    A world ``k`` times larger seen in the same photo puts the camera ``k`` times further away, so balls of the real
    radius look ``k`` times smaller than those the fitted camera predicts.
    """
    from pix2pockets.vision.locate.balls import locate_sphere, sphere_boxes  # locate imports this package

    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    if len(boxes) < MIN_BALLS_FOR_SIZE:
        return None
    observed = _ball_sizes(boxes, aspect)
    k = 1.0
    for _ in range(3):
        r = spec.ball_radius / k
        xy = locate_sphere(camera, boxes, r)
        ok = np.all(np.isfinite(xy), axis=1) & spec.contains(np.nan_to_num(xy, nan=-1e9), margin=-0.05)
        if ok.sum() < MIN_BALLS_FOR_SIZE:
            return None
        predicted = _ball_sizes(sphere_boxes(camera, np.column_stack([xy[ok], np.full(ok.sum(), r)]), r), aspect)
        ratio = predicted / np.maximum(observed[ok], 1e-6)
        k = k * float(np.median(ratio))
        if not 0.2 < k < 5.0:
            return None
    return k


def spec_of_length(length: float, base: TableSpec | None = None) -> TableSpec:
    """The table of playing-surface ``length`` [m]: the nearest preset within :data:`SNAP_TOLERANCE`, else ``base``
    (default 9-foot) resized to that length with the usual 2:1 proportions."""
    nearest = min(TABLE_PRESETS.values(), key=lambda p: abs(math.log(p.length / length)))
    if abs(math.log(nearest.length / length)) <= SNAP_TOLERANCE:
        return nearest
    base = base or TableSpec()
    feet = length / (12 * INCH) + 0.5  # named by the usual "nominal feet" (playing length + about half a foot)
    return replace(base, name=f"{feet:.1f}ft (measured)", length=length, width=length / 2)


# ----------------------------------------------------------------------------- hypotheses
def _diamond_matches(camera: PinholeCamera, diamonds: np.ndarray, spec: TableSpec, tol_px: float) -> int:
    if not len(diamonds):
        return 0
    proj = camera.project_table(spec.diamonds, diamond_height(spec))
    d = np.linalg.norm(diamonds[:, None, :] - proj[None], axis=-1)
    return int(np.sum(np.nanmin(np.where(np.isfinite(d), d, np.inf), axis=1) < tol_px))


def fit_outline(
    corners_px: np.ndarray,
    image_size: tuple[int, int],
    spec: TableSpec | None = None,
    ball_boxes: np.ndarray | None = None,
    diamonds: np.ndarray | None = None,
    pocket_darkness: np.ndarray | None = None,
    pixel_aspect: float = 1.0,
    offset: float = CUSHION_WIDTH,
) -> TableFit:
    """Fit the table from the four corners of its cloth outline.

    Args:
        corners_px: the outline's corners [px] (4, 2), in order around it (as
            :attr:`~pix2pockets.vision.table.cloth.ClothOutline.corners_px`); which of them is which table corner is
            found here.
        image_size: (width, height) [px].
        spec: the table; ``None`` measures its size from the balls (9-foot proportions and pockets, snapped to the
            nearest preset when close; 9-foot without balls).
        ball_boxes: ball boxes (n, 4) [px]: the table's size and, with ``spec``, evidence for the long rails.
        diamonds: diamond centres (m, 2) [px] (evidence for the long rails).
        pocket_darkness: per side, how dark its middle is (side pockets mark the long rails).
        pixel_aspect: width over height of one pixel (photos squashed by an export).
        offset: cushion width: how far the outline lies outside the playing surface [m].

    Returns:
        A :class:`TableFit` with ``source="cloth"``; ``rms_px`` is the corners' reprojection error, no diamonds.

    Raises:
        TableFitError: the corners give no plausible camera and table.
    """
    corners = np.asarray(corners_px, dtype=float).reshape(4, 2)
    if not np.all(np.isfinite(corners)):
        raise TableFitError("no table found: the cloth outline has no four corners")
    # the table frame is counter-clockwise seen from above, which a camera above shows clockwise (v down)
    area = 0.5 * float(np.dot(corners[:, 0], np.roll(corners[:, 1], -1)) - np.dot(corners[:, 1], np.roll(corners[:, 0], -1)))
    if area > 0:
        corners = corners[::-1].copy()
    boxes = np.zeros((0, 4)) if ball_boxes is None else np.asarray(ball_boxes, dtype=float).reshape(-1, 4)
    dots = np.zeros((0, 2)) if diamonds is None else np.asarray(diamonds, dtype=float).reshape(-1, 2)
    base = spec or TableSpec()
    tol = 0.01 * math.hypot(*image_size)
    hypotheses = []
    first_error: TableFitError | None = None
    for shift in (0, 1):
        quad = np.roll(corners, -shift, axis=0)  # quad[k] is the table's corner k
        try:
            camera, cost, rms = camera_from_outline(quad, image_size, base, pixel_aspect, offset)
        except TableFitError as err:
            first_error = first_error or err
            continue
        evidence = cost
        if pocket_darkness is not None:
            dark = np.roll(np.asarray(pocket_darkness, dtype=float), -shift)
            evidence -= POCKET_WEIGHT * float(np.clip(dark[0] + dark[2] - dark[1] - dark[3], -40, 40))
        if spec is not None and len(boxes):
            k = size_from_balls(camera, boxes, base, pixel_aspect)
            if k is not None:
                evidence += (math.log(k) / BALL_SIZE_SIGMA) ** 2
        evidence -= 2.0 * _diamond_matches(camera, dots, base, tol)
        hypotheses.append((evidence, cost, rms, quad, camera))
    if not hypotheses:
        raise first_error or TableFitError("no table found")
    evidence, cost, rms, quad, camera = min(hypotheses, key=lambda h: h[0])
    if cost > MAX_RECTANGLE_COST:
        raise TableFitError(
            f"no table found: the cloth outline is not a table seen by a camera (rectangle error {cost:.0f}); "
            "show the whole table with its four cushions"
        )
    size_source = "given"
    final = base
    if spec is None:
        size_source = "default"
        k = size_from_balls(camera, boxes, base, pixel_aspect) if len(boxes) else None
        if k is not None:
            outline_length = k * (base.length + 2 * offset)
            final = spec_of_length(outline_length - 2 * offset, base)
            size_source = "balls"
            if final is not base:
                camera, cost, rms = camera_from_outline(quad, image_size, final, pixel_aspect, offset)
    _check_camera(camera, final, image_size)
    camera = head_rail_convention(camera, final)
    h = diamond_height(final)
    rect = camera.project_table(
        np.array([[0.0, 0.0], [final.length, 0.0], [final.length, final.width], [0.0, final.width]]), h
    )
    return TableFit(
        final,
        camera,
        np.full(len(dots), -1),
        rect * np.nan,
        rms,
        0,
        h,
        source="cloth",
        size_source=size_source,
    )


def _check_camera(camera: PinholeCamera, spec: TableSpec, image_size: tuple[int, int]) -> None:
    """Raise :class:`TableFitError` for a camera below the rails, a table behind it or an implausible focal length."""
    if not np.all(np.isfinite(camera.position)) or camera.position[2] < spec.cushion_height + 0.2:
        raise TableFitError("no table found: the fitted camera is not above the table")
    validate_corners(camera.project_table(spec.corners, 0.0), image_size)
    f = camera.K[1, 1]
    if not FOCAL_RANGE[0] * 0.9 * max(image_size) < f < FOCAL_RANGE[1] * 1.1 * max(image_size):
        raise TableFitError(f"no table found: implausible camera (focal length {f:.0f} px)")


def outline_residual_px(fit: TableFit, corners_px: np.ndarray, offset: float = CUSHION_WIDTH) -> float:
    """Largest distance [px] from the fitted outline's corners to ``corners_px`` (4, 2), over the orders that
    describe the same quadrilateral."""
    proj = fit.camera.project_table(outline_rectangle(fit.spec, offset), fit.spec.cushion_height)
    corners = np.asarray(corners_px, dtype=float)
    best = math.inf
    for c in (corners, corners[::-1]):
        for k in range(4):
            best = min(best, float(np.max(np.linalg.norm(np.roll(c, k, axis=0) - proj, axis=1))))
    return best


__all__ = [
    "CUSHION_WIDTH",
    "camera_from_outline",
    "fit_outline",
    "head_rail_convention",
    "outline_rectangle",
    "outline_residual_px",
    "rectangle_cost",
    "size_from_balls",
    "spec_of_length",
]

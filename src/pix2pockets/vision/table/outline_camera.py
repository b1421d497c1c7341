"""Cameras from a table's outline: four corners, or three sides and a focal length.

The cloth-coloured region of a table ends at the back of the cushion tops, where the rails begin: a rectangle
:data:`CUSHION_WIDTH` outside the playing surface on every side, at the cushion-nose height
(:func:`outline_rectangle`). Its four image corners fix a plane homography and, with square pixels and the principal
point at the image centre, a camera (:func:`camera_from_outline`); :func:`rectangle_cost` says how well any camera
can see the corners as a rectangle of the table's proportions. Three sides and a focal length fix a camera too
(:func:`complete_three_lines`).
"""

from __future__ import annotations

import math

import cv2
import numpy as np
from scipy.optimize import least_squares

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.homography import fit_homography, pose_from_homography
from pix2pockets.geometry.table import TableSpec
from pix2pockets.vision.table.errors import TableFitError

CUSHION_WIDTH = 0.05
"""Width of the cloth-covered cushion top, from the nose to the rail [m] (real tables about 4.5-5.5 cm)."""
MIN_CAMERA_CLEARANCE = 0.2
"""Least height of a camera fitted to exact corners or diamonds above the cushion tops [m]; a camera lower than this
over points read that surely is a wrong solution (the outline fit of a whole cloth allows less:
:data:`~pix2pockets.vision.table.outline_fit.MIN_CAMERA_HEIGHT`)."""
FOCAL_RANGE = (0.3, 8.0)
"""Focal lengths tried, as multiples of the larger (unstretched) image side."""
COS_SIGMA = 0.03  # expected error of the cosine between the table's axes seen through the corners
RATIO_SIGMA = 0.04  # expected error of the log length ratio of the table's axes
FOCAL_SIGMA = 0.7  # log-normal prior on the focal length around the larger image side
OFF_FRAME_HALF = 0.02
"""Distance of an outline corner outside the photo, as a share of the image diagonal, that halves its weight in a
fit (:func:`off_frame_weights`)."""
MAX_CONDITION = 1e4  # condition number above which an outline does not fix both focal lengths


def outline_rectangle(spec: TableSpec, offset: float = CUSHION_WIDTH) -> np.ndarray:
    """Corners of the cloth outline [m], (4, 2), in ``TableSpec.corners`` order: the playing surface grown by
    ``offset`` on every side."""
    L, W, c = spec.length, spec.width, offset
    return np.array([[-c, -c], [L + c, -c], [L + c, W + c], [-c, W + c]])


def rectangle_cost(H: np.ndarray, image_size: tuple[float, float], focal_prior: float) -> tuple[float, float]:
    """How well a camera can see the plane rectangle behind homography ``H`` (plane metres -> pixels) as drawn.

    For focal lengths over :data:`FOCAL_RANGE`, the back-projected plane axes ``K^-1 h1`` and ``K^-1 h2`` must be
    orthogonal and of equal length (a rotation). Returns ``(cost, focal [px])`` at the best focal length; the cost
    is a sum of squared normalised errors, about 0-3 for a rectangle of the right proportions.
    """
    w, h = image_size
    A = np.array([[1.0, 0.0, -w / 2], [0.0, 1.0, -h / 2], [0.0, 0.0, 1.0]]) @ H
    f = focal_prior * np.exp(np.linspace(math.log(FOCAL_RANGE[0]), math.log(FOCAL_RANGE[1]), 121))
    scale = np.column_stack([1 / f, 1 / f, np.ones_like(f)])
    h1, h2 = A[:, 0][None, :] * scale, A[:, 1][None, :] * scale
    n1, n2 = np.linalg.norm(h1, axis=1), np.linalg.norm(h2, axis=1)
    cos = np.sum(h1 * h2, axis=1) / (n1 * n2)
    ratio = np.log(n1 / n2)
    cost = (cos / COS_SIGMA) ** 2 + (ratio / RATIO_SIGMA) ** 2 + (np.log(f / focal_prior) / FOCAL_SIGMA) ** 2
    k = int(np.argmin(cost))
    return float(cost[k]), float(f[k])


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product of two 3-vectors (``np.cross`` is slow for single vectors)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def intrinsics(f: float, image_size: tuple[float, float]) -> np.ndarray:
    return np.array([[f, 0.0, image_size[0] / 2], [0.0, f, image_size[1] / 2], [0.0, 0.0, 1.0]])


def stretched(camera: PinholeCamera, aspect: float, image_size: tuple[int, int]) -> PinholeCamera:
    """A camera fitted on a photo with its x axis divided by ``aspect``, for the photo itself (``image_size``)."""
    K = np.diag([aspect, 1.0, 1.0]) @ camera.K
    return PinholeCamera(K, camera.R, camera.t, (int(image_size[0]), int(image_size[1])))


def head_rail_convention(camera: PinholeCamera, spec: TableSpec) -> PinholeCamera:
    """The camera relabelled so the head rail is the short rail further left and lower in the image (the convention
    of :mod:`pix2pockets.vision.table.fit`): the table frame turned by 180 degrees where needed."""
    head = camera.project_table(np.array([0.0, spec.width / 2]), spec.cushion_height)
    foot = camera.project_table(np.array([spec.length, spec.width / 2]), spec.cushion_height)
    if (head[0] - foot[0]) - (head[1] - foot[1]) <= 0:
        return camera
    D = np.diag([-1.0, -1.0, 1.0])
    c = np.array([spec.length, spec.width, 0.0])
    return PinholeCamera(camera.K, camera.R @ D, camera.R @ c + camera.t, camera.image_size)


def quick_camera(
    quad: np.ndarray,
    size: tuple[float, float],
    spec: TableSpec,
    offset: float,
    focal: float | None = None,
    plane_z: float | None = None,
) -> tuple[PinholeCamera, float] | None:
    """Camera (square pixels) seeing the outline of ``spec`` at ``quad`` (4, 2) [px, table corner order] and its
    rectangle cost, from the homography alone; None for a degenerate quadrilateral. The outline lies at
    ``plane_z`` [m] above the cloth (default: the cushion-nose height)."""
    world = outline_rectangle(spec, offset)
    try:
        H = fit_homography(world, quad)
    except ValueError:
        return None
    cost, f = rectangle_cost(H, size, max(size))
    if focal is not None:
        f = focal
    z = spec.cushion_height if plane_z is None else plane_z
    R, t = pose_from_homography(H, intrinsics(f, size), z, spec.size / 2)
    return PinholeCamera(intrinsics(f, size), R, t, (round(size[0]), round(size[1]))), cost


def refined(
    camera: PinholeCamera,
    world3: np.ndarray,
    image: np.ndarray,
    focal_prior: float,
    focal_sigma: float = FOCAL_SIGMA,
    weights: np.ndarray | None = None,
) -> PinholeCamera:
    """``camera`` refined by least squares on the points ``world3`` (n, 3) [m] seen at ``image`` (n, 2) [px]: focal
    length, rotation and translation, with a log-normal prior of spread ``focal_sigma`` on the focal length (weak by
    default; a small spread holds it); ``weights`` (n,) weigh the points' errors (default 1)."""
    w, h = camera.image_size
    centre = np.array([camera.K[0, 2], camera.K[1, 2]])
    weight = np.ones((len(image), 1)) if weights is None else np.asarray(weights, dtype=float).reshape(-1, 1)

    def residuals(p: np.ndarray) -> np.ndarray:
        R = cv2.Rodrigues(p[1:4])[0]
        cam = world3 @ R.T + p[4:7]
        proj = cam[:, :2] / cam[:, 2:3] * math.exp(p[0]) + centre
        return np.concatenate([((proj - image) * weight).ravel(), [(p[0] - math.log(focal_prior)) / focal_sigma]])

    p0 = np.concatenate([[math.log(camera.K[1, 1])], cv2.Rodrigues(camera.R)[0].ravel(), camera.t])
    try:
        sol = least_squares(residuals, p0, method="lm", x_scale="jac", max_nfev=200)
    except ValueError:
        return camera
    if not np.all(np.isfinite(sol.x)) or sol.cost > 0.5 * float(np.sum(residuals(p0) ** 2)) + 1e-9:
        return camera
    f = math.exp(sol.x[0])
    return PinholeCamera(intrinsics(f, (w, h)), cv2.Rodrigues(sol.x[1:4])[0], sol.x[4:7].copy(), (w, h))


def camera_through_outline(
    corners_px: np.ndarray,
    image_size: tuple[int, int],
    spec: TableSpec,
    offset: float = CUSHION_WIDTH,
    plane_z: float | None = None,
    max_stretch: float = 1.6,
) -> PinholeCamera | None:
    """The camera that sees the outline of ``spec`` exactly at ``corners_px`` (4, 2) [px, table corner order].

    Four corners fix the plane homography; with the principal point at the image centre the two conditions on a
    rotation (the back-projected plane axes orthogonal and of equal length) fix the focal lengths along x and y, so
    the pixels may be stretched (photos squashed by an export). ``None`` when they do not fix them (a view square-on
    or without roll about the optical axis) or have no real solution, the stretch exceeds ``max_stretch`` or the
    camera is not above the table."""
    w, h = image_size
    world = outline_rectangle(spec, offset)
    try:
        H = fit_homography(world, np.asarray(corners_px, dtype=float))
    except ValueError:
        return None
    Hc = np.array([[1.0, 0.0, -w / 2], [0.0, 1.0, -h / 2], [0.0, 0.0, 1.0]]) @ H
    h1, h2 = Hc[:, 0], Hc[:, 1]
    # a = 1 / fx^2, b = 1 / fy^2: a h1x h2x + b h1y h2y + h1z h2z = 0 and |h1|^2 = |h2|^2 after K^-1
    A = np.array([[h1[0] * h2[0], h1[1] * h2[1]], [h1[0] ** 2 - h2[0] ** 2, h1[1] ** 2 - h2[1] ** 2]])
    rhs = -np.array([h1[2] * h2[2], h1[2] ** 2 - h2[2] ** 2])
    scale = np.linalg.norm(np.column_stack([A, rhs]), axis=1, keepdims=True)
    if not np.all(scale > 0) or np.linalg.cond(A / scale) > MAX_CONDITION:
        return None  # e.g. no roll about the optical axis: a stretch along x is then a turn of the table
    a, b = np.linalg.solve(A, rhs)
    if not (a > 0 and b > 0):
        return None
    fx, fy = 1.0 / math.sqrt(a), 1.0 / math.sqrt(b)
    side = max(w, h)
    if not (1.0 / max_stretch <= fx / fy <= max_stretch and FOCAL_RANGE[0] * side <= fy <= FOCAL_RANGE[1] * side):
        return None
    K = np.array([[fx, 0.0, w / 2], [0.0, fy, h / 2], [0.0, 0.0, 1.0]])
    z = spec.cushion_height if plane_z is None else plane_z
    R, t = pose_from_homography(H, K, z, spec.size / 2)
    camera = PinholeCamera(K, R, t, (int(w), int(h)))
    if camera.position[2] < spec.cushion_height + MIN_CAMERA_CLEARANCE:
        return None
    return camera


def camera_from_outline(
    corners_px: np.ndarray,
    image_size: tuple[int, int],
    spec: TableSpec,
    pixel_aspect: float = 1.0,
    offset: float = CUSHION_WIDTH,
    focal_px: float | None = None,
    plane_z: float | None = None,
    focal_sigma: float = FOCAL_SIGMA,
) -> tuple[PinholeCamera, float, float]:
    """The camera that sees the cloth outline of ``spec`` at ``corners_px`` (4, 2) [px], corner ``k`` being
    ``outline_rectangle(spec)[k]``, refined by least squares on the corners. Returns ``(camera, rectangle cost,
    corner rms [px])``.

    Args:
        focal_px: focal length [px of image height] to start from and keep close to (default: the one the corners
            imply, :func:`rectangle_cost`).
        plane_z: height of the outline above the cloth [m] (default: the cushion-nose height).
        focal_sigma: spread of the log-normal prior on the focal length about ``focal_px`` (small: hold it).

    Raises:
        TableFitError: the corners give no camera.
    """
    aspect = float(pixel_aspect)
    corners = np.asarray(corners_px, dtype=float) / np.array([aspect, 1.0])
    size = (image_size[0] / aspect, image_size[1])
    quick = quick_camera(corners, size, spec, offset, focal_px, plane_z)
    if quick is None:
        raise TableFitError("no table found: the cloth outline's corners are degenerate")
    camera, cost = quick
    z = spec.cushion_height if plane_z is None else plane_z
    world3 = np.column_stack([outline_rectangle(spec, offset), np.full(4, z)])
    # corners read from the photo's cushion lines; with a focal length given (three cushions), the fourth side's
    # corners come from the completion, consistent with the rest, and keep their weight
    weights = None if focal_px is not None else off_frame_weights(corners, size)
    camera = refined(camera, world3, corners, focal_px or camera.K[1, 1], focal_sigma, weights)
    err = np.linalg.norm(camera.project(world3) - corners, axis=1)
    rms = float(np.sqrt(np.mean(err**2))) if np.all(np.isfinite(err)) else math.inf
    return stretched(camera, aspect, image_size), cost, rms


def off_frame_weights(corners: np.ndarray, image_size: tuple[float, float]) -> np.ndarray:
    """Weights (4,) of an outline's corners [px] (4, 2) in a fit: 1 inside the photo, falling with the distance
    outside it (half at :data:`OFF_FRAME_HALF` of the image diagonal). A corner outside is where two cushion lines
    read inside meet: where they meet at a glancing angle, a fraction of a degree moves it far."""
    w, h = image_size
    dx = np.maximum(np.maximum(-corners[:, 0], corners[:, 0] - w), 0.0)
    dy = np.maximum(np.maximum(-corners[:, 1], corners[:, 1] - h), 0.0)
    out = np.hypot(dx, dy) / (OFF_FRAME_HALF * math.hypot(w, h))
    return 1.0 / (1.0 + out)


def complete_three_lines(
    lines: np.ndarray,
    focal: float,
    image_size: tuple[float, float],
    mid_length: float,
    side_length: float,
    inner: np.ndarray,
) -> np.ndarray | None:
    """The quadrilateral of a rectangle seen with three of its sides, for a camera of focal length ``focal`` [px]
    (square pixels, principal point at the image centre).

    Args:
        lines: the lines ``a u + b v + c = 0`` of three consecutive sides (3, 3): before, middle, after.
        focal: focal length [px].
        image_size: (width, height) [px].
        mid_length: the rectangle's side along the middle line [m].
        side_length: its side along the other two [m].
        inner: a point inside the rectangle in the image [px] (on which side of the middle line the rectangle lies).

    Returns:
        The corners (4, 2) [px]: middle-line start, middle-line end, then the two corners on the unseen side; None
        when the lines give no rectangle in front of the camera.
    """
    before, mid, after = (np.asarray(x, dtype=float) for x in lines)
    K = intrinsics(focal, image_size)
    Kinv = np.array([[1 / focal, 0.0, -K[0, 2] / focal], [0.0, 1 / focal, -K[1, 2] / focal], [0.0, 0.0, 1.0]])
    p1, p2, v = cross3(before, mid), cross3(mid, after), cross3(before, after)
    if abs(p1[2]) < 1e-12 or abs(p2[2]) < 1e-12:
        return None
    r1, r2 = Kinv @ (p1 / p1[2]), Kinv @ (p2 / p2[2])
    perp = Kinv @ v
    along = cross3(K.T @ mid, perp)
    if np.linalg.norm(perp) < 1e-12 or np.linalg.norm(along) < 1e-12:
        return None
    perp, along = perp / np.linalg.norm(perp), along / np.linalg.norm(along)
    # X2 - X1 = mid_length * along (either sign), X1 = l1 r1, X2 = l2 r2
    A = np.column_stack([r1, -r2])
    best = None
    for sign in (1.0, -1.0):
        lam, *_ = np.linalg.lstsq(A, -sign * mid_length * along, rcond=None)
        if lam[0] > 0 and lam[1] > 0:
            best = (lam, sign)
    if best is None:
        return None
    (l1, l2), _ = best
    X1, X2 = l1 * r1, l2 * r2
    inner_h = np.array([inner[0], inner[1], 1.0])
    for sign in (1.0, -1.0):
        X4 = X1 + sign * side_length * perp
        X3 = X2 + sign * side_length * perp
        if X3[2] <= 1e-6 or X4[2] <= 1e-6:
            continue
        probe = K @ (X1 + 0.01 * side_length * sign * perp)
        if probe[2] <= 0 or np.sign(mid @ (probe / probe[2])) != np.sign(mid @ inner_h):
            continue
        p3, p4 = K @ X3, K @ X4
        return np.array([p1[:2] / p1[2], p2[:2] / p2[2], p3[:2] / p3[2], p4[:2] / p4[2]])
    return None

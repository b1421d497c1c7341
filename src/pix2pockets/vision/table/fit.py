"""Table fitting from diamond detections: rails, point ordering, homography and camera.

The method follows the paper (section 5.1) and makes it robust to missing diamonds:

1. **Rail lines and labelling** (:mod:`pix2pockets.vision.table.rails`): RANSAC lines through the diamond
   centres, and which of the table's 18 diamonds each centre is.
2. **Corners.** Where two adjacent rails each have at least two diamonds, their lines intersect in a corner of
   the diamond rectangle, ``(-s, -s)`` ... ``(L + s, W + s)`` for the diamond setback ``s``, on the rail
   cap at :func:`diamond_height` (not at the cushion nose corners). The corners are validated (convex,
   in a plausible region around the image, consistent with the fitted table) and added to the points.
3. **Homography and camera.** A robust homography (``cv2.USAC_MAGSAC``) from all matched points, then
   the camera (focal length, pose) from it, refined on the points at their true height
   (:func:`pix2pockets.geometry.homography.camera_from_homography`).

Convention for the inherent 180-degree ambiguity (the diamond pattern is symmetric): the head rail
(``x = 0``) is the short rail whose midpoint lies further left and lower in the image, i.e. the one that
minimises ``(u_head - u_foot) - (v_head - v_foot)``. For a top view with the long axis horizontal this
puts the head on the left; for a view along the table it puts the head rail nearest the camera.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import cv2
import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.homography import apply_homography, camera_from_homography, fit_homography
from pix2pockets.geometry.table import TableSpec
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.table.errors import TableFitError, counted, in_photo_px
from pix2pockets.vision.table.outline_camera import MIN_CAMERA_CLEARANCE
from pix2pockets.vision.table.pixel_aspect import EXPORT_ASPECTS, pixel_aspect_of_balls, snapped_aspect
from pix2pockets.vision.table.rails import (
    MIN_DIAMONDS,
    RAIL_DIAMONDS,
    fit_rail_lines,
    label_candidates,
    tls_line,
)

MIN_MATCHED_DIAMONDS = 6
"""Diamonds a fitted camera must explain. Four diamonds on two rails fix a camera and a fifth leaves one point
to check it, so such fits are hardly checked: on real phone photos three of the four fits from four or five
diamonds drew the table in the wrong place, all thirteen from six or more in the right one
(``docs/benchmarks-vision.md``). Fewer diamonds still give rail-line hypotheses; they are refused at the end."""
MIN_DIAMONDS_FOR_ASPECT = 10
"""Matched diamonds a fit with a guessed export stretch (one the balls do not show) needs; else ``MIN_DIAMONDS``."""
MAX_DIAMONDS = 40  # more candidates than this are cut by confidence (false positives)
MIN_SCATTER_DOF = 3  # rail-line residual degrees of freedom needed to judge the reprojection error
REPROJECTION_FACTOR = 4.0  # reprojection rms may be this many times the diamonds' 2-D scatter ...
REPROJECTION_FLOOR_PX = 2.5  # ... or this many pixels [px]
REPROJECTION_MAX_PX = 4.0  # diamonds' reprojection rms never above this [px] ...
REPROJECTION_MAX_DIAG = 0.003  # ... or this fraction of the image diagonal, whichever is larger


DIAMOND_RISE = 0.0075
"""Height of the rail cap (where the diamonds sit) above the cushion nose [m]. Rail caps stand a few
millimetres above the nose; 7.5 mm is the middle of the synthetic renderer's 3-12 mm range. A wrong
height shifts located balls by about the error x tan(camera tilt), so it matters for low views."""


def diamond_height(spec: TableSpec) -> float:
    """Height of the diamond centres above the cloth [m]: ``cushion_height + DIAMOND_RISE``."""
    return spec.cushion_height + DIAMOND_RISE


@dataclass(frozen=True, slots=True, eq=False)
class TableFit:
    """A fitted table.

    Attributes:
        spec: the table.
        camera: the recovered camera (table frame -> pixels).
        diamond_index: for each input diamond, the diamond index it was matched to (0-17), or -1 (outlier).
        diamond_corners_px: image positions of the diamond-rectangle corners (rail-cap height), (4, 2);
            NaN for corners whose two rails lacked the diamonds to intersect.
        rms_px: root-mean-square reprojection error of the matched points [px].
        n_matched: number of matched diamonds.
        diamond_z: height of the diamond plane above the cloth used for ``camera`` [m].
        source: the cues the camera was fitted to: ``"diamonds"``, ``"cloth"`` (the cloth outline; ``rms_px`` is
            then its corners' error) or ``"diamonds+cloth"``.
        size_source: where the table's size comes from: ``"diamonds"`` (the diamond pattern matched to ``spec``),
            ``"given"`` (passed by the caller), ``"balls"`` (measured from the balls' apparent size) or
            ``"default"`` (9-foot, nothing to measure it by).
        cloth_edges: sides of the table's cloth outline moved onto the cloth's edge in the photo (0-4;
            :mod:`pix2pockets.vision.table.cloth_edge`).
    """

    spec: TableSpec
    camera: PinholeCamera
    diamond_index: np.ndarray
    diamond_corners_px: np.ndarray
    rms_px: float
    n_matched: int
    diamond_z: float
    source: str = "diamonds"
    size_source: str = "diamonds"
    cloth_edges: int = 0

    def with_diamond_z(self, z: float) -> TableFit:
        """The same fit for diamonds at height ``z`` [m] above the cloth.

        The diamonds fix the camera relative to the diamond plane; another plane height only moves the cloth
        (and the camera's height above it): ``t' = t - R e_z (z - z_old)``.
        """
        cam = self.camera
        t = cam.t - cam.R[:, 2] * (float(z) - self.diamond_z)
        camera = PinholeCamera(cam.K, cam.R, t, cam.image_size)
        return replace(self, camera=camera, diamond_z=float(z))

    def scaled(self, sx: float, sy: float, image_size: tuple[int, int]) -> TableFit:
        """The same fit in the photo resized by ``sx`` across and ``sy`` down to ``image_size`` [px]."""
        return replace(
            self,
            camera=self.camera.scaled(sx, sy, image_size),
            diamond_corners_px=self.diamond_corners_px * np.array([sx, sy]),
            rms_px=self.rms_px * math.sqrt((sx * sx + sy * sy) / 2),
        )

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


# ----------------------------------------------------------------------------- corners
def diamond_rectangle(spec: TableSpec) -> np.ndarray:
    """Corners of the rectangle through the diamond centres [m], (4, 2), in ``TableSpec.corners`` order."""
    s = spec.diamond_setback
    L, W = spec.length, spec.width
    return np.array([[-s, -s], [L + s, -s], [L + s, W + s], [-s, W + s]])


def _rail_corners(diamonds: np.ndarray, index: np.ndarray, min_angle_deg: float = 8.0) -> np.ndarray:
    """Intersections of adjacent rail lines (rails with >= 2 matched diamonds), (4, 2), NaN where missing.

    Corner ``k`` is the meeting point of rails bottom/head, bottom/foot, foot/top, top/head (the
    ``TableSpec.corners`` order). Lines meeting at less than ``min_angle_deg`` in the image (a view along
    the table diagonal) give an ill-conditioned intersection and are skipped.
    """
    lines: list[np.ndarray | None] = []
    for r in range(4):
        m = np.isin(index, RAIL_DIAMONDS[r])
        lines.append(tls_line(diamonds[m]) if m.sum() >= 2 else None)
    pairs = [(3, 0), (0, 1), (1, 2), (2, 3)]
    out = np.full((4, 2), np.nan)
    sin_min = math.sin(math.radians(min_angle_deg))
    for k, (ra, rb) in enumerate(pairs):
        la, lb = lines[ra], lines[rb]
        if la is None or lb is None:
            continue
        if abs(la[0] * lb[1] - la[1] * lb[0]) < sin_min:
            continue
        p = np.cross(la, lb)
        out[k] = p[:2] / p[2]
    return out


def validate_corners(corners: np.ndarray, image_size: tuple[int, int], max_reach: float = 200.0) -> None:
    """Check the 4 table corners [px]: those in front of the camera (finite) lie within ``max_reach``
    image sizes of the image (a close phone shot may see the far corners well outside the frame) and,
    when all four are in front, form a convex quadrilateral. Corners behind the camera are NaN.

    Raises:
        TableFitError: with the reason.
    """
    corners = np.asarray(corners, dtype=float)
    if corners.shape != (4, 2):
        raise TableFitError("no table found: the rails do not give four corners")
    ok = np.all(np.isfinite(corners), axis=1)
    if ok.sum() < 2:
        raise TableFitError("no table found: most of the table would lie behind the camera")
    w, h = image_size
    c = corners[ok]
    far = (np.abs(c[:, 0] - w / 2) > max_reach * w) | (np.abs(c[:, 1] - h / 2) > max_reach * h)
    if far.any():
        raise TableFitError("no table found: table corners fall far outside the image")
    if ok.all():
        cross = []
        for i in range(4):
            a, b, c_ = corners[i], corners[(i + 1) % 4], corners[(i + 2) % 4]
            u, v = b - a, c_ - b
            cross.append(u[0] * v[1] - u[1] * v[0])
        if not (all(x < 0 for x in cross) or all(x > 0 for x in cross)):
            raise TableFitError("no table found: the corners do not form a convex quadrilateral")


def robust_homography(src: np.ndarray, dst: np.ndarray, thresh_px: float) -> tuple[np.ndarray, np.ndarray]:
    """Robust homography ``dst ~ H src``: MAGSAC++ (falling back to RANSAC, then plain least squares),
    refitted by least squares on the inliers. Returns ``(H, inlier mask)``."""
    H = mask = None
    if len(src) >= 5:
        for method in (cv2.USAC_MAGSAC, cv2.RANSAC):
            H, mask = cv2.findHomography(src, dst, method, thresh_px)
            if H is not None and mask is not None and mask.sum() >= 4:
                break
            H = None
    if H is None:
        mask = np.ones(len(src), dtype=bool)
    mask = np.asarray(mask).reshape(-1).astype(bool)
    try:
        H = fit_homography(src[mask], dst[mask])
    except ValueError as err:
        raise TableFitError(f"no table found: {err}") from None
    return H, mask


# ----------------------------------------------------------------------------- main entry
def _tolerance_px(diamonds: np.ndarray, image_size: tuple[int, int]) -> float:
    diag = math.hypot(*image_size)
    if len(diamonds) >= 2:
        d = np.linalg.norm(diamonds[:, None] - diamonds[None], axis=-1)
        d[np.diag_indices(len(diamonds))] = np.inf
        nn = float(np.median(d.min(axis=1)))
    else:
        nn = diag
    return float(np.clip(0.15 * nn, 1.5, 0.005 * diag))


def fit_table(
    diamonds: np.ndarray | Detections,
    image_size: tuple[int, int],
    spec: TableSpec | None = None,
    tol_px: float | None = None,
    focal_prior_px: float | None = None,
    diamond_z: float | None = None,
    pixel_aspect: float | None = None,
) -> TableFit:
    """Fit the table from diamond detections.

    Args:
        diamonds: diamond centres (n, 2) [px], or :class:`Detections` (its diamonds are used, best first).
        image_size: (width, height) [px].
        spec: the table (default 9-foot).
        tol_px: line inlier tolerance [px] (default: from the diamond spacing and image size).
        focal_prior_px: prior focal length [px] for near-top views (default: the larger image side).
        diamond_z: height of the diamond centres above the cloth [m] (default :func:`diamond_height`).
        pixel_aspect: width over height of one pixel when known or measured from the photo
            (:func:`~pix2pockets.vision.table.pixel_aspect.pixel_aspect_of_photo`); default: from the ball boxes.

    Photos stretched by an export (a 16:9 frame squashed to 640x640) are fitted with ``pixel_aspect`` or the
    one their ball boxes show (:mod:`pix2pockets.vision.table.pixel_aspect`), else, when square pixels fit no labelling,
    with one of the usual export stretches (:data:`~pix2pockets.vision.table.pixel_aspect.EXPORT_ASPECTS`), which
    then needs :data:`MIN_DIAMONDS_FOR_ASPECT` matched diamonds. The camera's ``K`` holds the aspect.

    Raises:
        TableFitError: too few diamonds, no consistent rails, or an implausible table.
    """
    spec = spec or TableSpec()
    ball_centres = np.zeros((0, 2))
    ball_aspect = 1.0
    if isinstance(diamonds, Detections):
        balls = diamonds[diamonds.is_ball]
        ball_centres = balls.centres
        ball_aspect = snapped_aspect(pixel_aspect_of_balls(balls.boxes, balls.own_score))
        d = diamonds[diamonds.is_diamond]
        order = np.argsort(-d.confidence)
        pts = d.centres[order][:MAX_DIAMONDS]
        back = order[:MAX_DIAMONDS]
        n_total = len(d)
    else:
        pts = np.asarray(diamonds, dtype=float).reshape(-1, 2)
        back = np.arange(len(pts))
        n_total = len(pts)
    if pixel_aspect is not None:
        ball_aspect = snapped_aspect(float(pixel_aspect))
    if not np.all(np.isfinite(pts)):
        raise TableFitError("diamond positions must be finite")
    if len(pts) < MIN_DIAMONDS:
        raise TableFitError(
            f"too few table points: {counted(len(pts), 'diamond')} detected, "
            f"need at least {MIN_DIAMONDS} on two rails "
            "(show more of the table: two rails with their sights, not hidden by players or the frame edge)"
        )
    h = diamond_height(spec) if diamond_z is None else float(diamond_z)
    # A stretched photo is fitted as the photo before the stretch (x divided by the pixel aspect), then the
    # camera is stretched back. The aspect the balls show goes first (a square-pixel camera tilted the wrong
    # way can pass the checks on a stretched photo), then square pixels, then the other usual export
    # stretches, which must explain more diamonds (a free aspect is one more way to fit scattered false diamonds).
    guessed = [a for a in EXPORT_ASPECTS if a not in (1.0, ball_aspect)]
    first_error: TableFitError | None = None
    guesses = []
    for aspect in [*dict.fromkeys([ball_aspect, 1.0]), *guessed]:
        unstretch = np.array([aspect, 1.0])
        try:
            fit = _fit_square_pixels(
                pts / unstretch,
                (image_size[0] / aspect, image_size[1]),
                ball_centres / unstretch,
                spec,
                tol_px,
                focal_prior_px,
                h,
            )
        except TableFitError as err:
            first_error = first_error or err
            continue
        fit = _stretched(fit, aspect, image_size)
        if aspect not in guessed:
            return _full_index(fit, back, n_total)
        if fit.n_matched >= MIN_DIAMONDS_FOR_ASPECT:
            guesses.append((aspect, fit))
    if not guesses:
        raise first_error or TableFitError("no table found")

    # the best explained guess; ties go to the focal length nearer the prior of its unstretched photo
    def rank(guess: tuple[float, TableFit]) -> tuple[int, float]:
        aspect, fit = guess
        f0 = focal_prior_px or max(image_size[0] / aspect, image_size[1])
        return (fit.n_matched, -(fit.n_matched * fit.rms_px**2 + (math.log(fit.camera.K[1, 1] / f0) / 0.7) ** 2))

    return _full_index(max(guesses, key=rank)[1], back, n_total)


def _full_index(fit: TableFit, back: np.ndarray, n_total: int) -> TableFit:
    """``fit`` with its diamond index over all ``n_total`` diamonds (the fit saw those at ``back``)."""
    index = np.full(n_total, -1)
    index[back] = fit.diamond_index
    return replace(fit, diamond_index=index)


def _stretched(fit: TableFit, aspect: float, image_size: tuple[int, int]) -> TableFit:
    """A fit made on a photo with its x axis divided by ``aspect``, for the photo itself (``image_size``)."""
    if aspect == 1.0:
        return fit
    cam = fit.camera
    camera = PinholeCamera(np.diag([aspect, 1.0, 1.0]) @ cam.K, cam.R, cam.t, (int(image_size[0]), int(image_size[1])))
    return replace(fit, camera=camera, diamond_corners_px=fit.diamond_corners_px * np.array([aspect, 1.0]))


def _fit_square_pixels(
    pts: np.ndarray,
    image_size: tuple[float, float],
    ball_centres: np.ndarray,
    spec: TableSpec,
    tol_px: float | None,
    focal_prior_px: float | None,
    h: float,
) -> TableFit:
    """:func:`fit_table` for a photo with square pixels; ``diamond_index`` is over ``pts``."""
    tol = tol_px if tol_px is not None else _tolerance_px(pts, image_size)
    lines = fit_rail_lines(pts, tol)
    if sum(len(x) >= 2 for x in lines) < 2:
        raise TableFitError(
            f"too few table points: the {len(pts)} diamonds found lie on one rail; diamonds on at least two "
            "rails are needed"
        )
    fits = []
    first_error: TableFitError | None = None
    for index in label_candidates(pts, lines, spec):
        try:
            fits.append(_fit_labelled(pts, index, spec, image_size, tol, h, focal_prior_px))
        except TableFitError as err:
            first_error = first_error or err
    if not fits:
        raise first_error or TableFitError("no table found")
    # near-ties (e.g. an L of diamonds around one corner: the long and short rail look alike there) are
    # broken by the balls, which must lie on the playing surface
    camera, index, corners, rms, n_matched = max(
        fits, key=lambda f: (f[4], _balls_on_table(f[0], ball_centres, spec), -round(f[3], 1))
    )

    # the 180-degree convention: head rail further left / lower in the image than the foot rail
    head_mid = camera.project_table(np.array([0.0, spec.width / 2]), h)
    foot_mid = camera.project_table(np.array([spec.length, spec.width / 2]), h)
    metric = (head_mid[0] - foot_mid[0]) - (head_mid[1] - foot_mid[1])
    if metric > 0:
        camera, index, corners = _rotate_half_turn(camera, index, corners, spec)
    return TableFit(spec, camera, index, corners, rms, n_matched, h)


def _fit_labelled(
    pts: np.ndarray,
    index: np.ndarray,
    spec: TableSpec,
    image_size: tuple[int, int],
    tol: float,
    h: float,
    focal_prior_px: float | None,
) -> tuple[PinholeCamera, np.ndarray, np.ndarray, float, int]:
    """Homography, camera and validation for one labelling. Returns (camera, index, corners, rms, n).

    Raises:
        TableFitError: the labelled diamonds do not give a plausible table and camera.
    """
    m = index >= 0
    world = spec.diamonds[index[m]]
    image = pts[m]
    rect = diamond_rectangle(spec)
    thresh = max(3.0, 2 * tol)
    H_diamonds, _ = robust_homography(world, image, thresh)
    # rail-line corners, kept only where they agree with the diamonds' homography
    corners = _rail_corners(pts, index)
    predicted = apply_homography(H_diamonds, rect)
    agree = np.linalg.norm(corners - predicted, axis=1) < max(5.0, 3 * tol)
    corners = np.where(agree[:, None], corners, np.nan)
    world_all = np.vstack([world, rect[agree]])
    image_all = np.vstack([image, corners[agree]])
    H, mask = robust_homography(world_all, image_all, thresh)
    if mask.sum() < 4:
        raise TableFitError("no table found: the diamonds do not fit a table (homography failed)")
    world3_all = np.column_stack([world_all, np.full(len(world_all), h)])
    keep = mask.copy()
    for _ in range(6):  # refit without the worst point while it is an outlier
        camera = camera_from_homography(
            H,
            image_size,
            z=h,
            world_points=world3_all[keep],
            image_points=image_all[keep],
            focal_prior_px=focal_prior_px,
        )
        err_all = np.linalg.norm(camera.project(world3_all) - image_all, axis=1)
        err_all = np.where(np.isfinite(err_all), err_all, np.inf)
        limit = max(3.0, 3 * 1.4826 * float(np.median(err_all[keep])))
        worst = int(np.argmax(np.where(keep, err_all, -1.0)))
        if err_all[worst] <= limit or keep.sum() <= 7:
            break
        keep[worst] = False
    err = err_all[keep]
    rms = float(np.sqrt(np.mean(err**2)))
    if not np.isfinite(rms) or rms > max(4.0, tol):
        raise TableFitError(f"no table found: the diamonds do not fit a {spec.name} table (error {in_photo_px(rms)})")
    diamond_rows = np.flatnonzero(m)
    index = index.copy()
    index[diamond_rows[~keep[: len(diamond_rows)]]] = -1
    m = index >= 0
    n_matched = int(m.sum())
    if n_matched < MIN_MATCHED_DIAMONDS:
        raise TableFitError(
            f"too few table points: only {n_matched} diamonds fit a {spec.name} table, {MIN_MATCHED_DIAMONDS} "
            "are needed "
            "to check the fit (show more of the table: two rails with their sights)"
        )
    if n_matched < 0.5 * len(pts):
        raise TableFitError(
            f"no table found: only {n_matched} of {len(pts)} diamonds fit the diamond pattern of a {spec.name} table"
        )
    check_reprojection(camera, pts, index, h, spec)
    if camera.position[2] < spec.cushion_height + MIN_CAMERA_CLEARANCE:
        raise TableFitError("no table found: the fitted camera is not above the table")
    validate_corners(camera.project_table(rect, h), image_size)
    if not 0.25 * max(image_size) < camera.focal_px < 6 * max(image_size):
        raise TableFitError(f"no table found: implausible camera (focal length {in_photo_px(camera.focal_px)})")

    return camera, index, corners, rms, n_matched


def diamond_scatter(pts: np.ndarray, index: np.ndarray) -> tuple[float, int]:
    """Scatter of the matched diamonds about their own rail lines [px] (per-coordinate standard deviation),
    pooled over rails with 3+ matched diamonds, and its degrees of freedom (0: not measurable).

    A correct labelling puts each rail's diamonds on one line in the image, so this measures the detector's
    diamond noise independently of the fitted camera.
    """
    ss, dof = 0.0, 0
    for ids in RAIL_DIAMONDS:
        m = np.isin(index, ids)
        if m.sum() >= 3:
            line = tls_line(pts[m])
            ss += float(np.sum((pts[m] @ line[:2] + line[2]) ** 2))
            dof += int(m.sum()) - 2
    return (math.sqrt(ss / dof) if dof else 0.0), dof


def check_reprojection(camera: PinholeCamera, pts: np.ndarray, index: np.ndarray, h: float, spec: TableSpec) -> None:
    """Reject a camera whose reprojection error of the matched diamonds is large in absolute terms
    (``REPROJECTION_MAX_PX`` or ``REPROJECTION_MAX_DIAG`` of the image diagonal) or far larger than the diamonds'
    own scatter about their rail lines (a wrong labelling that a general homography still fits roughly).

    Raises:
        TableFitError: with both numbers.
    """
    m = index >= 0
    proj = camera.project_table(spec.diamonds[index[m]], h)
    err = float(np.sqrt(np.mean(np.sum((proj - pts[m]) ** 2, axis=1))))
    absolute = max(REPROJECTION_MAX_PX, REPROJECTION_MAX_DIAG * math.hypot(*camera.image_size))
    if not err <= absolute:
        raise TableFitError(f"no table found: the diamonds do not fit one camera (reprojection {in_photo_px(err)})")
    sigma, dof = diamond_scatter(pts, index)
    if dof < MIN_SCATTER_DOF:
        return
    limit = max(REPROJECTION_FLOOR_PX, REPROJECTION_FACTOR * math.sqrt(2.0) * sigma)
    if not err <= limit:
        raise TableFitError(
            f"no table found: the diamonds do not fit one camera (reprojection {in_photo_px(err)}, "
            f"diamond scatter about the rails {in_photo_px(sigma)})"
        )


def _balls_on_table(camera: PinholeCamera, centres_px: np.ndarray, spec: TableSpec) -> int:
    """How many ball box centres [px] map onto the playing surface (ball-centre height)."""
    if len(centres_px) == 0:
        return 0
    xy = apply_homography(np.linalg.inv(camera.table_homography(spec.ball_radius)), centres_px)
    return int(np.sum(np.all(np.isfinite(xy), axis=1) & spec.contains(np.nan_to_num(xy, nan=-1.0))))


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

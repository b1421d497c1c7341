"""Plane homographies and camera recovery from a plane homography.

A homography ``H`` (3, 3) maps homogeneous plane points to homogeneous image points. Here the plane is a
horizontal plane of the table frame at some height ``z`` [m] and the image is in pixels. A
:class:`~pix2pockets.geometry.camera.PinholeCamera` gives ``H = K [r1, r2, z r3 + t]``; this module goes
the other way: from ``H`` (fitted to image points of the diamonds, which sit on the rail cap at
``TableSpec.cushion_height``) back to the focal length and pose, assuming square pixels and the
principal point at the image centre. The recovered camera then gives the homography of any other
height: the cloth (``z = 0``, ball contact points) or the ball centres (``z = ball_radius``).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import least_squares

from pix2pockets.geometry.camera import PinholeCamera

MAX_REFINE_STEPS = 200
"""Most residual evaluations of one camera refinement (a start that has not converged by then is a false labelling)."""

DEFAULT_FOCAL_FACTOR = 1.0
"""Prior focal length as a multiple of the larger image side (about 53 degrees horizontal field of view)."""


def apply_homography(H: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Map points (..., 2) through ``H`` (3, 3); points mapped to infinity give NaN."""
    pts = np.asarray(points, dtype=float)
    h = pts @ H[:, :2].T + H[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        out = h[..., :2] / h[..., 2:3]
    return np.where(np.abs(h[..., 2:3]) > 1e-12, out, np.nan)


def _normaliser(points: np.ndarray) -> np.ndarray:
    """Similarity moving ``points`` to zero mean and mean distance sqrt(2) (Hartley normalisation)."""
    mean = points.mean(axis=0)
    dist = np.linalg.norm(points - mean, axis=1).mean()
    s = math.sqrt(2) / dist if dist > 0 else 1.0
    return np.array([[s, 0.0, -s * mean[0]], [0.0, s, -s * mean[1]], [0.0, 0.0, 1.0]])


def fit_homography(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """Least-squares homography (normalised DLT) with ``dst ~ H src``.

    Args:
        src: source points (n, 2), n >= 4, not all collinear.
        dst: destination points (n, 2).

    Returns:
        ``H`` (3, 3) with ``H[2, 2] = 1`` (or unit norm when that entry vanishes).

    Raises:
        ValueError: fewer than 4 points or a degenerate configuration.
    """
    src = np.asarray(src, dtype=float).reshape(-1, 2)
    dst = np.asarray(dst, dtype=float).reshape(-1, 2)
    if len(src) != len(dst) or len(src) < 4:
        raise ValueError(f"a homography needs at least 4 point pairs, got {len(src)} and {len(dst)}")
    Ts, Td = _normaliser(src), _normaliser(dst)
    s = src @ Ts[:2, :2].T + Ts[:2, 2]
    d = dst @ Td[:2, :2].T + Td[:2, 2]
    n = len(s)
    A = np.zeros((2 * n, 9))
    A[0::2, 0:2] = s
    A[0::2, 2] = 1
    A[0::2, 6:8] = -d[:, :1] * s
    A[0::2, 8] = -d[:, 0]
    A[1::2, 3:5] = s
    A[1::2, 5] = 1
    A[1::2, 6:8] = -d[:, 1:2] * s
    A[1::2, 8] = -d[:, 1]
    _, sv, vt = np.linalg.svd(A)
    if sv[-2] < 1e-9 * sv[0]:
        raise ValueError("degenerate point configuration for a homography (collinear points?)")
    Hn = vt[-1].reshape(3, 3)
    H = np.linalg.inv(Td) @ Hn @ Ts
    return H / H[2, 2] if abs(H[2, 2]) > 1e-12 else H / np.linalg.norm(H)


def focal_from_homography(H: np.ndarray, image_size: tuple[int, int]) -> float | None:
    """Focal length [px] from a plane -> image homography, or ``None`` when the view is too frontal.

    Uses the two constraints of a rotation (``r1 . r2 = 0``, ``|r1| = |r2|``) with the principal point
    at the image centre and square pixels, combined in a least-squares sense. A camera looking almost
    straight down leaves the focal length undetermined (it trades off against the distance).
    """
    w, h = image_size
    T = np.array([[1.0, 0.0, -w / 2], [0.0, 1.0, -h / 2], [0.0, 0.0, 1.0]])
    A = T @ H
    A = A / np.linalg.norm(A[:, :2])
    a1, a2 = A[:, 0], A[:, 1]
    # rows: coefficient of 1/f^2 and of 1, both constraints linear in g = f^2: c * (1/g) + d = 0
    c1, d1 = a1[0] * a2[0] + a1[1] * a2[1], a1[2] * a2[2]
    c2, d2 = (a1[0] ** 2 + a1[1] ** 2) - (a2[0] ** 2 + a2[1] ** 2), a1[2] ** 2 - a2[2] ** 2
    # minimise (c1 x + d1)^2 + (c2 x + d2)^2 over x = 1 / f^2
    den = c1 * c1 + c2 * c2
    if den < 1e-15:
        return None
    x = -(c1 * d1 + c2 * d2) / den
    # the perspective terms (third row) must be big enough relative to the scale for a stable answer
    if x <= 0 or math.hypot(d1, d2) < 1e-9:
        return None
    f = 1.0 / math.sqrt(x)
    if not (0.05 * max(w, h) < f < 50 * max(w, h)):
        return None
    return f


def pose_from_homography(
    H: np.ndarray, K: np.ndarray, z: float = 0.0, ref_xy: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Rotation and translation of a camera with intrinsics ``K`` that sees the plane at height ``z``
    through ``H`` (plane -> pixels). The sign is chosen so that the plane point ``ref_xy`` [m] (a point
    seen in the image; default the plane origin) lies in front of the camera."""
    B = np.linalg.inv(K) @ H
    lam = 2.0 / (np.linalg.norm(B[:, 0]) + np.linalg.norm(B[:, 1]))
    B = B * lam
    r1, r2 = B[:, 0], B[:, 1]
    r3 = np.cross(r1, r2)
    Rm = np.column_stack([r1, r2, r3])
    U, _, Vt = np.linalg.svd(Rm)
    R = U @ Vt
    if np.linalg.det(R) < 0:
        R = U @ np.diag([1.0, 1.0, -1.0]) @ Vt
    t_plane = B[:, 2]
    ref = np.zeros(2) if ref_xy is None else np.asarray(ref_xy, dtype=float)
    # the seen plane point must lie in front of the camera: flip the overall sign if needed
    if (B[2, 0] * ref[0] + B[2, 1] * ref[1] + t_plane[2]) < 0:
        R = R @ np.diag([-1.0, -1.0, 1.0])
        t_plane = -t_plane
    t = t_plane - z * R[:, 2]
    return R, t


def _skew(v: np.ndarray) -> np.ndarray:
    """Cross-product matrices [v]x (..., 3, 3) of vectors (..., 3)."""
    out = np.zeros((*v.shape[:-1], 3, 3))
    out[..., 0, 1], out[..., 0, 2], out[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    out[..., 1, 0], out[..., 2, 0], out[..., 2, 1] = v[..., 2], -v[..., 1], v[..., 0]
    return out


def _rodrigues(rvec: np.ndarray) -> np.ndarray:
    theta = float(np.linalg.norm(rvec))
    if theta < 1e-12:
        return np.eye(3)
    Kx = _skew(rvec / theta)
    return np.eye(3) + math.sin(theta) * Kx + (1 - math.cos(theta)) * Kx @ Kx


def rotated_points_jacobian(rvec: np.ndarray, R: np.ndarray, points: np.ndarray) -> np.ndarray:
    """d(R(rvec) X) / d rvec (n, 3, 3) for points X (n, 3), R = :func:`_rodrigues` (rvec).

    Closed form of the rotation-vector derivative, -R [X]x (w w^T + (R^T - I)[w]x) / |w|^2 (Gallego and Yezzi,
    "A compact formula for the derivative of a 3-D rotation in exponential coordinates", 2015); -[X]x at w = 0.
    """
    theta2 = float(rvec @ rvec)
    if theta2 < 1e-24:
        return -_skew(points)
    m = (np.outer(rvec, rvec) + (R.T - np.eye(3)) @ _skew(rvec)) / theta2
    return -R @ _skew(points) @ m


def _rotation_vector(R: np.ndarray) -> np.ndarray:
    cos = np.clip((np.trace(R) - 1) / 2, -1.0, 1.0)
    theta = math.acos(cos)
    if theta < 1e-9:
        return np.zeros(3)
    if math.pi - theta < 1e-6:
        # 180 degrees: axis from the symmetric part
        M = (R + np.eye(3)) / 2
        axis = np.sqrt(np.clip(np.diag(M), 0, None))
        i = int(np.argmax(axis))
        axis = M[i] / math.sqrt(M[i, i])
        return axis * theta
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (2 * math.sin(theta))
    return w * theta


def camera_from_homography(
    H: np.ndarray,
    image_size: tuple[int, int],
    z: float = 0.0,
    world_points: np.ndarray | None = None,
    image_points: np.ndarray | None = None,
    focal_prior_px: float | None = None,
    focal_prior_sigma: float = 0.7,
) -> PinholeCamera:
    """Recover a :class:`PinholeCamera` from the homography of the plane at height ``z`` [m].

    The focal length comes from the rotation constraints when the view is oblique enough, else from the
    prior (``focal_prior_px``, default ``DEFAULT_FOCAL_FACTOR`` x the larger image side). When point
    correspondences are given, focal length and pose are refined by minimising the reprojection error
    [px] with a weak log-normal prior on the focal length (``focal_prior_sigma``), which only matters
    when the view is nearly straight down and the data cannot tell focal length from distance.

    Args:
        H: plane (table metres at height ``z``) -> image pixels homography (3, 3).
        image_size: (width, height) [px]; principal point at its centre.
        z: height of the plane [m].
        world_points: (n, 3) table points [m] for refinement (optional).
        image_points: (n, 2) their pixels.
        focal_prior_px: prior focal length [px].
        focal_prior_sigma: standard deviation of log focal length in the prior.
    """
    w, h = image_size
    f0 = focal_prior_px or DEFAULT_FOCAL_FACTOR * max(w, h)
    f = focal_from_homography(H, image_size) or f0
    if not 0.2 * f0 < f < 5 * f0:
        f = f0

    def intrinsics(f: float) -> np.ndarray:
        return np.array([[f, 0.0, w / 2], [0.0, f, h / 2], [0.0, 0.0, 1.0]])

    ref = None if world_points is None or len(world_points) == 0 else np.asarray(world_points)[:, :2].mean(axis=0)
    R, t = pose_from_homography(H, intrinsics(f), z, ref)
    if world_points is None or image_points is None or len(world_points) < 4:
        return PinholeCamera(intrinsics(f), R, t, (int(w), int(h)))
    X = np.asarray(world_points, dtype=float)
    uv = np.asarray(image_points, dtype=float)

    def residuals(p: np.ndarray) -> np.ndarray:
        fk = math.exp(p[0])
        Rk = _rodrigues(p[1:4])
        cam = X @ Rk.T + p[4:7]
        proj = cam[:, :2] / cam[:, 2:3] * fk + np.array([w / 2, h / 2])
        prior = (p[0] - math.log(f0)) / focal_prior_sigma
        return np.concatenate([(proj - uv).ravel(), [prior]])

    def jacobian(p: np.ndarray) -> np.ndarray:
        """d residuals / d parameters (2n + 1, 7), in closed form."""
        fk = math.exp(p[0])
        Rk = _rodrigues(p[1:4])
        cam = X @ Rk.T + p[4:7]
        inv_z = 1.0 / cam[:, 2]
        xy = cam[:, :2] * inv_z[:, None]
        # d(u, v) / d cam: f / z [[1, 0, -x / z], [0, 1, -y / z]]
        d_cam = np.zeros((len(X), 2, 3))
        d_cam[:, 0, 0] = d_cam[:, 1, 1] = fk * inv_z
        d_cam[:, :, 2] = -fk * xy * inv_z[:, None]
        jac = np.zeros((2 * len(X) + 1, 7))
        jac[:-1, 0] = (fk * xy).ravel()
        jac[:-1, 1:4] = (d_cam @ rotated_points_jacobian(p[1:4], Rk, X)).reshape(-1, 3)
        jac[:-1, 4:7] = d_cam.reshape(-1, 3)
        jac[-1, 0] = 1.0 / focal_prior_sigma
        return jac

    # multi-start over the focal length: near-degenerate point sets (few rails) have local minima
    starts = [f] + [k * f0 for k in (1.0, 0.5, 2.0) if abs(math.log(k * f0 / f)) > 0.1]
    best = None
    for fs in starts:
        Rs, ts = pose_from_homography(H, intrinsics(fs), z, ref)
        p0 = np.concatenate([[math.log(fs)], _rotation_vector(Rs), ts])
        try:
            sol = least_squares(residuals, p0, jac=jacobian, method="lm", x_scale="jac", max_nfev=MAX_REFINE_STEPS)
        except ValueError:
            continue
        if np.all(np.isfinite(sol.x)) and (best is None or sol.cost < best.cost):
            best = sol
    if best is None:
        return PinholeCamera(intrinsics(f), R, t, (int(w), int(h)))
    fk = math.exp(best.x[0])
    Rk = _rodrigues(best.x[1:4])
    # re-orthonormalise against round-off
    U, _, Vt = np.linalg.svd(Rk)
    return PinholeCamera(intrinsics(fk), U @ Vt, best.x[4:7].copy(), (int(w), int(h)))


def camera_tilt(camera: PinholeCamera) -> float:
    """Angle between the optical axis and straight down [rad]: 0 for a top view, pi/2 looking level."""
    forward = camera.R[2]  # optical axis in the world frame
    return float(math.acos(np.clip(-forward[2], -1.0, 1.0)))


def image_to_table(camera: PinholeCamera, uv: np.ndarray, z: float = 0.0) -> np.ndarray:
    """Pixels (..., 2) -> table points (..., 2) [m] on the horizontal plane at height ``z`` [m]."""
    return apply_homography(np.linalg.inv(camera.table_homography(z)), uv)

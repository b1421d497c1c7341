"""Pinhole camera looking at the table: the one projection model shared by rendering and vision.

World frame = table frame (see :mod:`pix2pockets.geometry.table`), ``z`` up from the cloth [m].
Camera frame: ``x`` right, ``y`` down, ``z`` forward (OpenCV convention). Pixels: ``u`` right, ``v``
down, origin at the top-left pixel corner.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, slots=True)
class PinholeCamera:
    """A pinhole camera without lens distortion.

    Attributes:
        K: intrinsics (3, 3) [px].
        R: rotation world -> camera (3, 3).
        t: translation world -> camera (3,) [m]: ``X_cam = R @ X_world + t``.
        image_size: (width, height) [px].
    """

    K: np.ndarray
    R: np.ndarray
    t: np.ndarray
    image_size: tuple[int, int]

    def __post_init__(self) -> None:
        if np.shape(self.K) != (3, 3) or np.shape(self.R) != (3, 3) or np.shape(self.t) != (3,):
            raise ValueError("PinholeCamera needs K (3, 3), R (3, 3) and t (3,)")
        if abs(np.linalg.det(self.R) - 1.0) > 1e-6:
            raise ValueError("PinholeCamera.R must be a rotation matrix (det 1)")

    @property
    def position(self) -> np.ndarray:
        """Camera centre in the world frame [m]."""
        return -self.R.T @ self.t

    @property
    def focal_px(self) -> float:
        """Focal length [px] (mean of fx, fy)."""
        return float((self.K[0, 0] + self.K[1, 1]) / 2)

    def scaled(self, sx: float, sy: float, image_size: tuple[int, int]) -> PinholeCamera:
        """The same camera seeing the photo resized by ``sx`` across and ``sy`` down to ``image_size`` [px]."""
        K = np.diag([sx, sy, 1.0]) @ self.K
        return PinholeCamera(K, self.R, self.t, (int(image_size[0]), int(image_size[1])))

    def world_to_camera(self, points: np.ndarray) -> np.ndarray:
        """World points (..., 3) [m] -> camera-frame points (..., 3) [m]."""
        return np.asarray(points, dtype=float) @ self.R.T + self.t

    def project(self, points: np.ndarray) -> np.ndarray:
        """World points (..., 3) [m] -> pixels (..., 2). Points behind the camera give NaN."""
        cam = self.world_to_camera(points)
        z = cam[..., 2:3]
        with np.errstate(divide="ignore", invalid="ignore"):
            uvw = cam @ self.K.T
            uv = uvw[..., :2] / z
        return np.where(z > 1e-9, uv, np.nan)

    def project_table(self, xy: np.ndarray, z: float = 0.0) -> np.ndarray:
        """Table points (..., 2) at height ``z`` [m] -> pixels (..., 2)."""
        xy = np.asarray(xy, dtype=float)
        pts = np.concatenate([xy, np.full((*xy.shape[:-1], 1), z)], axis=-1)
        return self.project(pts)

    def table_homography(self, z: float = 0.0) -> np.ndarray:
        """Homography (3, 3) mapping table points at height ``z`` [m] to pixels."""
        P = self.K @ np.column_stack([self.R[:, 0], self.R[:, 1], self.R[:, 2] * z + self.t])
        return P / P[2, 2]

    @classmethod
    def look_at(
        cls,
        eye: np.ndarray,
        target: np.ndarray,
        focal_px: float,
        image_size: tuple[int, int],
        roll: float = 0.0,
        up: np.ndarray | None = None,
    ) -> PinholeCamera:
        """A camera at ``eye`` [m] looking at ``target`` [m], rolled by ``roll`` [rad] about its axis.

        ``up`` is the world direction that should appear up in the image (default ``+z``, or ``+y`` when
        looking straight down).
        """
        eye = np.asarray(eye, dtype=float)
        forward = np.asarray(target, dtype=float) - eye
        norm = np.linalg.norm(forward)
        if norm < 1e-9:
            raise ValueError("camera eye and target coincide")
        forward /= norm
        if up is None:
            up = np.array([0.0, 0.0, 1.0])
            if abs(forward @ up) > 0.999:
                up = np.array([0.0, 1.0, 0.0])
        right = np.cross(forward, up)
        if np.linalg.norm(right) < 1e-9:
            raise ValueError("camera 'up' is parallel to the viewing direction")
        right /= np.linalg.norm(right)
        down = np.cross(forward, right)
        R = np.vstack([right, down, forward])
        if roll:
            c, s = np.cos(roll), np.sin(roll)
            R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ R
        t = -R @ eye
        w, h = image_size
        K = np.array([[focal_px, 0.0, w / 2], [0.0, focal_px, h / 2], [0.0, 0.0, 1.0]])
        return cls(K, R, t, (int(w), int(h)))

"""What the camera sees of each ball: its silhouette (:func:`sphere_boxes`, in closed form) less what the balls in
front, the near cushions and the image border hide (:func:`visible_boxes`).

A ball behind another ball, or beside the cushion nearest the camera in a low view, shows only part of its
silhouette, and its box stops where the part hidden begins. :func:`visible_boxes` predicts those boxes by casting a
grid of rays over each ball's silhouette box: a ray sees the ball where it meets the ball's sphere before any other
ball's, its line of sight from the camera to that point passes above every cushion nose between them (a cushion is
solid up to its nose's height outside the playing surface), and its pixel lies in the image.
"""

from __future__ import annotations

import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.table import TableSpec


def sphere_boxes(camera: PinholeCamera, centres: np.ndarray, radius: float) -> np.ndarray:
    """Bounding boxes [px] ``x1, y1, x2, y2`` of the images of spheres, (n, 4).

    Args:
        camera: the camera.
        centres: sphere centres in the table frame (n, 3) [m].
        radius: sphere radius [m].
    """
    C = camera.world_to_camera(np.asarray(centres, dtype=float).reshape(-1, 3))
    K = camera.K
    # dual conic of the silhouette: K (C C^T - R^2 I) K^T, per sphere
    Q = C[:, :, None] * C[:, None, :] - radius**2 * np.eye(3)[None]
    D = K[None] @ Q @ K.T[None]
    out = np.empty((len(C), 4))
    for axis in (0, 1):
        a, b, c = D[:, axis, axis], D[:, axis, 2], D[:, 2, 2]
        disc = np.sqrt(np.clip(b * b - a * c, 0.0, None))
        lo, hi = (b - disc) / c, (b + disc) / c
        out[:, axis] = np.minimum(lo, hi)
        out[:, axis + 2] = np.maximum(lo, hi)
    return out


RAY_GRID = 32
"""Rays across each side of a ball's silhouette box: a cell of about 1 px for a ball 32 px across."""


def _sphere_hits(origin_dirs: np.ndarray, centres: np.ndarray, radius: float) -> np.ndarray:
    """Distance along unit rays (m, 3) from the camera centre to their first meeting with each sphere (m, n)
    [m]; ``inf`` where a ray misses. Camera frame."""
    along = origin_dirs @ centres.T  # (m, n)
    off2 = np.sum(centres**2, axis=1)[None] - along**2
    inside = radius**2 - off2
    with np.errstate(invalid="ignore"):
        t = along - np.sqrt(np.where(inside >= 0, inside, np.nan))
    return np.where((inside >= 0) & (t > 0), t, np.inf)


def _cushion_sides(eye: np.ndarray, spec: TableSpec) -> list[tuple[int, float]]:
    """The cushion nose planes (axis, coordinate [m]) between the camera at ``eye`` (3,) and the playing surface."""
    bounds = ((0, 0.0, eye[0] < 0.0), (0, spec.length, eye[0] > spec.length))
    bounds += ((1, 0.0, eye[1] < 0.0), (1, spec.width, eye[1] > spec.width))
    return [(axis, bound) for axis, bound, outside in bounds if outside]


def _near_cushion(eye: np.ndarray, centre: np.ndarray, radius: float, spec: TableSpec, sides: list) -> bool:
    """Whether a cushion in ``sides`` can hide any of the ball at ``centre`` (3,) [m]: the line of sight to the ball's
    foot, at the ball's near edge, crosses the cushion's plane below its height."""
    for axis, bound in sides:
        gap = max(abs(centre[axis] - bound) - radius, 0.0)  # nose plane to the ball's near edge
        out = abs(eye[axis] - bound)  # camera to the nose plane
        if eye[2] * gap / (out + gap) < spec.cushion_height:
            return True
    return False


def _behind_cushion(eye: np.ndarray, points: np.ndarray, spec: TableSpec, sides: list) -> np.ndarray:
    """Mask (m,) of world points on balls whose line of sight from ``eye`` (3,) crosses a cushion nose's plane in
    ``sides`` below its height [m]."""
    hidden = np.zeros(len(points), dtype=bool)
    for axis, bound in sides:
        span = points[:, axis] - eye[axis]
        with np.errstate(divide="ignore", invalid="ignore"):
            s = (bound - eye[axis]) / span
        z = eye[2] + s * (points[:, 2] - eye[2])
        hidden |= (s > 0) & (s < 1) & (z < spec.cushion_height)
    return hidden


def visible_boxes(
    camera: PinholeCamera,
    centres: np.ndarray,
    radius: float,
    silhouettes: np.ndarray,
    spec: TableSpec | None = None,
    grid: int = RAY_GRID,
) -> np.ndarray:
    """Boxes ``x1, y1, x2, y2`` [px] (n, 4) of the part of each ball the camera sees; NaN rows for balls it does
    not see at all.

    Rays are cast only over balls that something can hide: a nearer ball whose silhouette box overlaps theirs, a
    cushion they lie near, or the image border; the others are seen whole.

    Args:
        camera: the camera.
        centres: ball centres in the table frame (n, 3) [m].
        radius: ball radius [m].
        silhouettes: each ball's whole silhouette box (n, 4) [px] (:func:`sphere_boxes`).
        spec: the table whose cushions hide balls beside them (``None``: no cushions).
        grid: rays across each side of a silhouette box.
    """
    centres = np.asarray(centres, dtype=float).reshape(-1, 3)
    sil = np.asarray(silhouettes, dtype=float).reshape(-1, 4)
    n = len(centres)
    out = sil.copy()
    if n == 0:
        return out
    w, h = camera.image_size
    cam_centres = camera.world_to_camera(centres)
    depth = cam_centres[:, 2]
    eye = camera.position
    sides = _cushion_sides(eye, spec) if spec is not None else []
    finite = np.all(np.isfinite(sil), axis=1) & (depth > 0)
    out[~finite] = np.nan
    overlap = (
        (sil[:, None, 0] < sil[None, :, 2])
        & (sil[None, :, 0] < sil[:, None, 2])
        & (sil[:, None, 1] < sil[None, :, 3])
        & (sil[None, :, 1] < sil[:, None, 3])
        & (depth[None, :] < depth[:, None])
    )
    in_image = (sil[:, 0] >= 0) & (sil[:, 1] >= 0) & (sil[:, 2] <= w) & (sil[:, 3] <= h)
    Kinv = np.linalg.inv(camera.K)
    frac = (np.arange(grid) + 0.5) / grid
    for i in np.flatnonzero(finite):
        front = np.flatnonzero(overlap[i] & finite)
        cushion = bool(sides) and _near_cushion(eye, centres[i], radius, spec, sides)
        if len(front) == 0 and not cushion and in_image[i]:
            continue
        x1, y1, x2, y2 = sil[i]
        cell = np.array([(x2 - x1) / grid, (y2 - y1) / grid])
        gx, gy = np.meshgrid(x1 + frac * (x2 - x1), y1 + frac * (y2 - y1))
        px = np.column_stack([gx.ravel(), gy.ravel()])
        rays = np.column_stack([px, np.ones(len(px))]) @ Kinv.T
        rays /= np.linalg.norm(rays, axis=1, keepdims=True)
        hits = _sphere_hits(rays, cam_centres[np.concatenate([[i], front])], radius)
        own = hits[:, 0]
        seen = np.isfinite(own) & (np.min(hits[:, 1:], axis=1, initial=np.inf) >= own)
        seen &= (px[:, 0] >= 0) & (px[:, 0] <= w) & (px[:, 1] >= 0) & (px[:, 1] <= h)
        if cushion and seen.any():
            points = (rays[seen] * own[seen, None] - camera.t) @ camera.R  # camera frame -> world
            idx = np.flatnonzero(seen)
            seen[idx[_behind_cushion(eye, points, spec, sides)]] = False
        if not seen.any():
            out[i] = np.nan
            continue
        p = px[seen]
        out[i, :2] = np.maximum(p.min(axis=0) - cell / 2, [x1, y1])
        out[i, 2:] = np.minimum(p.max(axis=0) + cell / 2, [x2, y2])
    return out


def visible_parts(
    camera: PinholeCamera, xy: np.ndarray, radius: float, spec: TableSpec | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The whole silhouette box and the visible box [px], each (n, 4), of balls resting on the cloth at table
    centres ``xy`` (n, 2) [m] (:func:`sphere_boxes`, :func:`visible_boxes`)."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    centres = np.column_stack([xy, np.full(len(xy), radius)])
    silhouettes = sphere_boxes(camera, centres, radius)
    return silhouettes, visible_boxes(camera, centres, radius, silhouettes, spec)


SHORTFALL_SLACK = 0.15
"""Share of a ball's silhouette by which its box may fall short of the part predicted visible without counting as cut:
real ball boxes are loose or tight by 10-15 %."""


def unexplained_shortfall(
    camera: PinholeCamera, boxes: np.ndarray, centres: np.ndarray, radius: float, spec: TableSpec | None = None
) -> np.ndarray:
    """How much shorter each ball's box is than the part of it predicted visible, per image axis (n, 2) [px], beyond
    :data:`SHORTFALL_SLACK` of its silhouette: what hides it there (a player, a cue, the hand on the cloth) is not
    modelled, so which side it hides is unknown and the ball's centre is unsure by up to half of it.

    Args:
        camera: the camera.
        boxes: the balls' boxes (n, 4) [px].
        centres: the balls' located centres in the table frame (n, 2) [m].
        radius: ball radius [m].
        spec: the table whose cushions hide balls beside them.
    """
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    silhouettes, seen = visible_parts(camera, centres, radius, spec)
    short = (seen[:, 2:] - seen[:, :2]) - (boxes[:, 2:] - boxes[:, :2])
    short -= SHORTFALL_SLACK * (silhouettes[:, 2:] - silhouettes[:, :2])
    return np.where(np.isfinite(short), np.maximum(short, 0.0), 0.0)

"""Ball location: from ball boxes in the image to ball centres on the table [m].

Three methods (:class:`LocateMethod`):

* ``sphere`` (default, exact): a ball is a sphere of radius ``R`` resting on the cloth, its centre at
  height ``R``. The image of a sphere is an ellipse whose bounding box follows in closed form from the
  camera (the dual conic ``K (C C^T - R^2 I) K^T`` for the centre ``C`` in camera coordinates). We find
  the table point whose sphere's box centre matches the detected box centre (a few fixed-point steps on
  the ball-centre plane; the box centre is robust to boxes that are uniformly a bit too tight or loose).
* ``contact``: the detector's predicted contact point (ball-cloth) mapped through the cloth homography;
  balls without a prediction fall back to ``sphere``.
* ``linear``: the paper's heuristic baseline. The point between the box centre and the top of the box,
  at the fraction ``tilt / 90 deg`` (camera tilt from the recovered camera), is mapped through the
  homography of the diamonds (rail-cap height).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.homography import apply_homography, camera_tilt
from pix2pockets.geometry.raster import table_to_env_pixels
from pix2pockets.geometry.table import TableSpec
from pix2pockets.state.ball import Ball
from pix2pockets.state.layout import TableLayout
from pix2pockets.vision.classes import ball_class_of
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.locate.visibility import sphere_boxes, visible_boxes, visible_parts
from pix2pockets.vision.table.fit import diamond_height


class LocateMethod(StrEnum):
    SPHERE = "sphere"
    CONTACT = "contact"
    LINEAR = "linear"


def _box_centres(boxes: np.ndarray) -> np.ndarray:
    return (boxes[:, :2] + boxes[:, 2:]) / 2


HIDDEN_EDGE = 0.06
"""A box edge counts as hidden when the ball's predicted visible part stops short of its silhouette there by more
than this share of the silhouette's size (and at least a pixel)."""


def hidden_edges(visible: np.ndarray, silhouettes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Masks ``(lo, hi)`` (n, 2) of the x and y box edges where a ball's visible box (n, 4) [px] stops short of its
    silhouette box (n, 4) [px]; none for a ball not seen at all."""
    size = silhouettes[:, 2:] - silhouettes[:, :2]
    slack = np.maximum(HIDDEN_EDGE * size, 1.0)
    with np.errstate(invalid="ignore"):
        lo = visible[:, :2] - silhouettes[:, :2] > slack
        hi = silhouettes[:, 2:] - visible[:, 2:] > slack
    return lo, hi


def locate_sphere(
    camera: PinholeCamera,
    boxes: np.ndarray,
    radius: float,
    iterations: int = 6,
    border_px: float = 1.0,
    spec: TableSpec | None = None,
    occlusion: bool = True,
) -> np.ndarray:
    """Table centres [m] (n, 2) of balls whose silhouette boxes best match ``boxes`` (n, 4) [px].

    A box cut on one side keeps only its other edge on that axis: the centre used is that edge less half the
    predicted silhouette size. A side is cut where the box touches the image border or, with ``occlusion``, where
    the ball's predicted visible part (:func:`~pix2pockets.vision.locate.visibility.visible_boxes`: the other
    balls, the cushions of ``spec`` and the image border hide parts of it) stops short of its silhouette. A box cut
    on both sides of an axis uses its centre there.
    """
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    if len(boxes) == 0:
        return np.zeros((0, 2))
    w, h = camera.image_size
    border_lo = boxes[:, :2] <= border_px
    border_hi = boxes[:, 2:] >= np.array([w, h]) - border_px
    Hinv = np.linalg.inv(camera.table_homography(radius))
    xy = apply_homography(Hinv, _box_centres(boxes))
    lo_cut, hi_cut = border_lo, border_hi
    for step in range(iterations):
        centres = np.column_stack([xy, np.full(len(xy), radius)])
        pred = sphere_boxes(camera, centres, radius)
        if occlusion and step < iterations - 1 and np.all(np.isfinite(xy)):
            hidden_lo, hidden_hi = hidden_edges(visible_boxes(camera, centres, radius, pred, spec), pred)
            lo_cut, hi_cut = border_lo | hidden_lo, border_hi | hidden_hi
        only_lo, only_hi = lo_cut & ~hi_cut, hi_cut & ~lo_cut
        half = (pred[:, 2:] - pred[:, :2]) / 2
        centre = _box_centres(boxes)
        centre = np.where(only_lo, boxes[:, 2:] - half, centre)
        centre = np.where(only_hi, boxes[:, :2] + half, centre)
        xy = xy + apply_homography(Hinv, centre) - apply_homography(Hinv, _box_centres(pred))
    return xy


def locate_contact(camera: PinholeCamera, contact_px: np.ndarray) -> np.ndarray:
    """Table points [m] (n, 2) of ball-cloth contact points [px] (n, 2)."""
    return apply_homography(np.linalg.inv(camera.table_homography(0.0)), np.asarray(contact_px, dtype=float))


def locate_linear(
    camera: PinholeCamera, boxes: np.ndarray, spec: TableSpec, diamond_z: float | None = None
) -> np.ndarray:
    """The paper's heuristic: a point between box centre and box top, by camera tilt, through the
    rail-cap (diamond) homography. ``diamond_z`` is that plane's height above the cloth [m] (default: the
    table spec's; pass the measured one, :attr:`TableFit.diamond_z`). Returns table points [m] (n, 2)."""
    z = diamond_height(spec) if diamond_z is None else float(diamond_z)
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    frac = camera_tilt(camera) / (np.pi / 2)
    centre = _box_centres(boxes)
    top = np.column_stack([centre[:, 0], boxes[:, 1]])
    point = centre + frac * (top - centre)
    return apply_homography(np.linalg.inv(camera.table_homography(z)), point)


@dataclass(frozen=True, slots=True, eq=False)
class LocatedBalls:
    """Balls located on the table.

    Attributes:
        detections: the ball detections kept (on the table, not in a pocket), in the same order as
            ``positions``.
        positions: ball centres in the table frame (n, 2) [m].
        contact_px: the contact points of the located balls projected back into the image (n, 2) [px].
        dropped: number of ball detections dropped (off the table or in a pocket).
    """

    detections: Detections
    positions: np.ndarray
    contact_px: np.ndarray
    dropped: int

    @property
    def env_positions(self) -> np.ndarray:
        """Positions in the paper's environment pixels (n, 2)."""
        return table_to_env_pixels(self.positions)

    def to_layout(self, spec: TableSpec) -> TableLayout:
        """A :class:`TableLayout` (classes only; ball numbers unknown), overlaps pushed apart."""
        balls = tuple(Ball(ball_class_of(int(c))) for c in self.detections.class_id)
        pos = settle_positions(self.positions, spec)
        return TableLayout(balls, pos, spec)


def locate_balls(
    camera: PinholeCamera,
    detections: Detections,
    spec: TableSpec | None = None,
    method: LocateMethod | str = LocateMethod.SPHERE,
    off_table_margin: float = 0.03,
    diamond_z: float | None = None,
    same_ball_distance: float | None = None,
    drop_small: bool = True,
) -> LocatedBalls:
    """Map each ball detection to its table centre; drop balls off the table, in pockets, seen twice, or too small
    for a ball there (:func:`too_small`).

    Args:
        camera: the recovered camera.
        detections: detections (diamonds are ignored).
        spec: the table.
        method: ``sphere``, ``contact`` or ``linear``.
        off_table_margin: balls further than this outside the legal centre region [m] are dropped (the
            rest are clamped onto it).
        diamond_z: height of the diamond plane the camera was fitted to [m] (``linear`` only; default the
            spec's).
        same_ball_distance: two detections whose table centres are closer than this [m] are one ball seen
            twice (two balls cannot be closer than a diameter); the less confident is dropped. Default: one
            ball radius, well above the location error and well below the gap of touching balls.
        drop_small: drop detections too small for a ball where they lie (:func:`too_small`).
    """
    spec = spec or TableSpec()
    det = detections[detections.is_ball]
    R = spec.ball_radius
    xy = table_centres(camera, det, spec, method, diamond_z)
    keep = playable(xy, spec, off_table_margin)
    keep[keep] = ~seen_twice(xy[keep], det.confidence[keep], R if same_ball_distance is None else same_ball_distance)
    if drop_small:
        keep[keep] = ~too_small(camera, det.boxes[keep], xy[keep], spec)
    xy = xy[keep]
    xy = (
        np.column_stack([np.clip(xy[:, 0], R, spec.length - R), np.clip(xy[:, 1], R, spec.width - R)])
        if len(xy)
        else np.zeros((0, 2))
    )
    contact = camera.project_table(xy, 0.0) if len(xy) else np.zeros((0, 2))
    return LocatedBalls(det[keep], xy, contact, int((~keep).sum()))


MIN_BALL_SHARE = 0.6
"""A detection whose box is, on both image axes, under this share of the part of a ball predicted visible where it
lies (measured against the photo's median ball) is no ball: a chalk mark, a speck of the cloth, a far reflection. On
150 renders of each set and the real photos whose balls were labelled by eye it drops 27 of the 209 detections on the
fitted tables that box no ball, and 1 of the 2,532 that box one (``benchmarks/ball_size_check.py``)."""

MIN_BALLS_FOR_SHARE = 3
"""Balls needed for the photo's median ball size, against which :func:`too_small` measures."""


def too_small(camera: PinholeCamera, boxes: np.ndarray, xy: np.ndarray, spec: TableSpec) -> np.ndarray:
    """Mask (n,) of ball boxes (n, 4) [px] at table centres (n, 2) [m] too small to be balls: on both axes under
    :data:`MIN_BALL_SHARE` of the ball predicted there (:func:`~pix2pockets.vision.locate.visibility.visible_boxes`:
    what other balls, the cushions and the frame hide of it left out), each axis's share divided by the median over
    the photo's balls of their larger share (a table of the wrong size makes every ball look too small or too big
    alike). None with fewer than :data:`MIN_BALLS_FOR_SHARE` balls."""
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    if len(boxes) < MIN_BALLS_FOR_SHARE:
        return np.zeros(len(boxes), dtype=bool)
    _, seen = visible_parts(camera, xy, spec.ball_radius, spec)
    with np.errstate(invalid="ignore", divide="ignore"):
        share = (boxes[:, 2:] - boxes[:, :2]) / (seen[:, 2:] - seen[:, :2])
    larger = np.max(share, axis=1)
    ok = np.isfinite(larger)
    if ok.sum() < MIN_BALLS_FOR_SHARE:
        return np.zeros(len(boxes), dtype=bool)
    return ok & (larger < MIN_BALL_SHARE * float(np.median(larger[ok])))


def table_centres(
    camera: PinholeCamera,
    detections: Detections,
    spec: TableSpec,
    method: LocateMethod | str = LocateMethod.SPHERE,
    diamond_z: float | None = None,
) -> np.ndarray:
    """Table centres (n, 2) [m] of ball detections (n of them, all balls), NaN where the camera sees none."""
    method = LocateMethod(method)
    if method is LocateMethod.LINEAR:
        return locate_linear(camera, detections.boxes, spec, diamond_z)
    xy = locate_sphere(camera, detections.boxes, spec.ball_radius, spec=spec)
    if method is LocateMethod.CONTACT:
        has = np.all(np.isfinite(detections.contact), axis=1)
        if has.any():
            xy[has] = locate_contact(camera, detections.contact[has])
    return xy


def playable(xy: np.ndarray, spec: TableSpec, off_table_margin: float = 0.03) -> np.ndarray:
    """Mask of table centres (n, 2) [m] on the playing surface (at most ``off_table_margin`` [m] outside the legal
    centre region) and in no pocket."""
    R = spec.ball_radius
    finite = np.all(np.isfinite(xy), axis=1)
    on_table = finite & spec.contains(np.where(finite[:, None], xy, -1e9), margin=R - off_table_margin)
    radii = np.array([p.capture_radius for p in spec.pockets])
    dist = np.linalg.norm(np.where(finite[:, None], xy, 1e9)[:, None, :] - spec.pocket_centres[None], axis=-1)
    return on_table & ~np.any(dist < radii[None], axis=1)


def on_the_table(
    camera: PinholeCamera,
    detections: Detections,
    spec: TableSpec,
    method: LocateMethod | str = LocateMethod.SPHERE,
    off_table_margin: float = 0.03,
    diamond_z: float | None = None,
) -> np.ndarray:
    """Mask (n,) of the detections that are diamonds or balls whose table centre :func:`locate_balls` would keep
    (on the playing surface, in no pocket); every entry of a raw detector's output counts on its own."""
    mask = np.ones(len(detections), dtype=bool)
    balls = np.flatnonzero(detections.is_ball)
    if len(balls):
        xy = table_centres(camera, detections[balls], spec, method, diamond_z)
        mask[balls] = playable(xy, spec, off_table_margin)
    return mask


def seen_twice(positions: np.ndarray, confidence: np.ndarray, min_distance: float) -> np.ndarray:
    """Mask of the detections that repeat a more confident one: centre closer than ``min_distance`` [m]."""
    pos = np.asarray(positions, dtype=float).reshape(-1, 2)
    repeat = np.zeros(len(pos), dtype=bool)
    kept: list[int] = []
    for i in np.argsort(-np.asarray(confidence, dtype=float), kind="stable"):
        if kept and np.min(np.linalg.norm(pos[kept] - pos[i], axis=1)) < min_distance:
            repeat[i] = True
        else:
            kept.append(int(i))
    return repeat


def settle_positions(positions: np.ndarray, spec: TableSpec, iterations: int = 50) -> np.ndarray:
    """Push overlapping ball centres apart (small location errors of touching balls) and keep them on
    the playing surface. Returns positions (n, 2) [m]."""
    pos = np.array(positions, dtype=float).reshape(-1, 2)
    R = spec.ball_radius
    need = 2 * R + 1e-5
    for _ in range(iterations):
        moved = False
        for i in range(len(pos)):
            for j in range(i + 1, len(pos)):
                d = pos[j] - pos[i]
                n = float(np.hypot(*d))
                if n < need:
                    direction = d / n if n > 1e-12 else np.array([1.0, 0.0])
                    push = (need - n) / 2 + 1e-7
                    pos[i] -= direction * push
                    pos[j] += direction * push
                    moved = True
        pos[:, 0] = np.clip(pos[:, 0], R, spec.length - R)
        pos[:, 1] = np.clip(pos[:, 1], R, spec.width - R)
        if not moved:
            break
    return pos

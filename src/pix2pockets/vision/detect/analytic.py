"""Analytic detections: what a perfect detector would report for a camera and a layout.

Diamonds are the projected diamond centres (at :func:`~pix2pockets.vision.table.fit.diamond_height`); ball
boxes are the exact bounding boxes of the projected spheres; contact points are the projected ball-cloth
contact points. Optional Gaussian pixel
noise imitates a real detector. Used as ground truth by tests and the projection-error benchmark.
"""

from __future__ import annotations

import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.table import TableSpec
from pix2pockets.state.layout import TableLayout
from pix2pockets.vision.classes import CLASS_NAMES, DIAMOND_ID
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.locate.balls import sphere_boxes
from pix2pockets.vision.table.fit import diamond_height

DIAMOND_BOX_HALF_PX = 4.0


def standard_views(spec: TableSpec | None = None, image_size: tuple[int, int] = (1280, 720)) -> dict:
    """The projection-error experiment's three cameras: ``top``, ``45`` (degrees) and ``front``.

    All look at the table centre with the head rail (``x = 0``) left or nearest, matching the
    head-rail convention of :mod:`pix2pockets.vision.table.fit`.
    """
    spec = spec or TableSpec()
    w, _ = image_size
    centre = np.array([spec.length / 2, spec.width / 2, 0.0])
    top = PinholeCamera.look_at(centre + np.array([0.0, 0.0, 3.0]), centre, 0.95 * w, image_size)
    # 45 degrees down, from the bottom-left (head) side
    d45 = np.array([-0.55, -0.45, 0.0])
    d45 = d45 / np.linalg.norm(d45)
    eye45 = centre + 3.3 * np.cos(np.pi / 4) * d45 + np.array([0.0, 0.0, 3.3 * np.sin(np.pi / 4)])
    cam45 = PinholeCamera.look_at(eye45, centre, 0.7 * w, image_size)
    # low front view from behind the head rail
    front = PinholeCamera.look_at(np.array([-1.3, spec.width / 2, 1.1]), centre, 0.85 * w, image_size)
    return {"top": top, "45": cam45, "front": front}


def analytic_detections(
    camera: PinholeCamera,
    layout: TableLayout,
    rng: np.random.Generator | None = None,
    box_noise_px: float = 0.0,
    diamond_noise_px: float = 0.0,
) -> Detections:
    """Exact (optionally noisy) detections of ``layout``'s balls and the 18 diamonds seen by ``camera``.

    Detections outside the image are left out. Balls come first (layout order), then diamonds.
    """
    spec = layout.spec
    rng = rng or np.random.default_rng(0)
    R = spec.ball_radius
    centres = np.column_stack([layout.positions, np.full(len(layout), R)])
    boxes = sphere_boxes(camera, centres, R) if len(layout) else np.zeros((0, 4))
    if box_noise_px:
        boxes = boxes + rng.normal(0.0, box_noise_px, boxes.shape)
    contact = camera.project_table(layout.positions, 0.0) if len(layout) else np.zeros((0, 2))
    cls = np.array([CLASS_NAMES.index(b.ball_class.value) for b in layout.balls], dtype=int)
    diamonds = camera.project_table(spec.diamonds, diamond_height(spec))
    if diamond_noise_px:
        diamonds = diamonds + rng.normal(0.0, diamond_noise_px, diamonds.shape)
    diamond_boxes = np.column_stack([diamonds - DIAMOND_BOX_HALF_PX, diamonds + DIAMOND_BOX_HALF_PX])
    det = Detections(
        np.vstack([boxes, diamond_boxes]),
        np.ones(len(boxes) + len(diamond_boxes)),
        np.concatenate([cls, np.full(len(diamond_boxes), DIAMOND_ID)]),
        np.vstack([contact, np.full((len(diamond_boxes), 2), np.nan)]),
    )
    w, h = camera.image_size
    c = det.centres
    inside = (c[:, 0] >= 0) & (c[:, 0] < w) & (c[:, 1] >= 0) & (c[:, 1] < h) & np.all(np.isfinite(c), axis=1)
    return det[inside]


def detections_from_synth_labels(labels: dict, silhouette: bool = False) -> Detections:
    """A perfect detector's output for a synthetic render's label dict (see ``docs/synth.md``).

    Labelled balls give their visible boxes (or their full silhouette boxes with ``silhouette``) and
    contact points; labelled diamonds give their boxes.
    """
    boxes, cls, contact = [], [], []
    for b in labels["balls"]:
        if b["labelled"]:
            box = b["silhouette_box_px"] if silhouette and b.get("silhouette_box_px") else b["box_px"]
            boxes.append(box)
            cls.append(int(b["class_id"]))
            contact.append(b["contact_px"])
    for d in labels["diamonds"]:
        if d["labelled"]:
            boxes.append(d["box_px"])
            cls.append(DIAMOND_ID)
            contact.append([np.nan, np.nan])
    n = len(boxes)
    return Detections(
        np.array(boxes, dtype=float).reshape(-1, 4),
        np.ones(n),
        np.array(cls, dtype=int),
        np.array(contact).reshape(-1, 2),
    )

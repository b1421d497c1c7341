"""The pixel aspect of a photo stretched by an export, read from its balls.

Exports often squash every photo to one size: Roboflow's 640x640 (the paper's dataset, the real ball photos
in ``shared/data``) turns a 16:9 frame's pixels into pixels 0.5625 times as wide as tall. Balls are round,
so their boxes are all stretched alike.
"""

from __future__ import annotations

import numpy as np

EXPORT_ASPECTS = (1.0, 0.5625, 0.75, 4 / 3, 16 / 9)
"""Pixel aspect ratios (width over height of one pixel) of the usual exports: square pixels, and photos of
16:9 or 4:3 (landscape or portrait) stretched to a square, as Roboflow's 640x640."""
SNAP_TOLERANCE = 1.08
"""A measured aspect within this factor of one of :data:`EXPORT_ASPECTS` is taken as that one."""


def pixel_aspect_of_balls(
    boxes: np.ndarray,
    scores: np.ndarray | None = None,
    min_score: float = 0.3,
    min_balls: int = 3,
    tolerance: float = 1.15,
) -> float:
    """Width over height of one pixel, read from ball boxes (n, 4): balls are round, so in a photo stretched
    by an export (a 16:9 frame squashed to 640x640) their boxes are all stretched alike.

    The median box width over height of the boxes scoring at least ``min_score`` (all boxes without
    ``scores``); 1 with fewer than ``min_balls`` of them or within ``tolerance`` of 1 (partly hidden balls and
    the image border cut single boxes).
    """
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    w, h = boxes[:, 2] - boxes[:, 0], boxes[:, 3] - boxes[:, 1]
    ok = (w > 0) & (h > 0)
    if scores is not None:
        ok &= np.asarray(scores, dtype=float).reshape(-1) >= min_score
    if ok.sum() < min_balls:
        return 1.0
    aspect = float(np.median(w[ok] / h[ok]))
    return 1.0 if 1 / tolerance < aspect < tolerance else aspect


def snapped_aspect(aspect: float, tolerance: float = SNAP_TOLERANCE) -> float:
    """``aspect``, or the export aspect (:data:`EXPORT_ASPECTS`) within ``tolerance`` of it."""
    nearest = min(EXPORT_ASPECTS, key=lambda a: abs(np.log(a / aspect)))
    return float(nearest) if abs(np.log(nearest / aspect)) <= np.log(tolerance) else float(aspect)

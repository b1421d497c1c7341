"""The pixel aspect of a photo stretched by an export, read from its balls.

Exports often squash every photo to one size: Roboflow's 640x640 (the paper's dataset, the real ball photos
in ``shared/data``) turns a 16:9 frame's pixels into pixels 0.5625 times as wide as tall. Balls are round,
so their boxes, or else their outlines in the photo, are all stretched alike. The detector reshapes its ball
boxes and cuts the classifier's crops with that aspect, and the table fit tries it first.
"""

from __future__ import annotations

import cv2
import numpy as np

EXPORT_ASPECTS = (1.0, 0.5625, 0.75, 4 / 3, 16 / 9)
"""Pixel aspect ratios (width over height of one pixel) of the usual exports: square pixels, and photos of
16:9 or 4:3 (landscape or portrait) stretched to a square, as Roboflow's 640x640."""
OUTLINE_SQUASH_LIMIT = 0.7
"""Median ball-outline aspect below which a square photo is taken for a squashed 16:9 frame (above its inverse,
a 9:16 one). Shadows and highlights make outlines noisy (a photo with square pixels measures 0.7-1.15), so
milder stretches (4:3 exports) are left alone. Measured with the shipped detector's boxes: photos with square
pixels 1 in 91 below 0.7 (720p and 640 px renders), squashed 720p renders 83 %, the real pub-video exports
25 of 26 (of the photos with three measurable balls)."""
SNAP_TOLERANCE = 1.08
"""A measured aspect within this factor of one of :data:`EXPORT_ASPECTS` is taken as that one."""


def median_box_aspect(
    boxes: np.ndarray, scores: np.ndarray | None = None, min_score: float = 0.3, min_balls: int = 3
) -> float | None:
    """Median width over height of the ball boxes (n, 4) scoring at least ``min_score`` (all boxes without
    ``scores``), or None with fewer than ``min_balls`` of them."""
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    w, h = boxes[:, 2] - boxes[:, 0], boxes[:, 3] - boxes[:, 1]
    ok = (w > 0) & (h > 0)
    if scores is not None:
        ok &= np.asarray(scores, dtype=float).reshape(-1) >= min_score
    return float(np.median(w[ok] / h[ok])) if ok.sum() >= min_balls else None


def pixel_aspect_of_balls(
    boxes: np.ndarray,
    scores: np.ndarray | None = None,
    min_score: float = 0.3,
    min_balls: int = 3,
    tolerance: float = 1.15,
) -> float:
    """Width over height of one pixel, read from ball boxes (n, 4): balls are round, so in a photo stretched
    by an export (a 16:9 frame squashed to 640x640) their boxes are all stretched alike.

    :func:`median_box_aspect`; 1 without enough boxes or within ``tolerance`` of 1 (partly hidden balls and
    the image border cut single boxes).
    """
    aspect = median_box_aspect(boxes, scores, min_score, min_balls)
    return 1.0 if aspect is None or 1 / tolerance < aspect < tolerance else aspect


def snapped_aspect(aspect: float, tolerance: float = SNAP_TOLERANCE) -> float:
    """``aspect``, or the export aspect (:data:`EXPORT_ASPECTS`) within ``tolerance`` of it."""
    nearest = min(EXPORT_ASPECTS, key=lambda a: abs(np.log(a / aspect)))
    return float(nearest) if abs(np.log(nearest / aspect)) <= np.log(tolerance) else float(aspect)


def ball_outline_aspect(image: np.ndarray, box: np.ndarray) -> float:
    """Width over height of one ball's outline in an RGB photo, from its xyxy box [px]; NaN when it cannot be
    measured (near the border, touching another ball, as dull as the cloth).

    The crop around the box centre (2.4 box sides) is compared with the cloth colour (the median of its border
    pixels); the connected region of clearly different pixels at the centre is the ball, and the aspect is
    the ratio of its standard deviations along x and y (exact for an ellipse).
    """
    x0, y0, x1, y1 = np.asarray(box, dtype=float)
    half = 1.2 * max(x1 - x0, y1 - y0)
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    left, right = round(cx - half), round(cx + half)
    top, bottom = round(cy - half), round(cy + half)
    height, width = image.shape[:2]
    if left < 0 or top < 0 or right > width or bottom > height or right - left < 8:
        return float("nan")
    crop = image[top:bottom, left:right].astype(np.float32)
    border = np.concatenate([crop[0], crop[-1], crop[:, 0], crop[:, -1]])
    cloth = np.median(border, axis=0)
    diff = np.sqrt(np.square(crop - cloth).sum(axis=2))
    border_diff = np.sqrt(np.square(border - cloth).sum(axis=1))
    threshold = max(1.5 * np.percentile(border_diff, 90), 0.35 * diff.max())
    _, labels = cv2.connectedComponents((diff > threshold).astype(np.uint8))
    ball = labels[labels.shape[0] // 2, labels.shape[1] // 2]
    if ball == 0:
        return float("nan")
    ys, xs = np.nonzero(labels == ball)
    touches_border = (
        xs.min() == 0 or ys.min() == 0 or xs.max() == labels.shape[1] - 1 or ys.max() == labels.shape[0] - 1
    )
    if len(xs) < 12 or touches_border:
        return float("nan")
    return float(np.sqrt(xs.var() / ys.var()))


def pixel_aspect_of_photo(
    image: np.ndarray,
    boxes: np.ndarray,
    scores: np.ndarray,
    min_score: float = 0.3,
    max_balls: int = 8,
    min_balls: int = 3,
) -> float:
    """Width over height of one pixel of an RGB photo with ball boxes (n, 4) and scores (n,).

    From the boxes (:func:`pixel_aspect_of_balls`) when they show a stretch. Otherwise, for a square photo
    (the shape exports squash to), from the outlines of up to ``max_balls`` confident balls
    (:func:`ball_outline_aspect`, median of at least ``min_balls``): a 16:9 frame squashed to a square (9/16)
    or a 9:16 one (16/9) when the median passes :data:`OUTLINE_SQUASH_LIMIT`; else 1. A detector can keep
    predicting round boxes on a squashed photo.
    """
    aspect = pixel_aspect_of_balls(boxes, scores, min_score)
    height, width = image.shape[:2]
    if aspect != 1.0 or abs(width - height) > 0.01 * max(width, height):
        return aspect
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    scores = np.asarray(scores, dtype=float).reshape(-1)
    best = np.argsort(-scores)[:max_balls]
    best = best[scores[best] >= min_score]
    measured = np.array([ball_outline_aspect(image, boxes[i]) for i in best])
    measured = measured[np.isfinite(measured)]
    if len(measured) < min_balls:
        return 1.0
    median = float(np.median(measured))
    if median < OUTLINE_SQUASH_LIMIT:
        return 9 / 16
    return 16 / 9 if median > 1 / OUTLINE_SQUASH_LIMIT else 1.0


def boxes_in_aspect(boxes: np.ndarray, scores: np.ndarray, aspect: float, min_score: float = 0.3) -> np.ndarray:
    """Ball boxes (n, 4) reshaped so their median width over height (of those scoring ``min_score`` or more)
    is the photo's pixel ``aspect``; each box keeps its centre and area. Unchanged for ``aspect`` 1.

    A detector trained on photos with square pixels draws round boxes around the squashed balls of a
    stretched export, which then miss the labelled (stretched) boxes at strict IoU.
    """
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    if aspect == 1.0 or len(boxes) == 0:  # a photo as the camera took it keeps its boxes
        return boxes
    factor = aspect / (median_box_aspect(boxes, scores, min_score) or 1.0)
    centre = 0.5 * (boxes[:, :2] + boxes[:, 2:])
    half = 0.5 * (boxes[:, 2:] - boxes[:, :2]) * np.array([np.sqrt(factor), 1 / np.sqrt(factor)])
    return np.hstack([centre - half, centre + half])

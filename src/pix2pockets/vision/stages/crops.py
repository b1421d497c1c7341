"""Square, scale-normalised crops around balls: the input of the second-stage ball classifier.

The detector sees the photo scaled to a 640 px long side, where a far ball is 8-12 px wide. The classifier
reads each ball again from the full-resolution photo, scaled so every ball fills the same part of the crop.
"""

from __future__ import annotations

import cv2
import numpy as np

CROP_SIZE = 32
"""Side of a classifier crop [px]."""
CROP_CONTEXT = 1.5
"""Crop side over ball diameter: the ball plus a thin ring of cloth around it."""


def ball_diameters(boxes: np.ndarray, aspect: float = 1.0) -> np.ndarray:
    """Ball diameters [px] from xyxy boxes (n, 4): the mean of width and height, at least 2 px.

    In a photo stretched to pixels of another aspect (``aspect`` = width over height of one pixel) a ball
    is ``aspect`` times as wide as tall; the diameter is then counted in rows (width / aspect and height).
    """
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    return np.maximum(0.5 * ((boxes[:, 2] - boxes[:, 0]) / aspect + (boxes[:, 3] - boxes[:, 1])), 2.0)


def crop_windows(centres: np.ndarray, diameters: np.ndarray, context: float = CROP_CONTEXT) -> tuple[np.ndarray, ...]:
    """Integer crop windows: top-left corners (n, 2) and sides (n,) [px], `context` diameters wide.

    The same rounding as :func:`crop_balls`, so a position inside a crop maps back to the photo exactly.
    """
    centres = np.asarray(centres, dtype=float).reshape(-1, 2)
    diameters = np.asarray(diameters, dtype=float).reshape(-1)
    if len(centres) != len(diameters):
        raise ValueError(f"{len(centres)} centres but {len(diameters)} diameters")
    sides = np.maximum(2, np.round(diameters * context)).astype(int)
    corners = np.round(centres - sides[:, None] / 2).astype(int)
    return corners, sides


def crop_balls(
    image: np.ndarray,
    centres: np.ndarray,
    diameters: np.ndarray,
    size: int = CROP_SIZE,
    context: float = CROP_CONTEXT,
    aspect: float = 1.0,
) -> np.ndarray:
    """Crops (n, size, size, 3) uint8 centred on balls, each `context` ball diameters wide.

    Args:
        image: RGB uint8 (H, W, 3).
        centres: (n, 2) ball centres x, y [px].
        diameters: (n,) ball diameters [px] (rows, in a stretched photo: :func:`ball_diameters`).
        size: crop side [px].
        context: crop side over ball diameter.
        aspect: width over height of one pixel; a crop is then ``aspect`` times as wide as tall in the photo,
            so the ball comes out round, as in an unstretched photo.

    Parts of a crop outside the image repeat the nearest edge pixel. Crop windows: :func:`stretched_windows`.
    """
    windows = stretched_windows(centres, diameters, context, aspect)
    h, w = image.shape[:2]
    out = np.empty((len(windows), size, size, 3), dtype=np.uint8)
    for i, (x0, y0, side_x, side_y) in enumerate(windows):
        xs = np.clip(np.arange(x0, x0 + side_x), 0, w - 1)
        ys = np.clip(np.arange(y0, y0 + side_y), 0, h - 1)
        region = image[ys[:, None], xs[None, :]]
        interp = cv2.INTER_AREA if min(side_x, side_y) > size else cv2.INTER_LINEAR
        out[i] = cv2.resize(region, (size, size), interpolation=interp)
    return out


def stretched_windows(
    centres: np.ndarray, diameters: np.ndarray, context: float = CROP_CONTEXT, aspect: float = 1.0
) -> np.ndarray:
    """Integer crop windows (n, 4): left, top, width, height [px], `context` diameters tall and ``aspect`` times
    as wide (:func:`crop_windows` per axis, the same rounding as :func:`crop_balls`)."""
    corners, sides = crop_windows(centres, diameters, context)
    x_corners, x_sides = corners[:, 0], sides
    if aspect != 1.0:
        x_corners, x_sides = crop_windows(centres, np.asarray(diameters, dtype=float) * aspect, context)
        x_corners = x_corners[:, 0]
    return np.stack([x_corners, corners[:, 1], x_sides, sides], axis=1).reshape(-1, 4)


def crops_of_boxes(image: np.ndarray, boxes: np.ndarray, size: int, aspect: float | None = None) -> np.ndarray:
    """Crops (n, size, size, 3) uint8 of the balls in xyxy boxes (n, 4) [px], as the second-stage ball models read
    them: centred on each box, :data:`CROP_CONTEXT` diameters wide. ``aspect`` (width over height of one pixel)
    is read from the boxes when None (:func:`~pix2pockets.vision.table.pixel_aspect.pixel_aspect_of_balls`), so the
    balls of a photo stretched by an export come out round."""
    from pix2pockets.vision.table.pixel_aspect import pixel_aspect_of_balls

    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    if len(boxes) == 0:
        return np.zeros((0, size, size, 3), dtype=np.uint8)
    aspect = pixel_aspect_of_balls(boxes) if aspect is None else aspect
    centres = 0.5 * (boxes[:, :2] + boxes[:, 2:])
    return crop_balls(image, centres, ball_diameters(boxes, aspect), size, aspect=aspect)

"""The second-stage diamond refiner run through onnxruntime: re-reads each diamond's box from the photo.

The detector finds diamonds on a stride-4 grid. A diamond box is only 4-8 px wide, so a centre off by one pixel
or a side off by two fails IoU 0.5, and the table fit draws its lines through these centres. The refiner looks at
a crop of the full-resolution photo around each detected diamond and returns the diamond's centre to a fraction of
a pixel and its box (a sight seen at a slant is wider than tall). It only moves and resizes boxes: scores and the
set of detections stay the detector's (``docs/detector.md``, "Diamond refiner").

Example:
    >>> refiner = DiamondRefiner.from_default()  # doctest: +SKIP
    >>> diamonds = refiner.refine(image_rgb, raw_diamonds)  # doctest: +SKIP
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from pix2pockets.vision.classes import MIN_DIAMOND_BOX_PX
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.stages.base import CropModel
from pix2pockets.vision.stages.crops import crop_balls, crop_windows

DEFAULT_DIAMOND_REFINER = "diamond-refiner.onnx"
DIAMOND_CROP_SIZE = 32
"""Side of a refiner crop [px]."""
DIAMOND_CROP_CONTEXT = 4.0
"""Crop side over the detected diamond's box side."""
MIN_DIAMOND_CROP_PX = 16.0
"""Smallest crop side in the photo [px] (a 4 px diamond plus room for the detector's centre error)."""
N_OUTPUTS = 4
"""Refiner outputs per crop: the diamond's centre x and y, as fractions of the crop side from its middle, then
its box's width and height as fractions of the crop side."""
OUTPUT_NAME = "diamond_box"
"""Name of the refiner's ONNX output."""
REFINE_MIN_SCORE = 0.15
"""Diamonds the detector scores below this keep their box: refining them too changed no AP on the test
renders (``docs/benchmarks-detector.md``), the pipeline reads only diamonds above 0.25, and they are 60 % of
the raw diamonds, so skipping them cuts the refiner's time by about that much."""


def diamond_crop_sides(boxes: np.ndarray) -> np.ndarray:
    """Crop sides [px] for diamond boxes (n, 4): :data:`DIAMOND_CROP_CONTEXT` box sides, at least
    :data:`MIN_DIAMOND_CROP_PX`."""
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    side = 0.5 * ((boxes[:, 2] - boxes[:, 0]) + (boxes[:, 3] - boxes[:, 1]))
    return np.maximum(DIAMOND_CROP_CONTEXT * side, MIN_DIAMOND_CROP_PX)


def crop_diamonds(
    image: np.ndarray, centres: np.ndarray, sides: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Crops (n, S, S, 3) uint8 of the photo, and their windows: top-left corners (n, 2) and sides (n,) [px]."""
    corners, windows = crop_windows(centres, sides, 1.0)
    return crop_balls(image, centres, sides, DIAMOND_CROP_SIZE, 1.0), corners, windows


def boxes_from_outputs(out: np.ndarray, corners: np.ndarray, sides: np.ndarray) -> np.ndarray:
    """Diamond boxes xyxy (n, 4) [px] from refiner outputs (n, 4) and the crop windows they were read from.

    A centre beyond the crop's edge (never seen in training) is held at the edge; each side is at least
    :data:`~pix2pockets.vision.classes.MIN_DIAMOND_BOX_PX` (the labels' floor) and at most the crop's side.
    """
    out = np.asarray(out, dtype=float).reshape(-1, N_OUTPUTS)
    side = np.asarray(sides, dtype=float)[:, None]
    centre = np.asarray(corners, dtype=float) + side * (0.5 + np.clip(out[:, :2], -0.5, 0.5))
    size = np.maximum(side * np.clip(out[:, 2:], 0.0, 1.0), MIN_DIAMOND_BOX_PX)
    return np.hstack([centre - 0.5 * size, centre + 0.5 * size])


def box_targets(boxes: np.ndarray, corners: np.ndarray, sides: np.ndarray) -> np.ndarray:
    """Refiner targets (n, 4) for labelled diamond boxes xyxy (n, 4) [px] seen in crop windows; the inverse of
    :func:`boxes_from_outputs` (above the size floor)."""
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    side = np.asarray(sides, dtype=float)[:, None]
    centre = 0.5 * (boxes[:, :2] + boxes[:, 2:])
    return np.hstack([(centre - corners) / side - 0.5, (boxes[:, 2:] - boxes[:, :2]) / side])


class DiamondRefiner(CropModel):
    """Refines the boxes of diamond detections from crops of the original photo
    (``pix2pockets train-diamond-refiner``).

    See :class:`~pix2pockets.vision.stages.base.CropModel` for the arguments.
    """

    what = "diamond refiner model"
    file_name = DEFAULT_DIAMOND_REFINER
    output_name = OUTPUT_NAME
    n_outputs = N_OUTPUTS
    fixed_crop_size = DIAMOND_CROP_SIZE

    def boxes(self, image_rgb: np.ndarray, boxes: np.ndarray) -> np.ndarray:
        """Refined boxes (n, 4) [px] of detected diamond boxes (n, 4) [px] in an RGB uint8 photo."""
        boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
        if len(boxes) == 0:
            return np.zeros((0, 4))
        crops, corners, sides = crop_diamonds(image_rgb, 0.5 * (boxes[:, :2] + boxes[:, 2:]), diamond_crop_sides(boxes))
        return boxes_from_outputs(self.run(crops), corners, sides)

    def refine(self, image_rgb: np.ndarray, diamonds: Detections, min_score: float = REFINE_MIN_SCORE) -> Detections:
        """The diamond detections scoring at least `min_score` with refined boxes (clipped to the image); the
        others, and every score, unchanged."""
        todo = diamonds.confidence >= min_score
        boxes = diamonds.boxes.copy()
        h, w = image_rgb.shape[:2]
        boxes[todo] = np.clip(self.boxes(image_rgb, boxes[todo]), 0, [w, h, w, h])
        return replace(diamonds, boxes=boxes)

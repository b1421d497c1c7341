"""The second-stage ball box refiner run through onnxruntime: re-reads each ball's box from the photo.

The detector places a ball on its stride-4 grid of a 640-1024 px image and predicts its size there. A far ball
is 6-10 px wide, so its box is often a pixel or two off in centre and size, and a third of the balls the
detector finds but scores as misses overlap their label at IoU 0.3-0.5 only. The refiner looks at a crop of the
full-resolution photo around each detected ball, two detected diameters wide, and returns the ball's box in
that crop. It moves and resizes boxes; scores and the set of detections stay the detector's
(``docs/detector.md``, "Ball box refiner"). The ball classifier then reads its crops around the refined boxes.

Example:
    >>> refiner = BallRefiner.from_default()  # doctest: +SKIP
    >>> balls = refiner.refine(image_rgb, raw_balls)  # doctest: +SKIP
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.stages.base import CropModel
from pix2pockets.vision.stages.crops import ball_diameters, crop_balls, stretched_windows

DEFAULT_BALL_REFINER = "ball-refiner.onnx"
BALL_REFINE_CROP_SIZE = 32
"""Side of a refiner crop [px]."""
BALL_REFINE_CONTEXT = 2.0
"""Crop side over the detected ball's diameter: room for a centre off by a third of a diameter and a size off by
as much (the detector's 99th percentiles on the test renders)."""
N_OUTPUTS = 4
"""Refiner outputs per crop: the ball's centre x and y, as fractions of the crop's width and height from its
middle, then the box's width and height as fractions of them."""
OUTPUT_NAME = "ball_box"
"""Name of the refiner's ONNX output."""
REFINE_MIN_SCORE = 0.1
"""Balls the detector scores below this keep their box: about 60 % of the raw candidates at the 0.05 floor, never
read by the pipeline (it keeps cue and 8 from 0.15, solids and stripes from 0.3); refining them too changed no AP50
on the 640 px test renders (``docs/benchmarks-detector.md``)."""
MAX_SIZE_CHANGE = 2.0
"""A refined box is kept within this factor of the detector's size per side (outputs never seen in training are
held there)."""


def crop_for_refiner(image: np.ndarray, boxes: np.ndarray, aspect: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Refiner crops (n, S, S, 3) uint8 around ball boxes (n, 4) [px], and their windows (n, 4): left, top, width,
    height [px]. In a photo whose pixels are ``aspect`` times as wide as tall the window is that much wider, so
    the ball comes out round."""
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    centres = 0.5 * (boxes[:, :2] + boxes[:, 2:])
    diameters = ball_diameters(boxes, aspect)
    crops = crop_balls(image, centres, diameters, BALL_REFINE_CROP_SIZE, BALL_REFINE_CONTEXT, aspect)
    return crops, stretched_windows(centres, diameters, BALL_REFINE_CONTEXT, aspect)


def boxes_from_outputs(out: np.ndarray, windows: np.ndarray) -> np.ndarray:
    """Ball boxes xyxy (n, 4) [px] from refiner outputs (n, 4) and the windows they were read from; centres beyond
    the crop's edge are held at the edge, sizes between 2 % and 100 % of the crop."""
    out = np.asarray(out, dtype=float).reshape(-1, N_OUTPUTS)
    windows = np.asarray(windows, dtype=float).reshape(-1, 4)
    centre = windows[:, :2] + windows[:, 2:] * (0.5 + np.clip(out[:, :2], -0.5, 0.5))
    half = 0.5 * windows[:, 2:] * np.clip(out[:, 2:], 0.02, 1.0)
    return np.hstack([centre - half, centre + half])


def box_targets(boxes: np.ndarray, windows: np.ndarray) -> np.ndarray:
    """Refiner targets (n, 4) for labelled ball boxes xyxy (n, 4) [px] seen in crop windows (n, 4); the inverse of
    :func:`boxes_from_outputs`."""
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    windows = np.asarray(windows, dtype=float).reshape(-1, 4)
    centre = 0.5 * (boxes[:, :2] + boxes[:, 2:])
    return np.hstack([(centre - windows[:, :2]) / windows[:, 2:] - 0.5, (boxes[:, 2:] - boxes[:, :2]) / windows[:, 2:]])


class BallRefiner(CropModel):
    """Refines the boxes of ball detections from crops of the original photo (``pix2pockets train-ball-refiner``).

    See :class:`~pix2pockets.vision.stages.base.CropModel` for the arguments.
    """

    what = "ball refiner model"
    file_name = DEFAULT_BALL_REFINER
    output_name = OUTPUT_NAME
    n_outputs = N_OUTPUTS
    fixed_crop_size = BALL_REFINE_CROP_SIZE

    def boxes(self, image_rgb: np.ndarray, boxes: np.ndarray, aspect: float = 1.0) -> np.ndarray:
        """Refined boxes (n, 4) [px] of detected ball boxes (n, 4) [px] in an RGB uint8 photo whose pixels are
        ``aspect`` times as wide as tall."""
        boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
        if len(boxes) == 0:
            return np.zeros((0, 4))
        crops, windows = crop_for_refiner(image_rgb, boxes, aspect)
        refined = boxes_from_outputs(self.run(crops), windows)
        return _limit_size_change(refined, boxes)

    def refine(
        self, image_rgb: np.ndarray, balls: Detections, aspect: float = 1.0, min_score: float = REFINE_MIN_SCORE
    ) -> Detections:
        """The ball detections scoring at least `min_score` with refined boxes (clipped to the image), contact points
        moved with their box's centre; the others, every score, class and the order unchanged."""
        todo = balls.confidence >= min_score
        if not todo.any():
            return balls
        boxes = balls.boxes.copy()
        h, w = image_rgb.shape[:2]
        boxes[todo] = np.clip(self.boxes(image_rgb, boxes[todo], aspect), 0, [w, h, w, h])
        shift = 0.5 * (boxes[:, :2] + boxes[:, 2:]) - balls.centres
        return replace(balls, boxes=boxes, contact=balls.contact + shift)


def _limit_size_change(refined: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """`refined` boxes with each side within :data:`MAX_SIZE_CHANGE` of the `boxes` they came from (same centre)."""
    old = np.maximum(boxes[:, 2:] - boxes[:, :2], 1e-6)
    size = np.clip(refined[:, 2:] - refined[:, :2], old / MAX_SIZE_CHANGE, old * MAX_SIZE_CHANGE)
    centre = 0.5 * (refined[:, :2] + refined[:, 2:])
    return np.hstack([centre - 0.5 * size, centre + 0.5 * size])

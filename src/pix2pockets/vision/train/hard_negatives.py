"""The detector's own false balls on training images, as "no ball" crops for the ball classifier.

Random points and diamonds teach the classifier little about what the detector actually takes for a ball: a
pocket's dark mouth, a cue's tip, chalk on a rail, a reflection. Run over the training renders, the bundled
detector (its post-processing with room for every object ball, :data:`~pix2pockets.pipeline.photo.LOOSE_OBJECT_CAPS`)
scores such things as balls; every ball it keeps from :data:`MIN_SCORE` up that overlaps no labelled ball (box IoU
under :data:`MAX_IOU`) gives a crop cut as the pipeline cuts its balls'
(:func:`~pix2pockets.vision.stages.crops.crop_balls`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pix2pockets.pipeline.photo import LOOSE_OBJECT_CAPS
from pix2pockets.vision.classes import BALL_IDS
from pix2pockets.vision.detect.base import Detector
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.postprocess import box_iou, resolve_ball_classes
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.stages.crops import crop_balls

MIN_SCORE = 0.1
"""Least detection score of a false ball taken as a "no ball" crop."""
MAX_IOU = 0.3
"""A detection overlapping a labelled ball by this much (box IoU) or more is no false ball."""


def false_ball_boxes(detections: Detections, labelled_boxes: np.ndarray) -> np.ndarray:
    """Boxes (m, 4) [px] of the detector's balls (resolved :class:`Detections`) scored :data:`MIN_SCORE` or more that
    overlap none of ``labelled_boxes`` (n, 4) [px] by :data:`MAX_IOU`."""
    balls = detections[detections.is_ball & (detections.confidence >= MIN_SCORE)]
    if not len(balls):
        return np.zeros((0, 4))
    if not len(labelled_boxes):
        return balls.boxes
    return balls.boxes[box_iou(balls.boxes, labelled_boxes).max(axis=1) < MAX_IOU]


def hard_negative_crops(
    sources: Sequence[tuple[LabelledImage, dict[int, int] | None]], detector: Detector, crop_size: int
) -> np.ndarray:
    """Crops (m, S, S, 3) uint8 of the ``detector``'s false balls on labelled images, for the "no ball" class.

    Args:
        sources: labelled images with their class maps (dataset class id -> detector class id; None for a
            ball-only set, all of whose labels are balls).
        detector: gives the raw detections of an RGB image.
        crop_size: crop side [px].
    """
    crops = [np.empty((0, crop_size, crop_size, 3), np.uint8)]
    for item, class_map in sources:
        image = read_image_rgb(item.image_path)
        resolved = resolve_ball_classes(detector.detect(image), caps=LOOSE_OBJECT_CAPS)
        ids = [class_map.get(int(c), -1) if class_map else BALL_IDS[0] for c in item.class_id]
        labelled = item.boxes.reshape(-1, 4)[np.isin(ids, BALL_IDS)]
        boxes = false_ball_boxes(resolved, labelled)
        if len(boxes):
            centres = 0.5 * (boxes[:, :2] + boxes[:, 2:])
            diameters = np.maximum(boxes[:, 2] - boxes[:, 0], boxes[:, 3] - boxes[:, 1])
            crops.append(crop_balls(image, centres, diameters, crop_size))
    return np.concatenate(crops)

"""The detector's false balls on labelled images become "no ball" crops; its true balls do not."""

import cv2
import numpy as np

from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.train.hard_negatives import MIN_SCORE, false_ball_boxes, hard_negative_crops


def _detections(boxes: list, scores: list) -> Detections:
    boxes = np.asarray(boxes, dtype=float)
    return Detections(boxes, np.asarray(scores, dtype=float), np.full(len(boxes), 2), (boxes[:, :2] + boxes[:, 2:]) / 2)


def test_only_confident_detections_off_every_labelled_ball_are_false_balls():
    labelled = np.array([[10.0, 10, 30, 30]])
    det = _detections([[11, 11, 31, 31], [60, 60, 80, 80], [100, 100, 120, 120]], [0.8, 0.4, MIN_SCORE / 2])
    assert false_ball_boxes(det, labelled).tolist() == [[60, 60, 80, 80]]
    assert len(false_ball_boxes(det, np.zeros((0, 4)))) == 2


class _FixedDetector:
    """Reports a ball on the labelled one and one on the pocket-like dark disc beside it."""

    def detect(self, rgb: np.ndarray) -> Detections:
        det = _detections([[20, 20, 44, 44], [80, 20, 104, 44]], [0.9, 0.6])
        return Detections(det.boxes, det.confidence, det.class_id, det.contact, ball_score=np.array([0.9, 0.6]))


def test_hard_negative_crops_are_cut_at_the_false_balls(tmp_path):
    img = np.full((64, 128, 3), (30, 120, 50), np.uint8)
    cv2.circle(img, (32, 32), 12, (235, 235, 230), -1)  # the labelled cue ball
    cv2.circle(img, (92, 32), 12, (5, 5, 5), -1)  # a pocket's mouth
    path = tmp_path / "table.png"
    cv2.imwrite(str(path), cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
    item = LabelledImage(path, np.array([[20.0, 20, 44, 44]]), np.array([0]), np.full((1, 2), np.nan), (128, 64))
    crops = hard_negative_crops([(item, {0: 0, 1: 1, 2: 2, 3: 3, 4: 4})], _FixedDetector(), 32)
    assert crops.shape == (1, 32, 32, 3)
    assert crops[0, 12:20, 12:20].mean() < 20  # the dark disc, not the white ball

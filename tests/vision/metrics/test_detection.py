import numpy as np
import pytest

from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.metrics.detection import (
    GroundTruth,
    average_precision,
    evaluate_class,
    match_image,
    mean_metrics,
)


def _gt(boxes, cls):
    return GroundTruth(np.asarray(boxes, float).reshape(-1, 4), np.asarray(cls, int))


def test_perfect_detections_score_one():
    gt = _gt([[0, 0, 10, 10], [20, 0, 30, 10]], [2, 2])
    det = Detections(gt.boxes, np.array([0.9, 0.8]), gt.class_id)
    m = evaluate_class([det], [gt], 2)
    assert m.precision == m.recall == m.f1 == 1.0
    assert m.ap50 == pytest.approx(1.0) and m.ap50_95 == pytest.approx(1.0)


def test_false_positive_ranked_first_halves_precision_at_first_recall():
    gt = _gt([[0, 0, 10, 10]], [0])
    det = Detections(np.array([[50, 50, 60, 60], [0, 0, 10, 10.0]]), np.array([0.9, 0.8]), np.array([0, 0]))
    m = evaluate_class([det], [gt], 0)
    assert m.precision == 0.5 and m.recall == 1.0
    assert m.ap50 == pytest.approx(0.5)


def test_false_positive_ranked_last_does_not_hurt_ap():
    gt = _gt([[0, 0, 10, 10]], [0])
    det = Detections(np.array([[0, 0, 10, 10], [50, 50, 60, 60.0]]), np.array([0.9, 0.8]), np.array([0, 0]))
    assert evaluate_class([det], [gt], 0).ap50 == pytest.approx(1.0)


def test_wrong_class_is_a_miss():
    gt = _gt([[0, 0, 10, 10]], [0])
    det = Detections(gt.boxes, np.array([0.9]), np.array([1]))
    assert evaluate_class([det], [gt], 0).recall == 0.0
    assert evaluate_class([det], [gt], None).recall == 1.0  # class-agnostic


def test_shifted_box_counts_at_50_not_at_95():
    gt = _gt([[0, 0, 10, 10]], [0])
    det = Detections(np.array([[1, 0, 11, 10.0]]), np.array([0.9]), np.array([0]))  # IoU 9/11 = 0.82
    m = evaluate_class([det], [gt], 0)
    assert m.ap50 == pytest.approx(1.0)
    assert 0.3 < m.ap50_95 < 0.8


def test_duplicate_detection_is_false_positive():
    tp = match_image(
        np.array([[0, 0, 10, 10], [0, 0, 10, 10.0]]), np.array([0.9, 0.8]), np.array([[0, 0, 10, 10.0]]), [0.5]
    )
    assert tp[:, 0].tolist() == [True, False]


def test_half_found_gives_half_ap():
    assert average_precision(np.array([1, 0]), np.array([0.9, 0.5]), 2) == pytest.approx(51 / 101)


def test_no_ground_truth_is_nan_and_skipped_in_mean():
    gt = _gt([[0, 0, 10, 10]], [0])
    det = Detections(gt.boxes, np.array([0.9]), np.array([0]))
    per = {0: evaluate_class([det], [gt], 0), 3: evaluate_class([det], [gt], 3)}
    assert np.isnan(per[3].ap50)
    assert mean_metrics(per)["ap50"] == pytest.approx(1.0)


def test_length_mismatch():
    with pytest.raises(ValueError, match="detection sets"):
        evaluate_class([], [_gt([], [])], 0)

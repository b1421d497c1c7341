import numpy as np
import pytest

from pix2pockets.vision.detections import Detections
from pix2pockets.vision.postprocess import apply_caps, box_iou, class_agnostic_nms, nms_indices, postprocess


def _grid(n: int, cls: int, conf: np.ndarray | None = None, x0: float = 0.0) -> Detections:
    """n non-overlapping 10 px boxes in a row."""
    xs = x0 + 20.0 * np.arange(n)
    boxes = np.stack([xs, np.zeros(n), xs + 10, np.full(n, 10.0)], axis=1)
    conf = np.linspace(0.9, 0.3, n) if conf is None else conf
    return Detections(boxes, conf, np.full(n, cls))


def test_box_iou_known_values():
    a = np.array([[0, 0, 10, 10.0]])
    b = np.array([[0, 0, 10, 10], [5, 0, 15, 10], [20, 20, 30, 30.0]])
    assert np.allclose(box_iou(a, b), [[1.0, 50 / 150, 0.0]])


def test_nms_keeps_best_of_overlapping_pair_and_far_box():
    boxes = np.array([[0, 0, 10, 10], [1, 0, 11, 10], [50, 50, 60, 60.0]])
    keep = nms_indices(boxes, np.array([0.5, 0.9, 0.7]), 0.5)
    assert keep.tolist() == [1, 2]


def test_class_agnostic_nms_merges_one_ball_seen_as_two_classes():
    det = Detections(np.array([[0, 0, 10, 10], [0.5, 0.5, 10.5, 10.5]]), np.array([0.6, 0.8]), np.array([2, 3]))
    out = class_agnostic_nms(det)
    assert len(out) == 1 and out.class_id[0] == 3


def test_touching_balls_survive_nms():
    det = Detections(np.array([[0, 0, 10, 10], [10, 0, 20, 10.0]]), np.array([0.9, 0.8]), np.array([2, 2]))
    assert len(class_agnostic_nms(det)) == 2


@pytest.mark.parametrize(("cls", "n", "cap"), [(0, 3, 1), (1, 2, 1), (2, 9, 7), (3, 8, 7), (4, 25, 18)])
def test_caps_keep_most_confident(cls, n, cap):
    conf = np.random.default_rng(cls).permutation(np.linspace(0.1, 0.95, n))
    det = _grid(n, cls, conf)
    out = apply_caps(det)
    assert len(out) == cap
    assert np.allclose(np.sort(out.confidence), np.sort(conf)[-cap:])


def test_postprocess_mixed_scene_counts():
    parts = [
        _grid(3, 0, x0=0),
        _grid(2, 1, x0=1000),
        _grid(10, 2, x0=2000),
        _grid(4, 3, x0=3000),
        _grid(20, 4, x0=4000),
    ]
    out = postprocess(Detections.concatenate(parts))
    assert np.bincount(out.class_id, minlength=5).tolist() == [1, 1, 7, 4, 18]
    assert np.all(np.diff(out.confidence) <= 0)


def test_postprocess_empty():
    assert len(postprocess(Detections.empty())) == 0


@pytest.mark.parametrize("iou", [-0.1, 1.5])
def test_bad_nms_threshold(iou):
    with pytest.raises(ValueError, match="iou_threshold"):
        nms_indices(np.zeros((1, 4)), np.ones(1), iou)


def test_bad_caps():
    with pytest.raises(ValueError, match="caps"):
        apply_caps(_grid(2, 0), caps=(-1, 1, 7, 7, 18))
    with pytest.raises(ValueError, match="no cap"):
        apply_caps(_grid(2, 4), caps=(1, 1))

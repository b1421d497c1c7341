"""The committed ONNX detector loads and finds balls on a freshly rendered synthetic image."""

import numpy as np
import pytest

from pix2pockets.vision.detect.base import Detector
from pix2pockets.vision.detect.onnx_detector import OnnxDetector, OnnxDetectorConfig, default_model_path
from pix2pockets.vision.detect.postprocess import box_iou, postprocess
from pix2pockets.vision.stages.ball_numbers import BallNumberReader
from pix2pockets.vision.stages.ball_refiner import BallRefiner

_needs_model = pytest.mark.skipif(
    not default_model_path().exists(), reason="no trained detector committed at data/models/detector.onnx yet"
)


def _render(seed, size):
    try:
        from pix2pockets.synth.renderer import render
    except ImportError:
        from pix2pockets.synth.render import render
    return render(seed, size)


@_needs_model
def test_model_loads_and_is_a_detector():
    det = OnnxDetector.from_default(OnnxDetectorConfig(threads=1))
    assert isinstance(det, Detector)
    assert len(det.detect(np.zeros((90, 160, 3), np.uint8))) < 20  # a black image holds few objects


@_needs_model
def test_detects_balls_on_fresh_render():
    pytest.importorskip("pix2pockets.synth")
    rend = _render((4243, 0), (640, 360))
    balls = [b for b in rend.labels["balls"] if b["labelled"] and b["visible_fraction"] > 0.8]
    assert len(balls) >= 3  # a scene with balls to find (12 clearly visible)
    gt = np.array([b["box_px"] for b in balls], float)
    det = postprocess(OnnxDetector.from_default().detect(rend.image))
    found = det[det.is_ball & (det.confidence > 0.3)]
    assert len(found) > 0
    hit = box_iou(gt, found.boxes).max(axis=1) > 0.3
    assert hit.mean() >= 0.6, f"found {hit.sum()} of {len(gt)} balls"
    ok = np.isfinite(found.contact).all(axis=1)
    assert ok.any()


def test_input_size_follows_the_photo_up_to_the_maximum():
    cfg = OnnxDetectorConfig()
    assert [cfg.long_side(n) for n in (300, 640, 800, 1000, 1280, 1920)] == [640, 640, 800, 992, 1024, 1024]
    fixed = OnnxDetectorConfig(input_size=640, max_input_size=640)
    assert fixed.long_side(1920) == 640
    with pytest.raises(ValueError, match="max_input_size"):
        OnnxDetectorConfig(max_input_size=1000)


@_needs_model
def test_the_shipped_ball_refiner_tightens_the_ball_boxes_of_renders():
    pytest.importorskip("pix2pockets.synth")

    if not BallRefiner.default_path().exists():
        pytest.skip("no ball refiner committed")
    with_refiner = OnnxDetector.from_default()
    assert with_refiner.ball_refiner is not None
    without = OnnxDetector(default_model_path(), classifier=with_refiner.classifier)
    refined, raw = [], []
    for seed in (4243, 4244, 4245):  # pooled: single renders vary either way
        rend = _render((seed, 0), (960, 540))
        gt = np.array([b["box_px"] for b in rend.labels["balls"] if b["labelled"] and b["visible_fraction"] > 0.8])
        for det, ious in ((with_refiner, refined), (without, raw)):
            balls = det.detect_balls(rend.image)
            ious.extend(box_iou(gt, balls[balls.confidence > 0.3].boxes).max(axis=1))
    refined, raw = np.array(refined), np.array(raw)
    assert refined.mean() > raw.mean() + 0.02
    assert (refined > 0.75).sum() > (raw > 0.75).sum()


@_needs_model
def test_the_number_reader_reweighs_ball_classes_and_leaves_the_rest():
    pytest.importorskip("pix2pockets.synth")

    if not BallNumberReader.default_path().exists():
        pytest.skip("no ball-number reader committed")
    with_numbers = OnnxDetector.from_default()
    assert with_numbers.number_reader is not None
    stages = with_numbers.classifier, with_numbers.diamond_refiner, with_numbers.ball_refiner
    without = OnnxDetector(default_model_path(), None, *stages)
    image = _render((4246, 0), (640, 360)).image
    a, b = with_numbers.detect(image), without.detect(image)
    np.testing.assert_allclose(a[a.is_diamond].boxes, b[b.is_diamond].boxes)
    balls_a, balls_b = a[a.is_ball], b[b.is_ball]
    assert 0 < len(balls_a) == len(balls_b)  # the same entries with their own scores ...
    np.testing.assert_allclose(np.sort(balls_a.own_score), np.sort(balls_b.own_score))
    assert np.all((balls_a.confidence >= 0) & (balls_a.confidence <= 1))  # ... weighed otherwise
    assert not np.allclose(np.sort(balls_a.confidence), np.sort(balls_b.confidence))

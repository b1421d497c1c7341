"""The ball box refiner's crop geometry, output decoding, and the shipped model on a fresh render."""

import numpy as np
import pytest

from pix2pockets.vision.classes import BALL_IDS
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.postprocess import paired_box_iou
from pix2pockets.vision.stages.ball_classifier import BallClassifier
from pix2pockets.vision.stages.ball_refiner import (
    BALL_REFINE_CONTEXT,
    BALL_REFINE_CROP_SIZE,
    MAX_SIZE_CHANGE,
    BallRefiner,
    box_targets,
    boxes_from_outputs,
    crop_for_refiner,
)


def test_outputs_decode_to_photo_pixels_and_targets_invert_them():
    windows = np.array([[100, 50, 40, 40], [7, 9, 30, 20]])
    out = np.array([[0.25, -0.125, 0.5, 0.4], [0.0, 0.1, 0.3, 0.6]])
    boxes = boxes_from_outputs(out, windows)
    assert np.allclose(boxes[0], [130 - 10, 65 - 8, 130 + 10, 65 + 8])
    assert np.allclose(box_targets(boxes, windows), out)
    wild = boxes_from_outputs(np.array([[3.0, -9.0, 5.0, -1.0]]), windows[:1])
    assert np.allclose(0.5 * (wild[0, :2] + wild[0, 2:]), [140, 50])  # centre held at the crop's edge
    assert np.all(wild[0, 2:] - wild[0, :2] <= 40)


def test_crops_are_two_diameters_wide_and_stretched_with_the_pixels():
    image = np.zeros((100, 200, 3), np.uint8)
    crops, windows = crop_for_refiner(image, np.array([[90, 40, 100, 50.0]]))
    assert crops.shape == (1, BALL_REFINE_CROP_SIZE, BALL_REFINE_CROP_SIZE, 3)
    assert windows[0].tolist() == [85, 35, 20, 20]
    # pixels half as wide as tall: a ball 5 px wide and 10 px tall; its window is 10 x 20 px
    _, windows = crop_for_refiner(image, np.array([[92.5, 40, 97.5, 50.0]]), aspect=0.5)
    assert windows[0, 2:].tolist() == [10, 20] and BALL_REFINE_CONTEXT == 2.0


def test_refined_targets_find_a_drawn_disc():
    """Targets from :func:`box_targets` point at the disc in the crop the windows describe."""
    image = np.full((120, 160, 3), 30, np.uint8)
    yy, xx = np.mgrid[:120, :160]
    image[(xx - 70.5) ** 2 + (yy - 60.5) ** 2 <= 36] = 240  # a disc 12 px wide at (70.5, 60.5)
    truth = np.array([[64.5, 54.5, 76.5, 66.5]])
    crops, windows = crop_for_refiner(image, np.array([[66, 57, 80, 71.0]]))  # off-centre, too large
    t = box_targets(truth, windows)[0]
    cx, cy = (t[:2] + 0.5) * BALL_REFINE_CROP_SIZE
    assert crops[0, int(cy), int(cx), 0] == 240
    assert np.allclose(boxes_from_outputs(t[None], windows), truth)


class _FixedOutputs:
    """Stands in for an onnxruntime session: every crop's ball is centred at (+0.1, 0) crop sides, and 0.5 x 2 crop
    sides large (wider than the refiner may make it)."""

    def run(self, _names, feeds):
        n = len(next(iter(feeds.values())))
        return [np.tile([0.1, 0.0, 0.5, 2.0], (n, 1))]


def _stub_refiner() -> BallRefiner:
    refiner = BallRefiner.__new__(BallRefiner)
    refiner.session, refiner.input_name = _FixedOutputs(), "crops"
    return refiner


def test_refine_moves_confident_balls_and_their_contacts_and_keeps_faint_ones():
    boxes = np.array([[40, 40, 50, 50], [80, 60, 90, 70], [0, 0, 10, 10.0]])
    balls = Detections(boxes, [0.9, 0.05, 0.5], [2, 3, 0], [[45, 50], [85, 70], [5, 10.0]])
    out = _stub_refiner().refine(np.zeros((100, 120, 3), np.uint8), balls)
    # ball 0: window 20 px from (35, 35): centre (47, 45), 10 px wide, height held at twice the detector's 10 px
    assert np.allclose(out.boxes[0], [42, 35, 52, 55])
    assert np.allclose(out.contact[0], [47, 50])
    assert np.array_equal(out.boxes[1], boxes[1]) and np.array_equal(out.contact[1], [85, 70])  # below 0.1
    assert out.boxes[2].min() >= 0  # clipped to the image
    assert np.array_equal(out.confidence, balls.confidence) and np.array_equal(out.class_id, balls.class_id)


def test_missing_or_wrong_model_is_a_clear_error(tmp_path):
    with pytest.raises(ValueError, match="not found"):
        BallRefiner(tmp_path / "nope.onnx")

    if BallClassifier.default_path().exists():  # a crop model, but not a ball refiner
        with pytest.raises(ValueError, match="not a ball refiner"):
            BallRefiner(BallClassifier.default_path())


@pytest.mark.skipif(not BallRefiner.default_path().exists(), reason="no ball refiner committed")
def test_shipped_refiner_moves_jittered_boxes_back_onto_the_balls():
    pytest.importorskip("pix2pockets.synth")
    from pix2pockets.synth.renderer import render

    rend = render((5155, 0), (960, 540))
    balls = [b for b in rend.labels["balls"] if b["labelled"] and b["visible_fraction"] > 0.9]
    if len(balls) < 4:
        pytest.skip("render holds fewer than 4 clearly visible balls")
    truth = np.array([b["box_px"] for b in balls], float)
    rng = np.random.default_rng(0)
    diameter = (truth[:, 2:] - truth[:, :2]).mean(axis=1, keepdims=True)
    centre = 0.5 * (truth[:, :2] + truth[:, 2:]) + rng.uniform(-0.15, 0.15, (len(truth), 2)) * diameter
    half = 0.5 * diameter * rng.uniform(0.75, 1.3, (len(truth), 2))
    jittered = np.hstack([centre - half, centre + half])
    n = len(truth)
    dets = Detections(jittered, np.linspace(0.9, 0.5, n), np.full(n, BALL_IDS[0]), centre + np.array([0, 2.0]))
    refined = BallRefiner.from_default().refine(rend.image, dets)

    def ious(boxes: np.ndarray) -> np.ndarray:
        return paired_box_iou(boxes, truth)

    assert np.median(ious(refined.boxes)) > max(0.8, np.median(ious(jittered)) + 0.1)
    assert np.array_equal(refined.confidence, dets.confidence) and np.array_equal(refined.class_id, dets.class_id)
    assert np.allclose(refined.contact - refined.centres, dets.contact - dets.centres)  # contacts move along
    assert np.all(refined.boxes[:, 2:] - refined.boxes[:, :2] <= MAX_SIZE_CHANGE * (2 * half) + 1e-9)

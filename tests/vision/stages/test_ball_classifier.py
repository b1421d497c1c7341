"""The second-stage ball classifier: score fusion, and the shipped model on a fresh render."""

import numpy as np
import pytest

from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.postprocess import postprocess
from pix2pockets.vision.stages.ball_classifier import (
    IN_VIEW_ABSENT_ODDS,
    BallClassifier,
    classified_balls,
)
from pix2pockets.vision.stages.diamond_refiner import DiamondRefiner


def _balls(n: int, conf: float = 0.9) -> Detections:
    boxes = np.array([[10.0 + 30 * i, 10.0, 30.0 + 30 * i, 30.0] for i in range(n)]).reshape(n, 4)
    return Detections(boxes, np.full(n, conf), np.zeros(n, int), boxes[:, :2] + [10.0, 20.0])


def test_one_entry_per_ball_and_class_scored_by_both_stages():
    heat = np.array([[0.8, 0.0, 0.1, 0.1]])
    probs = np.array([[0.7, 0.0, 0.0, 0.2, 0.1]])
    det = classified_balls(_balls(1), heat, probs, conf_threshold=0.01)
    assert sorted(det.class_id.tolist()) == [0, 3]  # black and solid score 0
    own = det.own_score[det.class_id == 0][0]
    assert own == pytest.approx(0.9 * np.sqrt(0.7 * 0.8))
    odds = own / (1 - own)  # a lone cue ball: the cue ball is usually in view, so a little above its own score
    assert det.confidence[det.class_id == 0][0] == pytest.approx(odds / (IN_VIEW_ABSENT_ODDS + odds))
    assert np.all(det.contact == [[20.0, 30.0], [20.0, 30.0]])
    assert det.ball_score.tolist() == [0.9, 0.9]  # each entry keeps its ball's "any ball" score
    assert postprocess(det).class_id.tolist() == [0]


def test_classifier_overrules_a_wrong_head_and_no_ball_lowers_every_class():
    heat = np.array([[0.5, 0.0, 0.0, 0.5], [0.5, 0.0, 0.0, 0.5]])
    probs = np.array([[0.05, 0.0, 0.0, 0.95, 0.0], [0.05, 0.0, 0.0, 0.15, 0.8]])
    det = postprocess(classified_balls(_balls(2), heat, probs))
    assert det.class_id.tolist() == [3, 3]
    assert det.confidence[0] > 2 * det.confidence[1]


def test_two_cue_like_balls_share_the_cue_and_keep_their_own_scores():
    heat = np.array([[0.9, 0.0, 0.0, 0.1], [0.9, 0.0, 0.0, 0.1], [0.1, 0.0, 0.0, 0.9]])
    probs = np.array([[0.9, 0.0, 0.0, 0.1, 0.0], [0.9, 0.0, 0.0, 0.1, 0.0], [0.1, 0.0, 0.0, 0.9, 0.0]])
    det = classified_balls(_balls(3), heat, probs, conf_threshold=0.01)
    cue = det.class_id == 0
    alone = classified_balls(_balls(1), heat[:1], probs[:1], conf_threshold=0.01)
    own = 0.9 * 0.9
    assert own < alone.confidence[alone.class_id == 0][0] < 1  # no rival: the cue ball is usually in view
    assert np.all(det.own_score[cue][:2] == pytest.approx(own))
    assert det.confidence[cue][0] == pytest.approx(det.confidence[cue][1])
    assert np.all(det.confidence[cue][:2] < 0.6 * own)  # the two rivals share it
    stripes = det.class_id == 3
    np.testing.assert_allclose(det.confidence[stripes], det.own_score[stripes])  # up to 7 stripes: not weighed


def test_empty_and_threshold():
    assert len(classified_balls(_balls(0), np.zeros((0, 4)), np.zeros((0, 5)))) == 0
    det = classified_balls(_balls(1, conf=0.1), np.full((1, 4), 0.25), np.full((1, 5), 0.2), conf_threshold=0.2)
    assert len(det) == 0


def test_missing_or_wrong_model_is_a_clear_error(tmp_path):
    with pytest.raises(ValueError, match="not found"):
        BallClassifier(tmp_path / "nope.onnx")
    bad = tmp_path / "bad.onnx"
    bad.write_bytes(b"not a model")
    with pytest.raises(ValueError, match="cannot load"):
        BallClassifier(bad)

    if DiamondRefiner.default_path().exists():  # the same crops in, but another kind of model
        with pytest.raises(ValueError, match="not a ball classifier"):
            BallClassifier(DiamondRefiner.default_path())


@pytest.mark.skipif(not BallClassifier.default_path().exists(), reason="no ball classifier committed")
def test_shipped_classifier_tells_ball_classes_apart_on_a_fresh_render():
    pytest.importorskip("pix2pockets.synth")
    from pix2pockets.synth.renderer import render
    from pix2pockets.vision.classes import CLASS_NAMES

    rend = render((5155, 0), (960, 540))
    balls = [b for b in rend.labels["balls"] if b["labelled"] and b["visible_fraction"] > 0.9]
    if len(balls) < 4:
        pytest.skip("render holds fewer than 4 clearly visible balls")
    boxes = np.array([b["box_px"] for b in balls], float)
    truth = np.array([CLASS_NAMES.index(b["class"]) for b in balls])
    probs = BallClassifier.from_default().classify(rend.image, boxes)
    assert probs.shape == (len(balls), 5)
    assert np.allclose(probs.sum(axis=1), 1.0, atol=1e-4)
    assert (probs.argmax(axis=1) == truth).mean() >= 0.6
    assert probs[:, 4].mean() < 0.5  # balls are not read as "no ball"


def test_ball_numbers_weigh_every_class_across_the_table():
    heat = np.array([[0.0, 0.0, 0.5, 0.5], [0.0, 0.0, 0.0, 1.0]])
    probs = np.array([[0.0, 0.0, 0.5, 0.5, 0.0], [0.0, 0.0, 0.0, 1.0, 0.0]])
    numbers = np.full((2, 16), 0.01)
    numbers[0, [5, 13]] = 0.43  # ball 0 is the orange 5 or 13; ball 1 is clearly the 13
    numbers[1, 13] = 0.85
    plain = classified_balls(_balls(2), heat, probs, conf_threshold=0.01)
    weighed = classified_balls(_balls(2), heat, probs, conf_threshold=0.01, number_probs=numbers)
    np.testing.assert_allclose(weighed.own_score, plain.own_score)
    first = weighed.boxes[:, 0] == weighed.boxes[:, 0].min()
    solid, stripe = (weighed.confidence[first & (weighed.class_id == k)][0] for k in (2, 3))
    assert solid > 2 * stripe
    assert postprocess(weighed).class_id[np.argmin(postprocess(weighed).boxes[:, 0])] == 2


def test_balls_that_read_alike_are_not_weighed_by_number():
    n = 7  # seven red pub balls: all read as the 3, no numbers to go by
    heat = np.tile([0.0, 0.0, 0.8, 0.2], (n, 1))
    probs = np.tile([0.0, 0.0, 0.8, 0.2, 0.0], (n, 1))
    numbers = np.full((n, 16), 0.01)
    numbers[:, 3] = 0.85
    plain = classified_balls(_balls(n), heat, probs, conf_threshold=0.01)
    read = classified_balls(_balls(n), heat, probs, conf_threshold=0.01, number_probs=numbers)
    np.testing.assert_allclose(read.confidence, plain.confidence)

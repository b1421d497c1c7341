import numpy as np
import pytest

from pix2pockets.vision import CLASS_NAMES, Detections


def make() -> Detections:
    return Detections(
        np.array([[0, 0, 10, 10], [5, 5, 15, 15], [20, 20, 22, 22.0]]), np.array([0.9, 0.4, 0.7]), np.array([0, 2, 4])
    )


def test_mask_indexing():
    det = make()
    sub = det[det.confidence > 0.5]
    assert len(sub) == 2
    assert sub.class_names == ["cue", "dot"]
    assert det[det.is_diamond].boxes.tolist() == [[20, 20, 22, 22]]
    assert det.is_ball.tolist() == [True, True, False]


def test_to_list_and_concat():
    det = make()
    items = det.to_list()
    assert items[0]["class"] == "cue" and "contact_px" not in items[0]
    assert len(Detections.concatenate([det, det])) == 6
    assert len(Detections.empty()) == 0


def test_own_score_defaults_to_confidence_and_follows_selection():
    det = make()
    np.testing.assert_array_equal(det.own_score, det.confidence)
    assert "own_score" not in det.to_list()[0]
    weighed = Detections(det.boxes, [0.3, 0.4, 0.7], det.class_id, own_score=[0.9, 0.4, 0.7])
    assert weighed[weighed.is_ball].own_score.tolist() == [0.9, 0.4]
    both = Detections.concatenate([det, weighed])
    assert both.own_score.tolist() == [0.9, 0.4, 0.7, 0.9, 0.4, 0.7]
    assert weighed.to_list()[0]["own_score"] == 0.9 and "own_score" not in weighed.to_list()[1]


def test_ball_score_is_unknown_unless_given_and_follows_selection():
    det = make()
    assert np.isnan(det.ball_score).all() and "ball_score" not in det.to_list()[0]
    scored = Detections(det.boxes, det.confidence, det.class_id, ball_score=[0.8, 0.6, np.nan])
    assert scored[scored.is_ball].ball_score.tolist() == [0.8, 0.6]
    both = Detections.concatenate([det, scored])
    np.testing.assert_array_equal(both.ball_score, [np.nan, np.nan, np.nan, 0.8, 0.6, np.nan])
    items = scored.to_list()
    assert items[0]["ball_score"] == 0.8 and "ball_score" not in items[2]


def test_class_order():
    assert CLASS_NAMES == ("cue", "black", "solid", "stripe", "dot")


def test_bad_lengths():
    with pytest.raises(ValueError, match="differ in length"):
        Detections(np.zeros((2, 4)), np.zeros(1), np.zeros(2))
    with pytest.raises(ValueError, match="own_score 1"):
        Detections(np.zeros((2, 4)), np.zeros(2), np.zeros(2), own_score=np.zeros(1))
    with pytest.raises(ValueError, match="ball_score 3"):
        Detections(np.zeros((2, 4)), np.zeros(2), np.zeros(2), ball_score=np.zeros(3))
    with pytest.raises(ValueError, match="class ids"):
        Detections(np.zeros((1, 4)), np.zeros(1), np.array([7]))


def test_scaled_moves_boxes_and_contacts_only():
    det = Detections(
        np.array([[10.0, 20.0, 30.0, 40.0]]), np.array([0.9]), np.array([0]), contact=np.array([[20.0, 39.0]]),
        data={"number_probs": np.full((1, 16), 1 / 16)}, pixel_aspect=0.5,
    )  # fmt: skip
    big = det.scaled(2.0, 0.5)
    assert big.pixel_aspect == pytest.approx(2.0)  # a round ball's box, 0.5 as wide as tall, is now twice as wide
    np.testing.assert_allclose(big.boxes, [[20.0, 10.0, 60.0, 20.0]])
    np.testing.assert_allclose(big.contact, [[40.0, 19.5]])
    np.testing.assert_allclose(big.confidence, det.confidence)
    np.testing.assert_allclose(big.data["number_probs"], det.data["number_probs"])

import numpy as np
import pytest

from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.postprocess import (
    apply_caps,
    at_most_one_posterior,
    box_iou,
    class_agnostic_nms,
    nms_indices,
    postprocess,
    resolve_ball_classes,
    share_inside,
)


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


def test_share_inside_is_the_part_of_each_box_within_the_other():
    small = np.array([[2, 2, 6, 6.0], [8, 0, 12, 10]])
    big = np.array([[0, 0, 10, 10.0]])
    assert np.allclose(share_inside(small, big), [[1.0], [0.5]])
    assert np.allclose(share_inside(big, small), [[0.16, 0.2]])  # the big box is mostly outside either


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


def _ball(x: float) -> list[float]:
    return [x, 0.0, x + 10.0, 10.0]


def test_resolve_keeps_a_faint_cue_that_paper_nms_loses():
    # ball A: stripe 0.67 and cue 0.5 (every head fires); ball B: a clear solid
    det = Detections(np.array([_ball(0), _ball(0.5), _ball(100)]), np.array([0.67, 0.5, 0.9]), np.array([3, 0, 2]))
    assert 0 not in postprocess(det).class_id.tolist()  # the paper's NMS keeps only 'stripe' for ball A
    out = resolve_ball_classes(det)
    assert sorted(out.class_id.tolist()) == [0, 2]
    cue = out[out.class_id == 0]
    assert cue.confidence[0] == pytest.approx(0.5)


def test_resolve_gives_cue_to_the_clearest_ball_only_once():
    # ball A is mostly cue, ball B has some cue score but is mostly stripe
    det = Detections(np.array([_ball(0), _ball(100), _ball(100.5)]), np.array([0.8, 0.6, 0.9]), np.array([0, 0, 3]))
    out = resolve_ball_classes(det)
    assert len(out) == 2
    assert out.class_id[np.argmin(out.boxes[:, 0])] == 0
    assert out.class_id[np.argmax(out.boxes[:, 0])] == 3


def test_resolve_passes_diamonds_and_handles_no_balls():
    diamonds = Detections(np.array([_ball(0), _ball(50)]), np.array([0.9, 0.8]), np.array([4, 4]))
    assert resolve_ball_classes(diamonds).class_id.tolist() == [4, 4]
    assert len(resolve_ball_classes(Detections.empty())) == 0


def test_resolve_gives_cue_by_class_evidence_not_by_detection_confidence():
    # ball A: half hidden by the cue stick, found with 0.36, all of it cue; ball B: an open stripe seen from its
    # white pole, found with 0.45 as cue but with a real stripe score too
    boxes = np.array([_ball(0), _ball(0.5), _ball(100), _ball(100.5)])
    det = Detections(boxes, np.array([0.36, 0.05, 0.45, 0.18]), np.array([0, 3, 0, 3]))
    out = resolve_ball_classes(det)
    assert out.class_id[np.argmin(out.boxes[:, 0])] == 0
    assert out.class_id[np.argmax(out.boxes[:, 0])] == 3


def test_a_faint_entry_that_is_only_a_cue_does_not_out_claim_a_clear_cue_ball():
    # ball A: a clear cue ball (cue 0.5) with a little stripe score; B: a pocket's rim scoring only as a cue (0.27)
    boxes = np.array([_ball(0), _ball(0.5), _ball(100)])
    det = Detections(boxes, np.array([0.5, 0.1, 0.27]), np.array([0, 3, 0]))
    out = resolve_ball_classes(det)
    assert out.class_id[np.argmin(out.boxes[:, 0])] == 0
    assert out.class_id[np.argmax(out.boxes[:, 0])] != 0


def test_a_doubtful_ball_claims_the_cue_only_when_no_sure_ball_does():
    det = Detections(np.array([_ball(0), _ball(100)]), np.array([0.2, 0.9]), np.array([0, 2]))
    assert resolve_ball_classes(det).class_id.tolist().count(0) == 1
    sure = Detections(np.array([_ball(0), _ball(100), _ball(100.5)]), np.array([0.2, 0.5, 0.4]), np.array([0, 0, 3]))
    out = resolve_ball_classes(sure)
    assert out.class_id[np.argmax(out.boxes[:, 0])] == 0  # the sure ball (0.5 cue vs 0.4 stripe) wins


def test_a_clear_eight_is_not_taken_for_a_faint_cue():
    # one ball, clearly the 8 (0.61) with a faint cue score (0.12) and a stripe score; no cue ball in view:
    # claimed cue first, it would be the cue and the 8 would go to a ball with next to no 8 score
    boxes = np.array([_ball(0), _ball(0.5), _ball(1.0), _ball(100), _ball(100.5)])
    det = Detections(boxes, np.array([0.61, 0.12, 0.18, 0.9, 0.05]), np.array([1, 0, 3, 2, 1]))
    out = resolve_ball_classes(det)
    assert out.class_id[np.argmin(out.boxes[:, 0])] == 1
    assert out.class_id[np.argmax(out.boxes[:, 0])] == 2
    # a clear cue ball beside it still takes the cue
    with_cue = Detections.concatenate([det, Detections(np.array([_ball(200)]), np.array([0.8]), np.array([0]))])
    out = resolve_ball_classes(with_cue)
    assert out.class_id[np.argsort(out.boxes[:, 0])].tolist() == [1, 2, 0]


def test_a_plain_stripe_with_a_trace_of_cue_does_not_take_the_cue_from_a_faint_cue_ball():
    # ball A: a stripe (0.37) the cue head barely fires on (0.07); ball B: a faint cue ball by the player's tip (0.2)
    boxes = np.array([_ball(0), _ball(0.5), _ball(100)])
    det = Detections(boxes, np.array([0.37, 0.07, 0.2]), np.array([3, 0, 0]))
    out = resolve_ball_classes(det)
    assert out.class_id[np.argmin(out.boxes[:, 0])] == 3
    assert out.class_id[np.argmax(out.boxes[:, 0])] == 0
    # with a real cue score the sure ball still out-claims the faint one
    det = Detections(boxes, np.array([0.37, 0.3, 0.2]), np.array([3, 0, 0]))
    out = resolve_ball_classes(det)
    assert out.class_id[np.argmin(out.boxes[:, 0])] == 0


def test_at_most_one_posterior_keeps_a_lone_ball_and_splits_between_rivals():
    lone = at_most_one_posterior(np.array([0.7, 0.0, 0.02]))
    assert lone[0] > 0.69 and lone[1] == 0.0  # no rival: about its own score (the rest is "no cue in view")
    rivals = at_most_one_posterior(np.array([0.7, 0.7]))
    assert rivals[0] == pytest.approx(rivals[1]) and rivals.sum() < 0.9 and rivals[0] < 0.5
    assert at_most_one_posterior(np.array([0.999999, 0.1]))[0] > 0.99
    np.testing.assert_allclose(at_most_one_posterior(np.array([1.0, 0.5])), [1.0, 0.0])
    assert len(at_most_one_posterior(np.zeros(0))) == 0


def test_at_most_one_posterior_absent_odds_weighs_the_not_in_view_case():
    lone = np.array([0.6, 0.01])
    usually_there = at_most_one_posterior(lone, absent_odds=0.25)
    assert usually_there[0] > 0.8 > at_most_one_posterior(lone)[0]
    assert usually_there.sum() < 1  # some chance stays with "not in view"
    with pytest.raises(ValueError, match="absent_odds"):
        at_most_one_posterior(lone, absent_odds=0.0)


def test_balls_are_classed_by_their_own_scores():
    boxes = np.array([_ball(0), _ball(0.5), _ball(100), _ball(100.5)])
    cls = np.array([0, 3, 0, 3])
    own = np.array([0.5, 0.4, 0.6, 0.9])  # ball 1 is more clearly the cue (0.5 of 0.9) than ball 2 (0.6 of 1.5)
    weighed = np.array([0.2, 0.4, 0.3, 0.9])  # image-level cue chances a detector may report instead
    plain = resolve_ball_classes(Detections(boxes, own, cls))
    out = resolve_ball_classes(Detections(boxes, weighed, cls, own_score=own))
    assert out.class_id.tolist() == plain.class_id.tolist()
    np.testing.assert_allclose(out.confidence, plain.confidence)
    assert out.class_id[np.argmin(out.boxes[:, 0])] == 0


def test_resolved_cue_confidence_drops_when_another_ball_is_as_cue_like():
    alone = Detections(np.array([_ball(0), _ball(100)]), np.array([0.6, 0.9]), np.array([0, 2]))
    rival = Detections(np.array([_ball(0), _ball(100), _ball(100.5)]), np.array([0.6, 0.9, 0.6]), np.array([0, 2, 0]))
    c_alone = resolve_ball_classes(alone)
    c_rival = resolve_ball_classes(rival)
    assert c_alone.confidence[c_alone.class_id == 0][0] > c_rival.confidence[c_rival.class_id == 0][0]


def test_solid_or_stripe_follows_the_table_wide_scores():
    boxes = np.array([_ball(0), _ball(0.5), _ball(100)])
    cls = np.array([2, 3, 2])
    own = np.array([0.45, 0.5, 0.9])  # ball 1 looks a little more like a stripe on its own
    weighed = np.array([0.7, 0.2, 0.9])  # but its stripe number is taken elsewhere on the table
    plain = resolve_ball_classes(Detections(boxes, own, cls))
    out = resolve_ball_classes(Detections(boxes, weighed, cls, own_score=own))
    first = np.argmin(out.boxes[:, 0])
    assert plain.class_id[np.argmin(plain.boxes[:, 0])] == 3
    assert out.class_id[first] == 2
    assert out.confidence[first] == pytest.approx(0.7)


def test_a_resolved_ball_keeps_the_best_ball_score_of_its_group():
    boxes = np.array([_ball(0), _ball(0.5), _ball(100), _ball(200)])
    det = Detections(boxes, [0.6, 0.3, 0.5, 0.4], [2, 3, 2, 3], ball_score=[0.5, 0.7, 0.4, np.nan])
    out = resolve_ball_classes(det)
    by_x = out.ball_score[np.argsort(out.boxes[:, 0])]
    np.testing.assert_array_equal(by_x, [0.7, 0.4, np.nan])

"""The paper's post-processing (section 6.1): class-agnostic NMS, then per-class caps by confidence.

A ball cannot be two classes at once and a table holds at most 1 cue, 1 black, 7 solids, 7 stripes and
18 diamonds, so overlapping detections of different classes are merged by NMS and surplus low-confidence
detections of a class are dropped. Pure numpy.

Example:
    >>> import numpy as np
    >>> from pix2pockets.vision.detect.detections import Detections
    >>> det = Detections(np.array([[0, 0, 10, 10], [1, 1, 11, 11.0]]), np.array([0.9, 0.8]), np.array([0, 1]))
    >>> len(postprocess(det))
    1
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from pix2pockets.vision.classes import DETECTION_CAPS, ONE_PER_TABLE
from pix2pockets.vision.detect.detections import Detections

DEFAULT_NMS_IOU = 0.5


def _area(boxes: np.ndarray) -> np.ndarray:
    """Areas of boxes, xyxy in the last axis."""
    return np.prod(np.clip(boxes[..., 2:] - boxes[..., :2], 0, None), axis=-1)


def _intersection(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Intersection areas of boxes ``a`` and ``b``, xyxy in the last axis, other axes broadcast."""
    return _area(np.concatenate([np.maximum(a[..., :2], b[..., :2]), np.minimum(a[..., 2:], b[..., 2:])], axis=-1))


def paired_box_iou(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """IoU of boxes ``a`` and ``b`` paired element by element: xyxy in the last axis, other axes broadcast."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    inter = _intersection(a, b)
    union = _area(a) + _area(b) - inter
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(union > 0, inter / union, 0.0)


def box_iou(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Pairwise IoU of boxes ``a`` (n, 4) and ``b`` (m, 4), xyxy [px]; returns (n, m)."""
    a = np.asarray(a, dtype=float).reshape(-1, 4)
    b = np.asarray(b, dtype=float).reshape(-1, 4)
    return paired_box_iou(a[:, None, :], b[None, :, :])


def share_inside(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Share of each box of ``a`` (n, 4) that lies inside each box of ``b`` (m, 4), xyxy [px]; returns (n, m)."""
    a = np.asarray(a, dtype=float).reshape(-1, 1, 4)
    b = np.asarray(b, dtype=float).reshape(1, -1, 4)
    area = _area(a)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(area > 0, _intersection(a, b) / area, 0.0)


def nms_indices(boxes: np.ndarray, scores: np.ndarray, iou_threshold: float = DEFAULT_NMS_IOU) -> np.ndarray:
    """Greedy non-maximum suppression; returns kept indices, highest score first.

    Raises:
        ValueError: if ``iou_threshold`` is outside [0, 1].
    """
    if not 0.0 <= iou_threshold <= 1.0:
        raise ValueError(f"iou_threshold must be in [0, 1], got {iou_threshold}")
    order = np.argsort(-np.asarray(scores, dtype=float), kind="stable")
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    keep: list[int] = []
    while order.size:
        i = order[0]
        keep.append(int(i))
        if order.size == 1:
            break
        ious = box_iou(boxes[i : i + 1], boxes[order[1:]])[0]
        order = order[1:][ious <= iou_threshold]
    return np.asarray(keep, dtype=int)


def class_agnostic_nms(det: Detections, iou_threshold: float = DEFAULT_NMS_IOU) -> Detections:
    """NMS over all classes together, so one ball keeps only its most confident class."""
    return det[nms_indices(det.boxes, det.confidence, iou_threshold)]


def apply_caps(det: Detections, caps: Sequence[int] = DETECTION_CAPS) -> Detections:
    """Keep at most ``caps[c]`` detections of each class ``c``, the most confident ones.

    Raises:
        ValueError: if a cap is negative or a class id has no cap.
    """
    caps = tuple(int(c) for c in caps)
    if any(c < 0 for c in caps):
        raise ValueError(f"caps must be >= 0, got {caps}")
    if len(det) and det.class_id.max() >= len(caps):
        raise ValueError(f"class id {det.class_id.max()} has no cap (caps {caps})")
    order = np.argsort(-det.confidence, kind="stable")
    seen = np.zeros(len(caps), dtype=int)
    keep = []
    for i in order:
        k = det.class_id[i]
        if seen[k] < caps[k]:
            seen[k] += 1
            keep.append(i)
    return det[np.asarray(keep, dtype=int)]


def postprocess(
    det: Detections, iou_threshold: float = DEFAULT_NMS_IOU, caps: Sequence[int] = DETECTION_CAPS
) -> Detections:
    """Class-agnostic NMS, then per-class caps (paper section 6.1); result sorted by confidence."""
    return apply_caps(class_agnostic_nms(det, iou_threshold), caps)


CLAIM_MIN_SCORE = 0.25
"""Balls whose best class score is below this claim the cue or the 8 only when no surer ball does."""
CLAIM_CLASS_SCORE = 0.1
"""A sure ball claims the cue or the 8 by its share of that class only where its score for the class reaches this;
below it, it claims as a faint ball of that class would (a ball that is plainly a stripe, with a cue score of 0.07,
does not take the cue from a faint cue ball by the player's tip)."""
CLAIM_SCORE_POWER = 0.5
"""A ball's claim on the cue or the 8 is its share of that class times its score to this power: a faint entry
that scores only as a cue (a pocket's rim, a cue's tip) does not out-claim a clear cue ball that also scores a little
as a stripe, while a half-hidden cue ball still out-claims an open stripe."""


def at_most_one_posterior(scores: np.ndarray, absent_odds: float = 1.0) -> np.ndarray:
    """Chance that each of one image's balls is the ball of a kind a table holds at most once (cue, 8).

    Read each ball's score c_i for the kind as the chance that it is there and is that ball, independently of
    the others. Under "at most one" ball i is it with probability o_i / (a + sum_j o_j), odds o = c / (1 - c),
    where ``absent_odds`` a weighs the "not in view" case (1: as likely as one ball's even odds; below 1: the
    kind is usually in the photo). With a = 1 a ball with no rival keeps about its own score and never more;
    balls that look alike share the chance, so a stripe seen from its white pole scores low beside a clear
    cue ball.
    """
    if not absent_odds > 0:
        raise ValueError(f"absent_odds must be > 0, got {absent_odds}")
    c = np.clip(np.asarray(scores, dtype=float), 0.0, 1.0)
    certain = c >= 1.0
    if certain.any():  # the limit of infinite odds: the certain balls share the kind
        return certain / certain.sum()
    odds = c / (1.0 - c)
    return odds / (absent_odds + odds.sum())


def resolve_ball_classes(
    det: Detections, iou_threshold: float = DEFAULT_NMS_IOU, caps: Sequence[int] = DETECTION_CAPS
) -> Detections:
    """Class-aware post-processing for the product pipeline (ours, not the paper's).

    The paper's NMS keeps each ball's single most confident class, so when every class head fires on the
    cue ball (cue 0.5, stripe 0.67, say) the table loses its cue ball. Here overlapping ball detections are
    grouped into one ball with a score per class; the cue and the 8 are then given to the ball that is most
    clearly each, once each and the clearest claim first (a ball that is plainly the 8 is not taken for a faint cue
    when the cue ball is out of view), and every other ball takes the better of solid and stripe. Diamonds pass through;
    finally the usual caps apply.

    "Most clearly" is the class's share of the ball's class scores, weighed by the square root of that class's
    score (:data:`CLAIM_SCORE_POWER`), among balls whose best score is at least :data:`CLAIM_MIN_SCORE`: which
    ball is the cue is a question of class evidence, and a cue ball half hidden by the cue stick is found with less
    confidence than an open stripe seen from its white pole (doubtful balls only get a class when no sure ball
    claims it; a sure ball whose score for the class is under :data:`CLAIM_CLASS_SCORE` claims it as a faint ball of
    that class would). On the 720p test renders the share lifted cue AP50 from 71 to 82 over ranking by score
    (``docs/benchmarks-detector.md``); the weight lifts blackball renders' cue AP50 from 94.0 to 95.0. The chosen
    cue ball's confidence is then its :func:`at_most_one_posterior` (cue AP50 +1 to +2 on the test renders).

    Balls are grouped, and the cue and the 8 claimed, by each entry's ``own_score``: a detector that reports
    the cue and the 8 as image-level chances (:func:`pix2pockets.vision.stages.ball_classifier.classified_balls`) is
    resolved as one that does not. Solid or stripe, and that score, come from each entry's confidence, which
    such a detector may have weighed across the table by the balls' numbers
    (:mod:`pix2pockets.vision.stages.number_posterior`; stripes and solids AP50 after +1 to +2 on the validation
    renders); for other detectors the two scores are the same. Each resolved ball keeps the best ``ball_score``
    of its group (NaN when the detector gives none). ``caps`` are the most balls of each class kept (looser caps
    let a later step rename the object balls, as :mod:`pix2pockets.vision.stages.ball_colours` does).
    """
    balls, diamonds = det[det.is_ball], det[det.is_diamond]
    if not len(balls):
        return postprocess(det, iou_threshold, caps)
    used = np.zeros(len(balls), dtype=bool)
    leaders, scores, table_scores, ball_scores = [], [], [], []
    own = balls.own_score
    for i in np.argsort(-own, kind="stable"):
        if used[i]:
            continue
        members = np.flatnonzero((box_iou(balls.boxes[i : i + 1], balls.boxes)[0] >= iou_threshold) & ~used)
        used[members] = True
        per_class, per_class_table = np.zeros(4), np.zeros(4)
        np.maximum.at(per_class, balls.class_id[members], own[members])
        np.maximum.at(per_class_table, balls.class_id[members], balls.confidence[members])
        leaders.append(i)
        scores.append(per_class)
        table_scores.append(per_class_table)
        known = balls.ball_score[members][np.isfinite(balls.ball_score[members])]
        ball_scores.append(known.max() if len(known) else np.nan)
    S = np.array(scores)
    T = np.array(table_scores)
    best = np.maximum(S.max(axis=1), 1e-9)
    assigned = np.full(len(S), -1)
    share = S / np.maximum(S.sum(axis=1, keepdims=True), 1e-9)
    sure = S.max(axis=1) >= CLAIM_MIN_SCORE
    claims = np.stack(
        [
            np.where(
                sure & (S[:, k] >= CLAIM_CLASS_SCORE),
                share[:, k] * S[:, k] ** CLAIM_SCORE_POWER,
                0.1 * np.where(sure, S[:, k], S[:, k] * S[:, k] / best),
            )
            for k in ONE_PER_TABLE
        ],
        axis=1,
    )
    for _ in ONE_PER_TABLE:  # the clearest claim first: each class to one ball, each ball to one class
        j, c = np.unravel_index(int(np.argmax(claims)), claims.shape)
        if claims[j, c] <= 0:
            break
        assigned[j] = ONE_PER_TABLE[c]
        claims[j, :], claims[:, c] = -1.0, -1.0
    rest = assigned < 0
    assigned[rest] = 2 + np.argmax(T[rest, 2:], axis=1)
    conf = np.where(assigned >= 2, T[np.arange(len(S)), assigned], S[np.arange(len(S)), assigned])
    conf = np.where(conf > 0, conf, S.max(axis=1))
    conf[assigned == 0] = at_most_one_posterior(S[:, 0])[assigned == 0]
    idx = np.asarray(leaders, dtype=int)
    resolved = Detections(
        balls.boxes[idx],
        conf,
        assigned,
        balls.contact[idx],
        ball_score=np.array(ball_scores),
        data={key: value[idx] for key, value in balls.data.items()},
        pixel_aspect=balls.pixel_aspect,
    )
    return postprocess(Detections.concatenate([resolved, diamonds]), iou_threshold, caps)

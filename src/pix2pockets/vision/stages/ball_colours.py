"""Red and yellow balls: which ball set a photo shows, and each object ball's group in a blackball set.

The detector names balls cue, black, solid or stripe: a UK blackball set's reds and yellows are "solids" to it. Their
colours tell them apart without a model: each object ball's inner disc is read in HSV, its coloured pixels (enough
saturation and light) sorted into red (hue within :data:`RED_HUE` of 0), yellow (hue in :data:`YELLOW_HUES`, the
orange-yellow of a yellow ball under warm light included) and other. A table whose coloured object balls are
nearly all red or yellow, with both colours present and no clear stripes, holds a blackball set
(:func:`read_ball_set`); :func:`blackball_classes` then gives every red ball the solid class and every yellow ball
the stripe class (:mod:`pix2pockets.state.ball_set`: reds play as solids, yellows as stripes).

Hues are OpenCV's (0-180 for 0-360 degrees).
"""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np

from pix2pockets.state.ball_set import BallSet
from pix2pockets.vision.classes import CLASS_NAMES
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.postprocess import share_inside

BLACK_ID = CLASS_NAMES.index("black")
SOLID_ID = CLASS_NAMES.index("solid")
STRIPE_ID = CLASS_NAMES.index("stripe")
RED_HUE = 9
"""Largest hue distance from pure red of a red pixel (OpenCV units, 2 degrees each)."""
YELLOW_HUES = (11, 38)
"""Hues of yellow pixels (orange-yellow to lemon)."""
MIN_SATURATION = 70
MIN_VALUE = 40
INNER = 0.6
"""Share of the box's half-size read: the ball's middle, without the cloth around it."""
MIN_COLOURED = 0.25
"""Share of a ball's inner pixels that must be coloured for its colour to count (cue and black are not)."""
MAJORITY = 0.6
"""Share of a ball's coloured pixels one colour needs to name it."""
BLACKBALL_SHARE = 0.85
"""Share of the coloured object balls, each weighed by its detection score, that must be red or yellow for a blackball
set: a chalked cue tip, a pocket cap or a hand on the cloth is a faint "ball" of another colour and weighs little."""
MIN_COLOURED_BALLS = 3
"""Coloured object balls a photo needs before its set is read from them."""
AMERICAN_SAME_COLOUR = 4
"""Most balls of an American set that read as one of red or yellow: more of one colour is a blackball set."""
MIN_SET_SCORE = 0.2
"""Only object balls the detector is at least this sure of tell the set (faint ones are often not balls)."""
STRIPE_EVIDENCE = 0.6
"""A ball the detector calls a stripe at least this surely, neither red nor yellow, marks an American set."""
RED_YELLOW_STRIPE_EVIDENCE = 0.7
"""A red or yellow ball the detector calls a stripe at least this surely (an 11 or a 9) marks an American set (the
reds and yellows of 30 real pub frames reach 0.54 at most)."""

MAX_BLACK_SCORE = 190.0
"""A ball that is not red is taken for an unfound black when its :func:`black_scores` is below this (blacks in the
labelled pub frames: 84-202, median 140; yellows 168-365, median 304)."""

BLACKER_THAN_YELLOWS = 0.8
"""A ball read as yellow is taken for an unfound black only when its :func:`black_scores` is below this share of the
median of the photo's other yellows (at least :data:`MIN_OTHER_YELLOWS` of them): a yellow in shadow is dark, but
about as dark as the yellows beside it."""
MIN_OTHER_YELLOWS = 2

SURE_BLACK = 0.5
"""A black the detector is this sure of stays the black."""
MIN_BLACK_SCORE = 0.15
"""Least detection score of a ball counted among one colour's balls when one too many of them hides the black (the
pipeline keeps a black from this score up; fainter ones are mostly pockets)."""
BLACK_CANDIDATE_SCORE = 0.25
"""Least detection score of a ball that may be taken for an unfound black."""
PART_OF_BALL = 0.6
"""A box with at least this share inside another ball's box is a part of that ball (a black mirroring a window can be
boxed twice: whole, and its dark half alone)."""

RED, YELLOW, OTHER, NONE = 0, 1, 2, 3
"""Colours :func:`ball_colours` returns (``NONE``: too few coloured pixels, e.g. the cue ball or the black)."""
BALL_COLOUR = "ball_colour"
"""``Detections.data`` key of the colours :func:`blackball_classes` read."""


def _ring(rgb: np.ndarray, box: np.ndarray, inner: float, outer: float) -> np.ndarray:
    """HSV pixels (m, 3) of a ball's box between ``inner`` and ``outer`` shares of its radius."""
    x1, y1, x2, y2 = box
    h, w = rgb.shape[:2]
    cx, cy = (x1 + x2) / 2, (y1 + y2) / 2
    r = min(x2 - x1, y2 - y1) / 2
    if r < 1:
        return np.zeros((0, 3), np.uint8)
    a, b = max(int(cx - outer * r), 0), max(int(cy - outer * r), 0)
    patch = rgb[b : min(int(np.ceil(cy + outer * r)) + 1, h), a : min(int(np.ceil(cx + outer * r)) + 1, w)]
    if patch.size == 0:
        return np.zeros((0, 3), np.uint8)
    yy, xx = np.mgrid[b : b + patch.shape[0], a : a + patch.shape[1]]
    d2 = (xx + 0.5 - cx) ** 2 + (yy + 0.5 - cy) ** 2
    keep = (d2 <= (outer * r) ** 2) & (d2 >= (inner * r) ** 2)
    return cv2.cvtColor(np.ascontiguousarray(patch), cv2.COLOR_RGB2HSV)[keep]


def ball_colours(rgb: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """Each ball's colour (n,): :data:`RED`, :data:`YELLOW`, :data:`OTHER` or :data:`NONE`, from its inner disc.

    Args:
        rgb: the photo, RGB uint8 (H, W, 3).
        boxes: ball boxes ``x1, y1, x2, y2`` [px] (n, 4).
    """
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    out = np.full(len(boxes), NONE)
    for k, box in enumerate(boxes):
        hsv = _ring(rgb, box, 0.0, INNER)
        if not len(hsv):
            continue
        coloured = hsv[(hsv[:, 1] >= MIN_SATURATION) & (hsv[:, 2] >= MIN_VALUE)]
        if len(coloured) < max(3, MIN_COLOURED * len(hsv)):
            continue
        hue = coloured[:, 0].astype(int)
        red = np.minimum(hue, 180 - hue) <= RED_HUE
        yellow = (hue >= YELLOW_HUES[0]) & (hue <= YELLOW_HUES[1])
        shares = np.array([red.mean(), yellow.mean()])
        best = int(np.argmax(shares))
        out[k] = best if shares[best] >= MAJORITY else OTHER
    return out


def black_scores(rgb: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """How black each ball looks (n,), lower is blacker: the dark quarter of its outer ring's brightness plus half
    its middle's saturation (HSV, 0-255). A black ball that mirrors a window keeps a dark rim and a pale middle;
    a yellow is bright and saturated throughout."""
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    out = np.full(len(boxes), np.inf)
    for k, box in enumerate(boxes):
        ring, middle = _ring(rgb, box, 0.55, 0.85), _ring(rgb, box, 0.0, INNER)
        if len(ring) and len(middle):
            out[k] = float(np.percentile(ring[:, 2], 25) + np.median(middle[:, 1]) / 2)
    return out


def _object_balls(det: Detections) -> np.ndarray:
    return np.flatnonzero(det.is_ball & np.isin(det.class_id, (SOLID_ID, STRIPE_ID)))


def read_ball_set(rgb: np.ndarray, det: Detections) -> BallSet:
    """The ball set of a photo from its resolved detections (one class per ball).

    Blackball when at least :data:`MIN_COLOURED_BALLS` object balls (of score :data:`MIN_SET_SCORE` or more) are
    coloured, at least :data:`BLACKBALL_SHARE` of them (weighed by their scores) red or yellow with both colours
    present (or more of one than an American set has, :data:`AMERICAN_SAME_COLOUR`), and no ball is a sure stripe
    (:data:`STRIPE_EVIDENCE`, :data:`RED_YELLOW_STRIPE_EVIDENCE` for a red or yellow one); American otherwise (the
    default for too few coloured balls).
    """
    objects = _object_balls(det)
    objects = objects[det.confidence[objects] >= MIN_SET_SCORE]
    colours = ball_colours(rgb, det.boxes[objects])
    coloured = colours != NONE
    if coloured.sum() < MIN_COLOURED_BALLS:
        return BallSet.AMERICAN
    score = det.confidence[objects]
    red_yellow = np.isin(colours, (RED, YELLOW))
    red_yellow_share = score[red_yellow].sum() / score[coloured].sum()
    both = (colours == RED).any() and (colours == YELLOW).any()
    # an American set has at most four red-ish (3, 7, 11, 15) and four yellow-ish balls (1, 9 and orange 5, 13)
    one_colour = max((colours == RED).sum(), (colours == YELLOW).sum()) > AMERICAN_SAME_COLOUR
    stripe_floor = np.where(red_yellow, RED_YELLOW_STRIPE_EVIDENCE, STRIPE_EVIDENCE)
    sure_stripes = (det.class_id[objects] == STRIPE_ID) & (score >= stripe_floor) & coloured
    if red_yellow_share >= BLACKBALL_SHARE and (both or one_colour) and not sure_stripes.any():
        return BallSet.BLACKBALL
    return BallSet.AMERICAN


def _blacker_than_yellows(
    rgb: np.ndarray,
    det: Detections,
    objects: np.ndarray,
    colours: np.ndarray,
    candidates: np.ndarray,
    scores: np.ndarray,
) -> np.ndarray:
    """Which black candidates (indices into ``det``, their :func:`black_scores` ``scores``) may be the black: all
    but the yellow ones no darker than :data:`BLACKER_THAN_YELLOWS` of the photo's other yellows."""
    yellows = objects[colours == YELLOW]
    yellow_scores = black_scores(rgb, det.boxes[yellows])
    ok = np.ones(len(candidates), dtype=bool)
    for k, (cand, score) in enumerate(zip(candidates, scores, strict=True)):
        if cand not in yellows:
            continue
        others = yellow_scores[(yellows != cand) & np.isfinite(yellow_scores)]
        ok[k] = len(others) >= MIN_OTHER_YELLOWS and score < BLACKER_THAN_YELLOWS * float(np.median(others))
    return ok


def unfound_black(
    rgb: np.ndarray, det: Detections, objects: np.ndarray, colours: np.ndarray, blacks: np.ndarray
) -> int | None:
    """The black of a blackball set the detector is unsure of (an index into ``det``), or None.

    In this order: where one colour counts more than 7 balls (of score :data:`MIN_BLACK_SCORE` or more), the blackest
    of them (a black mirroring the room can look yellow throughout), or the detector's own unsure black where it is
    blacker still or holds that ball's box (:func:`_whole_black`); else the detector's own unsure black when it looks
    black (:func:`black_scores` under :data:`MAX_BLACK_SCORE`, score :data:`BLACK_CANDIDATE_SCORE` or more); else the
    blackest yellow or colourless ball (under :data:`MAX_BLACK_SCORE`, score :data:`BLACK_CANDIDATE_SCORE` or more:
    fainter ones are often pockets), a yellow one only when clearly darker than at least :data:`MIN_OTHER_YELLOWS`
    other yellows (:data:`BLACKER_THAN_YELLOWS`). A ball of another clear colour (blue chalk on a cue's tip) is none.

    Args:
        rgb: the photo, RGB uint8 (H, W, 3).
        det: the resolved detections.
        objects: indices of the object balls (solid or stripe) in ``det``; ``colours`` (their :func:`ball_colours`).
        blacks: indices of the detector's blacks.
    """
    for colour in (RED, YELLOW):
        same = objects[(colours == colour) & (det.confidence[objects] >= MIN_BLACK_SCORE)]
        if len(same) > 7:  # one too many of a colour: the black is among them, or it is the detector's unsure one
            return _whole_black(rgb, det, same, blacks[det.confidence[blacks] >= MIN_BLACK_SCORE])
    own = blacks[det.confidence[blacks] >= BLACK_CANDIDATE_SCORE]
    own_scores = black_scores(rgb, det.boxes[own])
    if len(own) and own_scores.min() < MAX_BLACK_SCORE:
        return int(own[int(np.argmin(own_scores))])
    candidates = objects[np.isin(colours, (YELLOW, NONE)) & (det.confidence[objects] >= BLACK_CANDIDATE_SCORE)]
    scores = black_scores(rgb, det.boxes[candidates])
    scores[~_blacker_than_yellows(rgb, det, objects, colours, candidates, scores)] = np.inf
    if len(candidates) and scores.min() < MAX_BLACK_SCORE:
        return int(candidates[int(np.argmin(scores))])
    return None


def _whole_black(rgb: np.ndarray, det: Detections, same: np.ndarray, blacks: np.ndarray) -> int:
    """The black where one colour counts one ball too many (indices ``same`` into ``det``): the blackest of them
    (:func:`black_scores`), or of the detector's own unsure ``blacks`` where one of those is blacker still, or the
    detector's black that holds the chosen ball's box (:data:`PART_OF_BALL`: the chosen box is part of it)."""
    scores = black_scores(rgb, det.boxes[same])
    pick = int(same[int(np.argmin(scores))])
    if not len(blacks):
        return pick
    holders = blacks[share_inside(det.boxes[pick], det.boxes[blacks])[0] >= PART_OF_BALL]
    if len(holders):
        return int(holders[int(np.argmax(det.confidence[holders]))])
    own_scores = black_scores(rgb, det.boxes[blacks])
    return int(blacks[int(np.argmin(own_scores))]) if own_scores.min() < scores.min() else pick


def blackball_classes(rgb: np.ndarray, det: Detections) -> Detections:
    """The detections with every red object ball classed solid and every yellow one stripe (a blackball set's
    reds and yellows); balls of no clear colour keep their class. Numbers read by the detector are dropped
    (blackball balls carry none); ``data[BALL_COLOUR]`` holds each object ball's colour (:data:`NONE` for the
    others).

    The black is chosen by :func:`unfound_black` unless the detector is sure of one (:data:`SURE_BLACK`); an
    object ball boxed within the chosen black's box (:data:`PART_OF_BALL`) is a part of it and is dropped.
    """
    objects = _object_balls(det)
    colours = ball_colours(rgb, det.boxes[objects])
    class_id = det.class_id.copy()
    class_id[objects[colours == RED]] = SOLID_ID
    class_id[objects[colours == YELLOW]] = STRIPE_ID
    blacks = np.flatnonzero(det.is_ball & (det.class_id == BLACK_ID))
    keep = np.ones(len(det), dtype=bool)
    if not np.any(det.confidence[blacks] >= SURE_BLACK):
        black = unfound_black(rgb, det, objects, colours, blacks)
        if black is not None:
            class_id[blacks] = STRIPE_ID  # unsure blacks that lose play as object balls
            class_id[black] = BLACK_ID
            parts = share_inside(det.boxes[objects], det.boxes[black])[:, 0] >= PART_OF_BALL
            keep[objects[parts & (objects != black)]] = False  # a part of the black boxed on its own
    colour = np.full(len(det), NONE)
    colour[objects] = colours
    # a red or yellow ball's class is its colour: its score is the detector's evidence of a ball there
    confidence = det.confidence.copy()
    named = objects[(colours == RED) | (colours == YELLOW)]
    confidence[named] = np.fmax(confidence[named], det.ball_score[named])
    data = {k: v for k, v in det.data.items() if k != "number_probs"}
    classed = replace(det, class_id=class_id, confidence=confidence, data={**data, BALL_COLOUR: colour})
    return classed if keep.all() else classed[keep]

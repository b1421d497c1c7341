"""Reading a blackball set from the balls' colours, and naming its reds, yellows and black."""

from __future__ import annotations

import cv2
import numpy as np

from pix2pockets.state.ball_set import BallSet
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.stages.ball_colours import (
    BLACK_ID,
    MAX_BLACK_SCORE,
    NONE,
    OTHER,
    RED,
    SOLID_ID,
    STRIPE_ID,
    YELLOW,
    ball_colours,
    black_scores,
    blackball_classes,
    read_ball_set,
)

CLOTH = (30, 120, 50)
COLOURS = {
    "red": (150, 25, 30),
    "yellow": (235, 170, 30),
    "blue": (30, 60, 200),
    "purple": (110, 40, 150),
    "green": (20, 140, 60),
    "white": (235, 235, 230),
    "black": (20, 20, 22),
}


def table_photo(balls: list[str], radius: int = 12) -> tuple[np.ndarray, np.ndarray]:
    """Balls of the named colours in a row on a green cloth, with their boxes (n, 4) [px]; ``pale-black`` is a
    black ball mirroring a bright window (pale yellowish middle, dark rim)."""
    img = np.zeros((80, 40 + 34 * len(balls), 3), np.uint8)
    img[:] = CLOTH
    boxes = []
    for k, name in enumerate(balls):
        c = (30 + 34 * k, 40)
        if name == "pale-black":
            cv2.circle(img, c, radius, COLOURS["black"], -1, cv2.LINE_AA)
            cv2.circle(img, c, int(radius * 0.55), (215, 205, 150), -1, cv2.LINE_AA)
        else:
            cv2.circle(img, c, radius, COLOURS[name], -1, cv2.LINE_AA)
        boxes.append([c[0] - radius, c[1] - radius, c[0] + radius, c[1] + radius])
    return img, np.array(boxes, dtype=float)


def detections(boxes: np.ndarray, class_ids: list[int], conf: float = 0.6) -> Detections:
    n = len(boxes)
    return Detections(boxes, np.full(n, conf), np.asarray(class_ids), (boxes[:, :2] + boxes[:, 2:]) / 2)


def test_each_ball_reads_as_red_yellow_other_or_no_colour():
    img, boxes = table_photo(["red", "yellow", "blue", "white", "black"])
    assert ball_colours(img, boxes).tolist() == [RED, YELLOW, OTHER, NONE, NONE]


def test_reds_and_yellows_make_a_blackball_set_and_other_colours_an_american_one():
    img, boxes = table_photo(["red", "yellow", "red", "yellow", "yellow", "white"])
    assert read_ball_set(img, detections(boxes, [2, 2, 2, 2, 3, 0])) is BallSet.BLACKBALL
    img, boxes = table_photo(["red", "yellow", "blue", "purple", "green", "white"])
    assert read_ball_set(img, detections(boxes, [2, 2, 2, 2, 3, 0])) is BallSet.AMERICAN
    img, boxes = table_photo(["red", "yellow", "white"])  # too few coloured balls to tell: American
    assert read_ball_set(img, detections(boxes, [2, 2, 0])) is BallSet.AMERICAN


def test_more_yellows_than_an_american_set_holds_is_a_blackball_set():
    img, boxes = table_photo(["yellow"] * 5 + ["white"])
    assert read_ball_set(img, detections(boxes, [2] * 5 + [0])) is BallSet.BLACKBALL
    img, boxes = table_photo(["yellow"] * 4 + ["white"])  # 1, 9, 5, 13 of an American set may all read yellow
    assert read_ball_set(img, detections(boxes, [2] * 4 + [0])) is BallSet.AMERICAN


def test_reds_play_as_solids_and_yellows_as_stripes():
    img, boxes = table_photo(["red", "yellow", "yellow", "black", "white"])
    det = detections(boxes, [3, 2, 2, 1, 0])
    named = blackball_classes(img, det)
    assert named.class_id.tolist() == [SOLID_ID, STRIPE_ID, STRIPE_ID, BLACK_ID, 0]


def test_a_black_mirroring_the_room_is_found_among_the_yellows():
    img, boxes = table_photo(["yellow"] * 7 + ["pale-black", "white"])
    det = detections(boxes, [2] * 8 + [0])
    assert black_scores(img, boxes[7:8])[0] < black_scores(img, boxes[:1])[0]
    named = blackball_classes(img, det)
    assert named.class_id[7] == BLACK_ID and (named.class_id[:7] == STRIPE_ID).all()


def test_a_yellow_in_shadow_is_no_black_but_a_much_darker_one_is():
    img, boxes = table_photo(["yellow"] * 4 + ["white"])
    for k, light in enumerate([0.36, 0.36, 0.36, 0.3]):  # a dim table, one yellow in a little more shadow
        x1, y1, x2, y2 = boxes[k].astype(int)
        img[y1 : y2 + 1, x1 : x2 + 1] = (img[y1 : y2 + 1, x1 : x2 + 1] * light).astype(np.uint8)
    det = detections(boxes, [2] * 4 + [0])
    assert (ball_colours(img, boxes[:4]) == YELLOW).all()
    assert black_scores(img, boxes[3:4])[0] < MAX_BLACK_SCORE  # dark enough for a black on its own
    assert (blackball_classes(img, det).class_id[:4] == STRIPE_ID).all()  # no black on this table
    img, boxes = table_photo(["yellow"] * 3 + ["pale-black", "white"])
    named = blackball_classes(img, detections(boxes, [2] * 4 + [0]))
    assert named.class_id[3] == BLACK_ID and (named.class_id[:3] == STRIPE_ID).all()


def test_a_sure_black_stays_the_black():
    img, boxes = table_photo(["yellow", "pale-black", "black", "white"])
    det = Detections(boxes, np.array([0.6, 0.6, 0.9, 0.9]), np.array([2, 2, 1, 0]), (boxes[:, :2] + boxes[:, 2:]) / 2)
    assert blackball_classes(img, det).class_id[2] == BLACK_ID


def test_all_fourteen_object_balls_of_a_blackball_set_survive_the_caps():
    from pix2pockets.pipeline.photo import clean_detections, clean_detections_for_set

    names = ["red", "yellow"] * 7 + ["black", "white"]
    img, boxes = table_photo(names)
    raw = detections(boxes, [2] * 14 + [1, 0], conf=0.7)  # the detector calls every red and yellow a solid
    assert (clean_detections(raw).class_id == SOLID_ID).sum() == 7  # an American set holds 7 solids
    det, ball_set = clean_detections_for_set(raw, img, "auto")
    assert ball_set is BallSet.BLACKBALL
    assert det.class_id.tolist().count(SOLID_ID) == 7 and det.class_id.tolist().count(STRIPE_ID) == 7
    assert det.class_id.tolist().count(BLACK_ID) == 1 and len(det) == 16
    same, chosen = clean_detections_for_set(raw, img, "american")
    assert chosen is BallSet.AMERICAN and len(same) == len(clean_detections(raw))

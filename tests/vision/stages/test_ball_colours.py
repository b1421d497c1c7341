"""Reading a blackball set from the balls' colours, and naming its reds, yellows and black."""

from __future__ import annotations

import cv2
import numpy as np

from pix2pockets.state.ball_set import BallSet
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.stages.ball_colours import (
    BLACK_CANDIDATE_SCORE,
    BLACK_ID,
    MAX_BLACK_SCORE,
    MIN_BLACK_SCORE,
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


def test_a_faint_ball_of_another_colour_weighs_little_against_sure_reds_and_yellows():
    img, boxes = table_photo(["red", "yellow", "red", "yellow", "blue", "white"])
    det = detections(boxes, [2, 2, 2, 2, 2, 0])
    # a blue cue tip or pocket cap the detector is unsure of: 4 x 0.8 against 0.3 is 91 % red and yellow
    det.confidence[:] = [0.8, 0.8, 0.8, 0.8, 0.3, 0.9]
    assert read_ball_set(img, det) is BallSet.BLACKBALL
    det.confidence[4] = 0.8  # a sure blue ball: 80 %
    assert read_ball_set(img, det) is BallSet.AMERICAN


def test_a_sure_red_or_yellow_stripe_is_an_american_set():
    img, boxes = table_photo(["red", "yellow", "red", "yellow", "yellow", "white"])
    det = detections(boxes, [2, 2, 2, 2, 3, 0])
    det.confidence[4] = 0.8  # a 9
    assert read_ball_set(img, det) is BallSet.AMERICAN
    det.confidence[4] = 0.55  # a blackball yellow the detector takes for a stripe, unsure
    assert read_ball_set(img, det) is BallSet.BLACKBALL


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


def test_a_red_or_yellow_ball_scores_as_a_ball_whatever_its_class_scores():
    img, boxes = table_photo(["red", "yellow", "blue", "white"])
    det = Detections(
        boxes, np.full(4, 0.2), np.array([2, 3, 2, 0]), (boxes[:, :2] + boxes[:, 2:]) / 2, ball_score=np.full(4, 0.9)
    )
    named = blackball_classes(img, det)
    # red and yellow: the "any ball" score; a ball of another colour and the cue keep their class scores
    assert named.confidence.tolist() == [0.9, 0.9, 0.2, 0.2]
    without = blackball_classes(img, Detections(boxes, np.full(4, 0.2), np.array([2, 3, 2, 0])))
    assert without.confidence.tolist() == [0.2] * 4  # no "any ball" score: the class scores stay


def test_a_black_mirroring_the_room_is_found_among_the_yellows():
    img, boxes = table_photo(["yellow"] * 7 + ["pale-black", "white"])
    det = detections(boxes, [2] * 8 + [0])
    assert black_scores(img, boxes[7:8])[0] < black_scores(img, boxes[:1])[0]
    named = blackball_classes(img, det)
    assert named.class_id[7] == BLACK_ID and (named.class_id[:7] == STRIPE_ID).all()


def test_a_black_boxed_whole_and_in_part_is_named_whole_and_its_part_dropped():
    """A black mirroring a window boxed twice: whole, as an unsure black, and its pale middle alone, which makes one
    yellow too many. The whole box is the black; the part is no ball of its own."""
    img, boxes = table_photo(["yellow"] * 7 + ["pale-black", "white"])
    centre = (boxes[7, :2] + boxes[7, 2:]) / 2
    part = np.concatenate([centre - 5, centre + 5])[None]  # the middle of the black
    boxes = np.concatenate([boxes, part])
    det = Detections(
        boxes, np.array([0.6] * 7 + [0.2, 0.9, 0.3]), np.array([2] * 7 + [1, 0, 2]), (boxes[:, :2] + boxes[:, 2:]) / 2
    )
    assert (ball_colours(img, boxes[[0, 9]]) == YELLOW).all()
    named = blackball_classes(img, det)
    assert len(named) == 9  # seven yellows, the black and the cue ball
    assert np.flatnonzero(named.class_id == BLACK_ID).tolist() == [7] and named.boxes[7].tolist() == boxes[7].tolist()


def test_an_unsure_black_blacker_than_one_yellow_too_many_is_the_black():
    img, boxes = table_photo(["yellow"] * 8 + ["black", "white"])
    x1, y1, x2, y2 = boxes[7].astype(int)  # a yellow in shadow: the blackest of the eight
    img[y1 : y2 + 1, x1 : x2 + 1] = (img[y1 : y2 + 1, x1 : x2 + 1] * 0.6).astype(np.uint8)
    det = Detections(
        boxes, np.array([0.6] * 8 + [0.2, 0.9]), np.array([2] * 8 + [1, 0]), (boxes[:, :2] + boxes[:, 2:]) / 2
    )
    named = blackball_classes(img, det)
    assert np.flatnonzero(named.class_id == BLACK_ID).tolist() == [8]


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


def test_an_unsure_black_that_looks_black_stays_the_black():
    img, boxes = table_photo(["yellow", "yellow", "black", "black", "white"])
    cv2.circle(img, (98, 40), 12, (70, 70, 72), -1, cv2.LINE_AA)  # the detector's black, lit grey
    det = Detections(  # the last "black" is a pocket's mouth the detector takes for a solid
        boxes, np.array([0.6, 0.6, 0.4, 0.3, 0.9]), np.array([3, 3, 1, 2, 0]), (boxes[:, :2] + boxes[:, 2:]) / 2
    )
    assert black_scores(img, boxes[3:4])[0] < black_scores(img, boxes[2:3])[0] < MAX_BLACK_SCORE
    named = blackball_classes(img, det)
    assert named.class_id[2] == BLACK_ID and named.class_id[3] != BLACK_ID


def test_faint_yellows_do_not_count_among_one_too_many():
    img, boxes = table_photo(["yellow"] * 9 + ["white"])
    cv2.circle(img, (30 + 34 * 7, 40), 12, (20, 20, 22), -1, cv2.LINE_AA)  # a black mirroring a yellow-lit room
    cv2.circle(img, (30 + 34 * 7, 40), 9, (215, 190, 90), -1, cv2.LINE_AA)
    x1, y1, x2, y2 = boxes[8].astype(int)  # a faint, dark yellow detection
    img[y1 : y2 + 1, x1 : x2 + 1] = (img[y1 : y2 + 1, x1 : x2 + 1] * 0.2).astype(np.uint8)
    conf = np.array([0.6] * 8 + [MIN_BLACK_SCORE / 2, 0.9])
    det = Detections(boxes, conf, np.array([2] * 9 + [0]), (boxes[:, :2] + boxes[:, 2:]) / 2)
    assert (ball_colours(img, boxes[:9]) == YELLOW).all()
    assert black_scores(img, boxes[8:9])[0] < black_scores(img, boxes[7:8])[0] < black_scores(img, boxes[:1])[0]
    named = blackball_classes(img, det)
    assert named.class_id[7] == BLACK_ID and named.class_id[8] == STRIPE_ID


def test_a_lone_yellow_or_a_ball_of_another_colour_is_no_unfound_black():
    img, boxes = table_photo(["yellow", "yellow", "red", "red", "white"])
    x1, y1, x2, y2 = boxes[0].astype(int)  # a yellow in deep shadow, with only one other yellow to compare
    img[y1 : y2 + 1, x1 : x2 + 1] = (img[y1 : y2 + 1, x1 : x2 + 1] * 0.25).astype(np.uint8)
    assert ball_colours(img, boxes[:1])[0] == YELLOW and black_scores(img, boxes[:1])[0] < MAX_BLACK_SCORE
    assert BLACK_ID not in blackball_classes(img, detections(boxes, [2] * 4 + [0])).class_id
    img, boxes = table_photo(["blue", "red", "yellow", "yellow", "yellow", "white"])
    x1, y1, x2, y2 = boxes[0].astype(int)  # blue chalk on a cue's tip
    img[y1 : y2 + 1, x1 : x2 + 1] = (img[y1 : y2 + 1, x1 : x2 + 1] * 0.3).astype(np.uint8)
    det = detections(boxes, [2] * 5 + [0], conf=max(0.6, BLACK_CANDIDATE_SCORE))
    assert ball_colours(img, boxes[:1])[0] == OTHER and black_scores(img, boxes[:1])[0] < MAX_BLACK_SCORE
    assert BLACK_ID not in blackball_classes(img, det).class_id


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


def test_a_ball_off_the_playing_surface_does_not_read_the_set():
    """Blue chalk on the rail beside three reds and two yellows: a ball of another colour reads the set American,
    unless the table model's surface shows it lies off the cloth."""
    from pix2pockets.pipeline.photo import clean_detections_for_set, on_surface

    img, boxes = table_photo(["red", "yellow", "red", "yellow", "red", "blue"])
    raw = detections(boxes, [2] * 6, conf=0.7)
    assert clean_detections_for_set(raw, img, "auto")[1] is BallSet.AMERICAN
    surface = np.zeros(img.shape[:2], np.uint8)
    surface[:, : int(boxes[4, 2]) + 2] = 1  # the cloth ends beside the last red: the blue lies on the rail
    assert on_surface(raw.centres, surface).tolist() == [True] * 5 + [False]
    assert clean_detections_for_set(raw, img, "auto", surface)[1] is BallSet.BLACKBALL
    det, _ = clean_detections_for_set(raw, img, "blackball", surface)
    assert len(det) == 6  # the set is read from the balls on the cloth; the balls kept are all of them


def test_points_off_the_photo_are_off_the_surface():
    from pix2pockets.pipeline.photo import on_surface

    surface = np.ones((50, 80), np.uint8)
    assert on_surface(np.array([[-5.0, 10.0], [10.0, 60.0], [40.0, 25.0]]), surface).tolist() == [False, False, True]

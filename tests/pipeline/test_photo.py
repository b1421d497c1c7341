from dataclasses import replace

import numpy as np
import pytest

import pix2pockets
from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.pipeline.draw import render_result
from pix2pockets.pipeline.photo import find_table, load_image, no_cue_ball_reason, suggest
from pix2pockets.pipeline.result import power_level
from pix2pockets.state import Ball, Shot, TableLayout, eight_ball_rack
from pix2pockets.testing import (
    SPEC,
    Candidate,
    LabelDetector,
    LabelNumberReader,
    NearestPocketPlanner,
    blank_image,
    camera,
    example_layout,
)
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.table.fit import TableFitError


@pytest.mark.parametrize("view", ["top", "45", "front"])
def test_suggest_locates_balls_and_plans(view):
    cam = camera(view)
    layout = example_layout()
    res = suggest(blank_image(cam), "solids", LabelDetector(cam, layout), NearestPocketPlanner(), SPEC)
    assert len(res.balls) == len(layout)
    got = np.array([b.table_xy_m for b in res.balls])
    assert np.linalg.norm(got - layout.positions, axis=1).max() < 0.01
    np.testing.assert_allclose(res.corners_px, cam.project_table(SPEC.corners, 0.0), atol=3.0)
    doc = res.to_dict()
    assert doc["image"] == {"width": cam.image_size[0], "height": cam.image_size[1]}
    assert set(doc["table"]) >= {"corners_px", "homography"}
    assert {"class", "confidence", "bbox_px", "contact_px", "table_xy_m", "position_sigma_m"} <= set(doc["balls"][0])
    assert all(0 < b["position_sigma_m"] < 0.05 for b in doc["balls"])
    s = doc["suggestion"]
    assert s["kind"] == "direct"
    assert doc["balls"][s["target_ball"]]["class"] == "solid"
    assert 1 <= s["power_level"] <= 30
    assert set(s) >= {"target_ball", "pocket", "kind", "cue_angle_deg", "speed_mps", "success_probability"}
    # the homography maps contact points to table positions
    H = np.array(doc["table"]["homography"])
    c = np.array([b["contact_px"] + [1.0] for b in doc["balls"]]) @ H.T
    np.testing.assert_allclose(c[:, :2] / c[:, 2:], got, atol=2e-3)
    picture = render_result(blank_image(cam), res)
    assert picture.shape[0] > cam.image_size[1] and picture.shape[1] > cam.image_size[0]


def test_a_low_view_knows_its_far_balls_less_surely():
    spread = {}
    for view in ("top", "front"):
        cam = camera(view)
        res = suggest(blank_image(cam), "solids", LabelDetector(cam, example_layout()), NearestPocketPlanner(), SPEC)
        sigmas = np.array([b.position_sigma_m for b in res.balls])
        spread[view] = sigmas.max() / sigmas.min()
    assert spread["top"] < 1.3 < spread["front"]


def corner_view(shift: float, distance: float) -> PinholeCamera:
    """A top view over the table's centre moved ``shift`` [m] toward its foot, from ``distance`` [m] above."""
    target = np.array([SPEC.length / 2 + shift, SPEC.width / 2, 0.0])
    return PinholeCamera.look_at(target + np.array([0.0, 0.0, distance]), target, 700.0, (960, 540))


def test_a_shot_to_a_pocket_out_of_the_photo_says_so():
    """With the head end out of the photo, a shot to a foot pocket is to a pocket in view; one to a head pocket is
    to where the fit of a cut table is least sure, and the text and the JSON say so."""
    balls = (Ball.numbered(0), Ball.numbered(3), Ball.numbered(8))
    foot_end = TableLayout(balls, [[2.1, 0.6], [2.35, 0.95], [1.9, 0.35]])
    cam = corner_view(0.6, 2.0)
    res = suggest(blank_image(cam), "solids", LabelDetector(cam, foot_end), NearestPocketPlanner(), SPEC)
    head = [p.name for p in SPEC.pockets if p.centre[0] < 0.1]
    foot = [p.name for p in SPEC.pockets if p.centre[0] > SPEC.length - 0.1]
    assert res.shot.pocket in foot and res.pocket_in_view is True
    assert "the pocket lies there" not in res.text
    to_head = replace(res, shot=replace(res.shot, pocket=head[0]))
    assert to_head.pocket_in_view is False
    assert to_head.text.endswith("balls there are not seen, and the pocket lies there, where the fit is least sure")
    assert to_head.to_dict()["suggestion"]["pocket_in_view"] is False


def test_a_table_partly_out_of_the_photo_is_said_and_mostly_out_is_refused():
    balls = (Ball.numbered(0), Ball.numbered(3), Ball.numbered(8))
    foot_end = TableLayout(balls, [[2.1, 0.6], [2.35, 0.95], [1.9, 0.35]])
    cam = corner_view(0.6, 2.0)  # the head end out of the photo
    res = suggest(blank_image(cam), "solids", LabelDetector(cam, foot_end), NearestPocketPlanner(), SPEC)
    assert 0.6 < res.table_in_view < 0.95
    assert res.to_dict()["table"]["in_view"] == pytest.approx(res.table_in_view, abs=1e-3)
    assert "of the table is out of the photo: balls there are not seen" in res.text
    whole = camera("top")
    res = suggest(blank_image(whole), "solids", LabelDetector(whole, foot_end), NearestPocketPlanner(), SPEC)
    assert res.table_in_view == pytest.approx(1.0) and "out of the photo" not in res.text
    cam = corner_view(1.8, 2.0)  # two thirds of the table out of the photo
    with pytest.raises(ValueError, match=r"no table found: only \d+% of the table"):
        suggest(blank_image(cam), "solids", LabelDetector(cam, foot_end), NearestPocketPlanner(), SPEC)


def test_auto_picks_the_better_group_and_top_level_api():
    cam = camera("top")
    res = pix2pockets.suggest(
        blank_image(cam), "auto", detector=LabelDetector(cam, example_layout()), planner=NearestPocketPlanner()
    )
    assert res.shot.group in ("solids", "stripes")
    assert "pocket" in res.text


class SafetyPlanner:
    def suggest(self, layout, state, rng=None):
        return [Candidate(Shot(angle=1.0, speed=1.0), None, None, None, 0.0, -1.0, safety=True)]


def test_no_shot_gives_a_safety_not_an_error():
    cam = camera("top")
    res = suggest(blank_image(cam), "stripes", LabelDetector(cam, example_layout()), SafetyPlanner(), SPEC)
    assert res.shot.safety and res.to_dict()["suggestion"]["pocket"] is None
    assert "No good pot" in res.text
    render_result(blank_image(cam), res)


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"drop": (0,)}, ValueError, "no cue ball found on the table: none was seen"),
        ({"drop": tuple(range(len(example_layout())))}, ValueError, "no balls found on the table"),
        ({"diamonds": False}, TableFitError, "too few table points"),
    ],
)
def test_bad_photos(kwargs, error, match):
    cam = camera("45")
    with pytest.raises(error, match=match):
        suggest(blank_image(cam), "solids", LabelDetector(cam, example_layout(), **kwargs), NearestPocketPlanner())


@pytest.mark.parametrize("drop", [(0,), ()])
def test_ball_in_hand_puts_the_cue_ball_where_the_planner_likes_it(drop):
    cam = camera("45")
    layout = example_layout()
    detector = LabelDetector(cam, layout, drop=drop)
    res = suggest(blank_image(cam), "solids", detector, NearestPocketPlanner(), SPEC, ball_in_hand="table")
    assert len(res.balls) == len(layout)  # a cue ball seen in the photo is picked up, one is put down
    assert [b.ball_class for b in res.balls].count("cue") == 1
    placed = res.balls[-1]
    assert placed.in_hand and placed.ball_class == "cue" and not any(b.in_hand for b in res.balls[:-1])
    xy = np.array(placed.table_xy_m)
    others = np.array([b.table_xy_m for b in res.balls[:-1]])
    assert np.linalg.norm(others - xy, axis=1).min() > SPEC.cue_contact_distance
    np.testing.assert_allclose(placed.contact_px, cam.project_table(xy, 0.0), atol=0.05)
    doc = res.to_dict()
    assert doc["ball_in_hand"] == "table" and doc["balls"][-1]["in_hand"] is True
    assert res.text.startswith(f"Ball in hand: cue ball at ({xy[0]:.2f}, {xy[1]:.2f}) m; ")
    assert res.shot.cue_path[0] == pytest.approx(xy)
    render_result(blank_image(cam), res)
    baulk = suggest(blank_image(cam), "solids", detector, NearestPocketPlanner(), SPEC, ball_in_hand="baulk")
    assert baulk.balls[-1].table_xy_m[0] <= SPEC.baulk_line_x and baulk.to_dict()["ball_in_hand"] == "baulk"
    either = suggest(blank_image(cam), "auto", detector, NearestPocketPlanner(), SPEC, ball_in_hand="table")
    assert either.shot.group in ("solids", "stripes") and either.balls[-1].in_hand


def test_without_ball_in_hand_the_cue_ball_is_played_where_it_lies():
    cam = camera("45")
    res = suggest(blank_image(cam), "solids", LabelDetector(cam, example_layout()), NearestPocketPlanner(), SPEC)
    assert res.ball_in_hand is None and not any(b.in_hand for b in res.balls)
    assert res.to_dict()["ball_in_hand"] is None and not res.text.startswith("Ball in hand")
    with pytest.raises(ValueError, match="unknown ball in hand 'pocket'; choose none, table, baulk"):
        suggest(blank_image(cam), "solids", LabelDetector(cam, example_layout()), ball_in_hand="pocket")


def test_no_cue_ball_says_whether_one_was_seen():
    """A cue ball the photo shows but the fitted table does not hold points at the fit, not at the photo."""
    boxes = np.array([[10.0, 10.0, 30.0, 30.0], [50.0, 10.0, 70.0, 30.0]])
    seen = Detections(boxes, np.array([0.9, 0.9]), np.array([0, 2]))
    assert "lies off the table found there" in no_cue_ball_reason(seen)
    unseen = Detections(boxes, np.array([0.9, 0.9]), np.array([2, 3]))
    assert "none was seen in the photo" in no_cue_ball_reason(unseen)


class PocketTakenForTheEight:
    """The exact labels, with the 8 found unsurely and a surer "8" off the table (a pocket's mouth, a ball on the
    floor)."""

    def __init__(self, cam, layout):
        self.labels = LabelDetector(cam, layout)
        self.cam = cam
        self.eight = layout.black_index

    def detect(self, image_rgb):
        det = self.labels.detect(image_rgb)
        confidence = det.confidence.copy()
        confidence[self.eight] = 0.35
        off = self.cam.project_table(np.array([[-0.3, SPEC.width / 2]]), SPEC.ball_radius)[0]
        box = np.concatenate([off - 8.0, off + 8.0])[None]
        extra = Detections(box, np.array([0.6]), np.array([1]), off[None])
        return Detections.concatenate([Detections(det.boxes, confidence, det.class_id, det.contact), extra])


def test_the_eight_is_claimed_among_the_balls_on_the_table():
    cam = camera("45")
    layout = example_layout()
    res = suggest(blank_image(cam), "solids", PocketTakenForTheEight(cam, layout), NearestPocketPlanner(), SPEC)
    eights = [b for b in res.balls if b.ball_class == "black"]
    assert len(eights) == 1 and len(res.balls) == len(layout)
    assert np.linalg.norm(np.array(eights[0].table_xy_m) - layout.positions[layout.black_index]) < 0.01


class CueOffTheTable:
    """The exact labels without the cue ball, a sure cue ball off the table (a fit gone wrong, or a ball on the
    floor) and a faint cue reading of an object ball on the table."""

    def __init__(self, cam, layout):
        self.labels = LabelDetector(cam, layout, drop=(layout.cue_index,))
        self.cam = cam

    def detect(self, image_rgb):
        det = self.labels.detect(image_rgb)
        off = self.cam.project_table(np.array([[-0.3, SPEC.width / 2]]), SPEC.ball_radius)[0]
        faint = det[det.is_ball][:1]
        extra = Detections.concatenate(
            [
                Detections(np.concatenate([off - 8.0, off + 8.0])[None], np.array([0.6]), np.array([0]), off[None]),
                Detections(faint.boxes, np.array([0.03]), np.array([0]), faint.contact),
            ]
        )
        return Detections.concatenate([det, extra])


def test_a_cue_ball_claimed_on_nothing_after_the_fit_is_no_cue_ball():
    cam = camera("45")
    with pytest.raises(ValueError, match="lies off the table"):
        suggest(blank_image(cam), "solids", CueOffTheTable(cam, example_layout()), NearestPocketPlanner(), SPEC)


def test_no_balls_of_any_group():
    cam = camera("45")
    layout = example_layout()
    det = LabelDetector(cam, layout, drop=tuple(i for i in range(len(layout)) if i != layout.cue_index))
    with pytest.raises(ValueError, match="no object balls"):
        suggest(blank_image(cam), "auto", det, NearestPocketPlanner())


@pytest.mark.parametrize(
    ("image", "match"),
    [
        (np.zeros((10, 10, 3), dtype=np.uint8), "too small"),
        (np.zeros((100, 100, 3), dtype=np.float32), "RGB uint8"),
        (np.zeros((100, 100, 2), dtype=np.uint8), "RGB uint8"),
    ],
)
def test_load_image_rejects_bad_arrays(image, match):
    with pytest.raises(ValueError, match=match):
        load_image(image)


def test_power_levels():
    assert power_level(0.0) == 1
    assert power_level(8.0) == 30
    assert power_level(100.0) == 30
    assert 1 < power_level(3.0) < 30


def test_clean_detections_keeps_a_ball_that_lost_the_cue():
    from pix2pockets.pipeline.photo import clean_detections
    from pix2pockets.vision.detect.detections import Detections

    boxes = np.array([[0, 0, 10, 10], [0.5, 0, 10.5, 10], [100, 0, 110, 10], [100.5, 0, 110.5, 10.0]])
    raw = Detections(boxes, np.array([0.36, 0.05, 0.45, 0.18]), np.array([0, 3, 0, 3]))
    out = clean_detections(raw)
    assert sorted(out.class_id.tolist()) == [0, 3]  # the stripe scores 0.18 as a stripe but 0.45 as a ball


def test_clean_detections_keeps_a_sure_ball_whose_class_scores_disagree():
    from pix2pockets.pipeline.photo import SURE_BALL_SCORE, clean_detections
    from pix2pockets.vision.detect.detections import Detections

    boxes = np.array([[0, 0, 10, 10], [0, 0, 10, 10], [100, 0, 110, 10], [200, 0, 210, 10.0]])
    faint = [0.1, 0.08, 0.1, 0.1]  # e.g. an 8 the classifier is sure of and the black head is not
    ball = [SURE_BALL_SCORE, SURE_BALL_SCORE, SURE_BALL_SCORE - 0.01, np.nan]
    raw = Detections(boxes, faint, [1, 2, 2, 2], ball_score=ball)
    out = clean_detections(raw)
    assert out.boxes[:, 0].tolist() == [0]  # the doubtful ball and the one without a ball score are dropped
    assert out.class_id.tolist() == [1]


def test_ball_numbers_are_read_named_in_the_text_and_drawn():
    cam = camera("45")
    layout = example_layout()
    reader = LabelNumberReader(cam, layout)
    res = suggest(
        blank_image(cam), "solids", LabelDetector(cam, layout), NearestPocketPlanner(), SPEC, number_reader=reader
    )
    got = np.array([b.table_xy_m for b in res.balls])
    truth = [layout.balls[int(np.linalg.norm(layout.positions - xy, axis=1).argmin())].number for xy in got]
    assert [b.number for b in res.balls] == truth
    target = res.balls[res.shot.target_ball]
    assert res.text.startswith(f"{target.number} ball (solid) at")
    doc = res.to_dict()
    assert [b["number"] for b in doc["balls"]] == truth and doc["balls"][0]["number_chance"] > 0.5
    assert render_result(blank_image(cam), res).dtype == np.uint8

    plain = suggest(
        blank_image(cam), "solids", LabelDetector(cam, layout), NearestPocketPlanner(), SPEC, number_reader=False
    )
    assert all(b.number is None for b in plain.balls) and plain.text.startswith("solid ball at")
    assert plain.to_dict()["balls"][0]["number"] is None


def test_an_unsure_number_is_kept_in_json_but_not_named():
    from pix2pockets.pipeline.result import LocatedBall

    ball = LocatedBall("solid", 0.9, (0, 0, 10, 10), (5, 9), (1.0, 0.5), number=3, number_chance=0.3)
    assert ball.sure_number is None and ball.name == "solid ball"
    assert ball.to_dict()["number"] == 3
    sure = LocatedBall("solid", 0.9, (0, 0, 10, 10), (5, 9), (1.0, 0.5), number=3, number_chance=0.8)
    assert sure.name == "3 ball (solid)"


def test_find_table_gives_what_suggest_fits():
    cam = camera("45")
    layout = example_layout()
    image = blank_image(cam)
    raw = LabelDetector(cam, layout).detect(image)
    det, ball_set, _, fit = find_table(image, raw, SPEC, table_model=False)
    assert ball_set.value == "american"
    assert det.is_ball.sum() == len(layout)
    np.testing.assert_allclose(fit.corners_px, cam.project_table(SPEC.corners, 0.0), atol=3.0)
    res = suggest(image, "solids", LabelDetector(cam, layout), NearestPocketPlanner(), SPEC, table_model=False)
    np.testing.assert_allclose(res.corners_px, fit.corners_px)
    without_diamonds = LabelDetector(cam, layout, diamonds=False).detect(image)
    with pytest.raises(TableFitError, match="too few table points"):
        find_table(image, without_diamonds, SPEC, table_model=False)


def test_a_rack_without_its_cue_ball_is_broken_from_hand():
    cam = camera("top")
    rack = eight_ball_rack(SPEC, rng=np.random.default_rng(0))
    res = suggest(blank_image(cam), "auto", LabelDetector(cam, rack, drop=(rack.cue_index,)), NearestPocketPlanner())
    assert res.shot.kind == "break"
    assert res.ball_in_hand == "table"
    assert res.text.startswith("Ball in hand: cue ball at")
    cue = res.layout.positions[res.layout.cue_index]
    assert cue[0] == pytest.approx(SPEC.head_string_x, abs=0.02) or cue[0] == pytest.approx(
        SPEC.length - SPEC.head_string_x, abs=0.02
    )
    assert res.to_dict()["ball_in_hand"] == "table"
    # a cue ball left by the rack is picked up for the break; one in the kitchen is played from where it lies
    by_rack = TableLayout(rack.balls, np.vstack([[SPEC.length / 2, 0.4], rack.positions[1:]]), SPEC)
    res = suggest(blank_image(cam), "auto", LabelDetector(cam, by_rack), NearestPocketPlanner())
    assert res.shot.kind == "break" and res.ball_in_hand == "table"
    assert res.layout.positions[res.layout.cue_index][0] == pytest.approx(SPEC.head_string_x, abs=0.02)
    res = suggest(blank_image(cam), "auto", LabelDetector(cam, rack), NearestPocketPlanner())
    assert res.shot.kind == "break" and res.ball_in_hand is None
    np.testing.assert_allclose(res.layout.positions[res.layout.cue_index], rack.positions[0], atol=0.01)
    # scattered balls without a cue ball are no break: the photo lacks its cue ball
    with pytest.raises(ValueError, match="no cue ball found"):
        suggest(blank_image(cam), "solids", LabelDetector(cam, example_layout(), drop=(0,)), NearestPocketPlanner())


@pytest.mark.parametrize(
    ("size", "aspect", "copy_size"),
    [
        ((640, 640), 0.56, (1138, 640)),  # a 16:9 frame squashed to a square: stretched back across
        ((640, 640), 0.75, (853, 640)),  # a 4:3 photo
        ((640, 640), 4 / 3, (640, 853)),  # a 3:4 portrait photo
        ((4032, 3024), 1.0, (1920, 1440)),  # a 12 MP photo: shrunk
        ((1920, 1920), 0.5625, (1920, 1080)),  # stretched back, then shrunk
    ],
)
def test_the_fit_copy_undoes_an_export_squash_and_caps_the_size(size, aspect, copy_size):
    from pix2pockets.pipeline.photo import fit_copy

    photo = np.zeros((size[1], size[0], 3), np.uint8)
    copy, sx, sy = fit_copy(photo, aspect)
    assert (copy.shape[1], copy.shape[0]) == copy_size
    assert (sx, sy) == pytest.approx((copy_size[0] / size[0], copy_size[1] / size[1]))


@pytest.mark.parametrize("aspect", [None, 1.0, 0.9, 1.04])
def test_a_photo_with_square_or_unknown_pixels_is_fitted_as_it_is(aspect):
    from pix2pockets.pipeline.photo import fit_copy

    photo = np.zeros((640, 640, 3), np.uint8)
    copy, sx, sy = fit_copy(photo, aspect)
    assert copy is photo and sx == sy == 1.0


def test_a_large_photo_says_why_no_table_in_its_own_pixels(monkeypatch):
    import pix2pockets.pipeline.photo as photo
    from pix2pockets.vision.table.errors import in_photo_px

    def no_table(rgb, *args):
        assert max(rgb.shape[:2]) == photo.FIT_MAX_SIDE  # fitted on the shrunk copy
        raise TableFitError(f"no table found: the diamonds do not fit one camera (reprojection {in_photo_px(10.0)})")

    monkeypatch.setattr(photo, "_find_table", no_table)
    big = np.zeros((3024, 4032, 3), np.uint8)
    with pytest.raises(TableFitError, match=r"reprojection 21\.0 px"):
        find_table(big, Detections.empty())

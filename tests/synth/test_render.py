"""Labels of synthetic renders agree with the geometry; seeds reproduce images exactly."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.synth import labels, render, render_sample, render_views
from pix2pockets.synth import scene_codes as sc
from pix2pockets.synth.renderer import parse_size, scene_of, trace, trace_without_diamonds

SIZE = (320, 180)
SEEDS = list(range(8))
SIGHTED = [s for s in range(40) if scene_of(s).has_sights][:3]
"""Seeds whose tables carry sights (diamonds)."""


@pytest.fixture(scope="module")
def renders():
    return {s: render(s, SIZE) for s in SEEDS}


def test_same_seed_same_bytes():
    a, la = render_sample(3, SIZE)
    b, lb = render_sample(3, SIZE)
    assert a.dtype == np.uint8 and a.shape == (SIZE[1], SIZE[0], 3)
    assert a.tobytes() == b.tobytes()
    assert la == lb


def test_different_seeds_differ(renders):
    assert renders[0].image.tobytes() != renders[1].image.tobytes()


def test_labelled_ball_centres_inside_boxes_and_on_ball_pixels(renders):
    checked = 0
    for rend in renders.values():
        for i, ball in enumerate(rend.labels["balls"]):
            if not ball["labelled"] or ball["occluded_fraction"] > 0.05:
                continue
            x0, y0, x1, y1 = ball["box_px"]
            u, v = ball["centre_px"]
            assert x0 - 1 <= u <= x1 + 1 and y0 - 1 <= v <= y1 + 1, ball
            # the pixel at the projected centre shows this ball (exactly, in the id buffer)
            assert rend.ids[int(v), int(u)] == sc.ID_BALL0 + i
            checked += 1
    assert checked >= 20


def test_ball_pixels_have_ball_colours():
    """Unoccluded balls: the median colour of their pixels matches the ball (red 3, yellow 1, blue 2)."""
    checks = {
        3: lambda r, g, b: r > g + 15 and r > b + 15,
        1: lambda r, g, b: r > b + 30 and g > b + 30,
        2: lambda r, g, b: b > r,
    }
    seen = set()
    for seed in range(24):
        rend = render(seed, (640, 360), camera_kind="phone_low" if seed % 2 else "low")
        for i, ball in enumerate(rend.labels["balls"]):
            n = ball["number"]
            if n not in checks or not ball["labelled"] or ball["occluded_fraction"] > 0 or ball["visible_px"] < 60:
                continue
            pix = rend.image[rend.ids == sc.ID_BALL0 + i]
            r, g, b = (int(c) for c in np.median(pix, axis=0))
            assert checks[n](r, g, b), (seed, n, r, g, b)
            seen.add(n)
    assert seen == set(checks)


def test_diamonds_lie_on_rails(renders):
    for rend in renders.values():
        for diamond in rend.labels["diamonds"]:
            if not diamond["labelled"]:
                continue
            u, v = (int(c) for c in diamond["px"])
            around = rend.ids[max(v - 1, 0) : v + 2, max(u - 1, 0) : u + 2]
            on_rail = (around == sc.ID_DIAMOND0 + diamond["index"]) | (around == sc.ID_CAP)
            assert on_rail.any(), diamond
            assert not np.isin(around, [sc.ID_CLOTH, sc.ID_FLOOR, sc.ID_WALL]).all(), diamond
            x0, y0, x1, y1 = diamond["box_px"]
            assert x0 <= diamond["px"][0] <= x1 and y0 <= diamond["px"][1] <= y1


def test_diamonds_are_labelled_only_when_they_show_in_the_photo(renders, monkeypatch):
    signals, hidden = [], 0
    for rend in renders.values():
        for diamond in rend.labels["diamonds"]:
            if "signal" not in diamond:
                continue
            signals.append(diamond["signal"])
            assert diamond["labelled"] <= (diamond["signal"] >= labels.DIAMOND_MIN_SIGNAL)
            hidden += diamond["visible_fraction"] >= labels.DIAMOND_MIN_VISIBLE and (
                diamond["signal"] < labels.DIAMOND_MIN_SIGNAL
            )
    assert max(signals) > 50 and hidden >= 1  # plain sights show strongly; some are there but not seen
    monkeypatch.setattr(labels, "DIAMOND_MIN_SIGNAL", 256)
    assert not any(d["labelled"] for d in render(SIGHTED[0], SIZE).labels["diamonds"])


def test_leaving_the_diamonds_out_changes_only_diamond_pixels():
    rend = render(SIGHTED[1], SIZE)
    c = rend.labels["camera"]
    cam = PinholeCamera(np.array(c["K"]), np.array(c["R"]), np.array(c["t"]), tuple(c["image_size"]))
    scene = scene_of(SIGHTED[1])
    raw, ids, _, _ = trace(scene, cam)
    raw_plain, ids_plain, _, _ = trace(scene, cam, diamonds=False)
    on_diamond = (ids >= sc.ID_DIAMOND0) & (ids < sc.ID_DIAMOND0 + 18)
    assert on_diamond.any() and not ((ids_plain >= sc.ID_DIAMOND0) & (ids_plain < sc.ID_DIAMOND0 + 18)).any()
    near = cv2.dilate(on_diamond.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)  # anti-aliased edges
    assert np.array_equal(raw[~near], raw_plain[~near]) and not np.array_equal(raw[near], raw_plain[near])
    assert np.array_equal(ids_plain[on_diamond], np.full(on_diamond.sum(), sc.ID_CAP))


def test_retracing_only_around_the_diamonds_matches_a_full_trace_without_them():
    for seed in SIGHTED[:2]:
        rend = render(seed, SIZE)
        c = rend.labels["camera"]
        cam = PinholeCamera(np.array(c["K"]), np.array(c["R"]), np.array(c["t"]), tuple(c["image_size"]))
        scene = scene_of(seed)
        raw, ids, depth, _ = trace(scene, cam)
        fast = trace_without_diamonds(scene, cam, raw, ids, depth)
        assert np.array_equal(fast, trace(scene, cam, diamonds=False)[0])
        assert not np.array_equal(fast, raw)  # the sights were there and are gone


def test_occluded_objects_are_flagged_and_left_out():
    found = 0
    for seed in range(40):
        rend = render(seed, SIZE)
        occ = rend.occluded
        for i, ball in enumerate(rend.labels["balls"]):
            mask = rend.ids == sc.ID_BALL0 + i
            if mask.sum() < 10:
                continue
            hidden = (mask & occ).sum() / mask.sum()
            assert ball["occluded_fraction"] >= hidden - 1e-3
            if hidden > 0.9:
                assert not ball["labelled"]
                found += 1
    assert found >= 1


def test_out_of_frame_balls_flagged():
    seen = False
    for seed in range(40):
        rend = render(seed, SIZE, camera_kind="phone")
        for ball in rend.labels["balls"]:
            if ball["in_frame_fraction"] == 0.0:
                assert not ball["labelled"]
                seen = True
    assert seen


def test_multi_view_shares_layout():
    views = render_views(5, SIZE)
    assert [v.labels["view"] for v in views] == ["top", "high", "front"]
    centres = [[b["centre_table_m"] for b in v.labels["balls"]] for v in views]
    assert centres[0] == centres[1] == centres[2]
    assert len({v.labels["camera"]["position_m"][2] for v in views}) == 3


@pytest.mark.parametrize("bad", ["960", "x540", "10x10", "axb"])
def test_bad_size(bad):
    with pytest.raises(ValueError):
        parse_size(bad)


def test_rail_cap_step_closes_the_gap_above_the_cushion():
    """In low views the cap's inner step face sits right above a far cushion's top: no cloth, nose or room shows
    through between them (without the step face, almost every column would)."""
    gaps = columns = 0
    for seed in range(3):
        ids = render(seed, (320, 180), camera_kind="low").ids
        for col in ids.T:
            rows = np.flatnonzero(col == sc.ID_CUSHION)
            if len(rows) == 0 or rows[0] == 0 or (col[: rows[0]] == sc.ID_CLOTH).any():
                continue
            end = rows[0]
            while end + 1 < len(col) and col[end + 1] == sc.ID_CUSHION:
                end += 1
            if end + 1 >= len(col) or col[end + 1] not in (sc.ID_NOSE, sc.ID_CLOTH):
                continue  # a near cushion (the cloth lies above it in the image) or a cut-off one
            columns += 1
            gaps += col[rows[0] - 1] in (sc.ID_NOSE, sc.ID_FLOOR, sc.ID_WALL, sc.ID_CLOTH)
    assert columns > 300
    assert gaps < 0.1 * columns


def test_blackball_sets_are_plain_reds_and_yellows_on_uk_tables():
    """A blackball render: UK table, reds labelled with the solid id and yellows with the stripe id, and their pixels
    red or yellow all over (plain balls: no white band, no number circle)."""
    seen = set()
    for seed in range(12):
        rend = render(seed, (640, 360), camera_kind="phone_low" if seed % 2 else "low", ball_set="blackball")
        assert rend.labels["ball_set"] == "blackball" and rend.labels["table"]["name"] in ("uk7", "uk6")
        for i, ball in enumerate(rend.labels["balls"]):
            n = ball["number"]
            expected = {0: ("cue", 0), 8: ("black", 1)}.get(n, ("red", 2) if n < 8 else ("yellow", 3))
            assert (ball["class"], ball["class_id"]) == expected
            if n in (0, 8) or not ball["labelled"] or ball["occluded_fraction"] > 0 or ball["visible_px"] < 60:
                continue
            pix = rend.image[rend.ids == sc.ID_BALL0 + i].astype(int)
            white = (pix.min(axis=1) > 170).mean()  # bright and unsaturated: a band or a number circle
            median = np.median(pix, axis=0).astype(np.uint8).reshape(1, 1, 3)
            hue, sat, _ = (int(c) for c in cv2.cvtColor(median, cv2.COLOR_RGB2HSV)[0, 0])  # hue in 2-degree steps
            assert sat > 100, (seed, n, median)
            assert (hue <= 9 or hue >= 171) if n < 8 else (11 <= hue <= 38), (seed, n, median, hue)
            assert white < 0.12, (seed, n, white)
            seen.add("red" if n < 8 else "yellow")
    assert seen == {"red", "yellow"}


def test_american_set_is_the_default():
    a = render(5, SIZE)
    b = render(5, SIZE, ball_set="american")
    assert a.image.tobytes() == b.image.tobytes() and a.labels["ball_set"] == "american"
    with pytest.raises(ValueError, match="ball set"):
        render(5, SIZE, ball_set="snooker")


def test_a_uk_cue_ball_is_drawn_smaller_than_the_object_balls():
    """Seen from above, the 1 7/8 in cue ball covers about (1 7/8 / 2)^2 = 0.88 of an object ball's pixels."""
    ratios = []
    for seed in range(6):
        rend = render(seed, (960, 540), camera_kind="top", ball_set="blackball")
        whole = [b for b in rend.labels["balls"] if b["labelled"] and b["occluded_fraction"] == 0]
        cue = [b["visible_px"] for b in whole if b["number"] == 0]
        others = [b["visible_px"] for b in whole if b["number"] != 0]
        if cue and len(others) >= 3:
            ratios.append(cue[0] / float(np.median(others)))
            heights = {b["number"]: b["centre_table_m"][2] for b in rend.labels["balls"]}
            assert heights[0] < min(z for n, z in heights.items() if n != 0)  # centre height = radius
    assert ratios and 0.8 < float(np.median(ratios)) < 0.95, ratios

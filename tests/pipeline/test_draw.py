"""The top-down diagram: balls located unsurely carry a ring as wide as their position error; the cloth is drawn in
the cloth colour nearest the photo's; sights are drawn on tables fitted to them. A large photo is shown at a size
its lines can be seen at."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from pix2pockets.pipeline.draw import (
    CLOTH,
    CLOTH_NAMES,
    CLOTH_RGB,
    CUE_AFTER,
    MAX_PHOTO_SIDE,
    SCRATCH,
    TEXT_BAND,
    UNSURE,
    UNSURE_SIGMA,
    draw_diagram,
    photo_cloth,
    render_result,
)
from pix2pockets.pipeline.photo import suggest
from pix2pockets.testing import SPEC, LabelDetector, NearestPocketPlanner, blank_image, camera, example_layout

HEIGHT = 400


def with_sigma(result, sigma):
    return replace(result, balls=tuple(replace(b, position_sigma_m=sigma) for b in result.balls))


def test_unsure_balls_get_a_ring_and_sure_ones_none():
    cam = camera("top")
    res = suggest(blank_image(cam), "solids", LabelDetector(cam, example_layout()), NearestPocketPlanner(), SPEC)
    sure = draw_diagram(with_sigma(res, UNSURE_SIGMA / 2), HEIGHT)
    unknown = draw_diagram(with_sigma(res, None), HEIGHT)
    unsure = draw_diagram(with_sigma(res, 3 * UNSURE_SIGMA), HEIGHT)
    np.testing.assert_array_equal(sure, unknown)
    changed = np.any(sure != unsure, axis=-1)
    ring_coloured = np.all(np.abs(unsure.astype(int) - UNSURE) <= 30, axis=-1)
    assert (changed & ring_coloured).sum() > 20 * len(res.balls)


def located(cam):
    return suggest(blank_image(cam), "solids", LabelDetector(cam, example_layout()), NearestPocketPlanner(), SPEC)


@pytest.mark.parametrize(
    ("name", "light"), [("red", 0.9), ("black", 1.0), ("tan", 1.2), ("tournament_blue", 0.7), ("green", 0.6)]
)
def test_the_diagram_takes_the_cloth_colour_nearest_the_photos(name, light):
    cam = camera("45")
    res = located(cam)
    photo = np.zeros_like(blank_image(cam))
    photo[:] = np.clip(CLOTH_RGB[CLOTH_NAMES.index(name)] * light, 0, 255).astype(np.uint8)
    photo[:40] = (250, 250, 250)  # a bright wall outside the table is not read
    cloth = photo_cloth(photo, res)
    assert cloth == tuple(int(v) for v in CLOTH_RGB[CLOTH_NAMES.index(name)])
    diagram = draw_diagram(res, HEIGHT, cloth)
    assert tuple(diagram[HEIGHT // 2, diagram.shape[1] // 2]) == cloth


def test_a_table_fitted_outside_the_photo_keeps_the_default_cloth():
    cam = camera("top")
    res = replace(located(cam), corners_px=np.full((4, 2), np.nan))
    assert photo_cloth(blank_image(cam), res) == CLOTH


def test_the_rails_carry_sights_only_where_the_table_was_fitted_to_some():
    res = located(camera("top"))
    assert res.evidence["diamonds"] > 0
    plain = replace(res, evidence={**res.evidence, "diamonds": 0})
    with_sights, without = draw_diagram(res, HEIGHT), draw_diagram(plain, HEIGHT)
    spots = np.all(with_sights >= 200, axis=-1) & ~np.all(without >= 200, axis=-1)  # light dots on the rails only
    assert spots.sum() >= 18 * 4
    h, w = spots.shape
    assert not spots[int(0.15 * h) : int(0.85 * h), int(0.1 * w) : int(0.9 * w)].any()  # none on the cloth


def test_the_cue_balls_way_after_the_first_ball_is_drawn_to_where_it_stops():
    res = located(camera("top"))
    path = np.array([[1.0, 0.5], [1.3, 0.7], [1.6, 0.9]])
    with_path = replace(res, shot=replace(res.shot, cue_after=path))
    plain, drawn = draw_diagram(res, HEIGHT), draw_diagram(with_path, HEIGHT)

    def coloured(img, colour):
        return np.all(np.abs(img.astype(int) - colour) <= 30, axis=-1)

    changed = np.any(plain != drawn, axis=-1)
    assert (changed & coloured(drawn, CUE_AFTER)).sum() > 40  # the dashes and the ring where it stops
    assert not coloured(drawn, SCRATCH).any()
    scratched = draw_diagram(replace(with_path, shot=replace(with_path.shot, cue_pocketed=True)), HEIGHT)
    ring = np.any(scratched != drawn, axis=-1)  # only the ring where it stops changes ...
    redder = (scratched[ring].astype(int) - drawn[ring].astype(int)) @ np.array([1, -1, 0])
    assert ring.sum() > 20 and np.mean(redder) > 50  # ... to red: the cue ball drops there


def test_a_large_photo_is_drawn_on_a_copy_of_the_largest_shown_size():
    import cv2

    cam = camera("45")
    res = located(cam)
    w, h = cam.image_size
    factor = 2 * MAX_PHOTO_SIDE / w  # twice the largest size shown
    big_size = (round(w * factor), round(h * factor))
    big = res.scaled(factor, factor, big_size)
    big_photo = cv2.resize(blank_image(cam), big_size, interpolation=cv2.INTER_NEAREST)
    picture = render_result(big_photo, big)
    shown = (MAX_PHOTO_SIDE, round(big_size[1] * MAX_PHOTO_SIDE / big_size[0]))
    assert picture.shape[0] == shown[1] + TEXT_BAND
    half = factor / 2
    same = render_result(cv2.resize(blank_image(cam), shown), res.scaled(half, half, shown))
    np.testing.assert_array_equal(picture, same)


def test_a_scaled_answer_maps_its_pixels_to_the_same_table_points():
    res = located(camera("45"))
    big = res.scaled(3.0, 2.0, (3840, 1440))
    assert big.image_size == (3840, 1440) and big.camera.image_size == (3840, 1440)
    np.testing.assert_allclose(big.corners_px, res.corners_px * [3.0, 2.0])
    for old, new in zip(res.balls, big.balls, strict=True):
        np.testing.assert_allclose(new.contact_px, np.array(old.contact_px) * [3.0, 2.0])
        np.testing.assert_allclose(new.bbox_px, np.array(old.bbox_px) * [3.0, 2.0, 3.0, 2.0])
        uv = np.array([*new.contact_px, 1.0]) @ np.array(big.homography).T
        np.testing.assert_allclose(uv[:2] / uv[2], old.table_xy_m, atol=2e-3)
    assert big.text == res.text

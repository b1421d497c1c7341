"""Snapping a table's cloth outline onto the cloth's edge, and the camera through an exact outline."""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np

from pix2pockets.geometry import PinholeCamera, TableSpec
from pix2pockets.vision.detect.analytic import standard_views
from pix2pockets.vision.table import cloth_edge
from pix2pockets.vision.table.cloth_edge import (
    cloth_colour,
    cloth_hued,
    colour_region,
    pull_in_sides,
    snap_fit,
    snap_to_cloth_edge,
)
from pix2pockets.vision.table.outline_camera import camera_through_outline, outline_rectangle
from pix2pockets.vision.table.outline_fit import fit_outline
from tests.vision.table.test_cloth import corner_error, draw_table_photo, view

SPEC = TableSpec()


def true_outline(camera: PinholeCamera) -> np.ndarray:
    return camera.project_table(outline_rectangle(SPEC), SPEC.cushion_height)


def grown(corners: np.ndarray, factor: float) -> np.ndarray:
    centre = corners.mean(axis=0)
    return centre + factor * (corners - centre)


def region(corners: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    mask = np.zeros((size[1], size[0]), np.uint8)
    cv2.fillPoly(mask, [np.round(corners - 0.5).astype(np.int32)], 1)
    return mask.astype(bool)


def test_a_grown_outline_moves_back_onto_the_cloth_edge():
    camera = view("oblique")
    img, boxes = draw_table_photo(camera)
    truth = true_outline(camera)
    start = grown(truth, 1.04)
    assert corner_error(start, truth) > 4.0
    colour = cloth_colour(img, region(grown(truth, 0.9), camera.image_size), boxes)
    snapped = snap_to_cloth_edge(img, start, colour, reach=12.0)
    assert snapped.moved.sum() >= 3  # the player hides much of one rail
    assert corner_error(snapped.corners_px, truth) < 1.5


def test_a_reach_beyond_the_photo_is_cut_to_a_share_of_it():
    camera = view("oblique")
    img, boxes = draw_table_photo(camera, player=False)
    truth = true_outline(camera)
    colour = cloth_colour(img, region(grown(truth, 0.9), camera.image_size), boxes)
    snapped = snap_to_cloth_edge(img, grown(truth, 1.03), colour, reach=1e6)
    assert corner_error(snapped.corners_px, truth) < 1.5


def test_a_side_that_may_not_move_stays():
    camera = view("oblique")
    img, boxes = draw_table_photo(camera, player=False)
    truth = true_outline(camera)
    start = grown(truth, 1.03)
    colour = cloth_colour(img, region(grown(truth, 0.9), camera.image_size), boxes)
    snapped = snap_to_cloth_edge(img, start, colour, reach=12.0, sides=np.array([True, False, True, True]))
    assert not snapped.moved[1] and snapped.moved[[0, 2, 3]].all()
    # side 1 (corner 1 -> 2) still lies on the line it started on
    a, b = start[1], start[2]
    normal = np.array([b[1] - a[1], a[0] - b[0]]) / np.linalg.norm(b - a)
    assert np.abs((snapped.corners_px[[1, 2]] - a) @ normal).max() < 1e-6


def test_an_edge_that_separates_nothing_is_not_taken():
    camera = view("oblique")
    img, boxes = draw_table_photo(camera, player=False)
    truth = true_outline(camera)
    flat = np.full_like(img, 90)  # no cloth anywhere: no side finds an edge better than it had
    colour = cloth_colour(img, region(grown(truth, 0.9), camera.image_size), boxes)
    snapped = snap_to_cloth_edge(flat, truth, colour, reach=12.0)
    assert not snapped.moved.any()
    assert np.allclose(snapped.corners_px, truth)


def test_snap_fit_sharpens_a_fit_that_is_a_few_pixels_off():
    camera = view("oblique")
    img, boxes = draw_table_photo(camera)
    truth = true_outline(camera)
    rough = fit_outline(grown(truth, 1.03), camera.image_size, SPEC, ball_boxes=boxes)
    off = rough.camera.project_table(outline_rectangle(SPEC), SPEC.cushion_height)
    assert corner_error(off, truth) > 3.0
    mask = region(grown(truth, 0.9), camera.image_size)
    sharp = snap_fit(img, rough, mask, boxes)
    assert sharp.cloth_edges >= 3 and sharp.spec is rough.spec
    assert corner_error(sharp.camera.project_table(outline_rectangle(SPEC), SPEC.cushion_height), truth) < 1.5
    # a fit already on the edge stays where it is
    again = snap_fit(img, replace(sharp, cloth_edges=0), mask, boxes)
    assert corner_error(again.corners_px, sharp.corners_px) < 0.5


def test_the_colour_is_read_within_the_fits_own_surface():
    camera = view("oblique")
    _img, boxes = draw_table_photo(camera, player=False)
    truth = true_outline(camera)
    fit = fit_outline(truth, camera.image_size, SPEC, ball_boxes=boxes)
    w, h = camera.image_size
    surface = region(fit.camera.project_table(outline_rectangle(SPEC, 0.0), 0.0), (w, h))
    leaky = region(grown(truth, 1.3), (w, h))  # the table and the floor round it
    assert (colour_region(leaky, fit) ^ (leaky & surface)).sum() < 0.02 * surface.sum()
    elsewhere = np.zeros((h, w), dtype=bool)
    elsewhere[:40, :40] = True  # a region off the table (a wall): the fit's own surface instead
    assert (colour_region(elsewhere, fit) ^ surface).sum() < 0.02 * surface.sum()


def test_snap_fit_finds_the_cloth_edge_when_the_region_is_off_the_table():
    camera = view("oblique")
    img, boxes = draw_table_photo(camera)
    truth = true_outline(camera)
    rough = fit_outline(grown(truth, 1.03), camera.image_size, SPEC, ball_boxes=boxes)
    w, h = camera.image_size
    wall = np.zeros((h, w), dtype=bool)
    wall[:40, :40] = True
    sharp = snap_fit(img, rough, wall, boxes)
    assert corner_error(sharp.camera.project_table(outline_rectangle(SPEC), SPEC.cushion_height), truth) < 1.5


def rolled(camera: PinholeCamera, degrees: float) -> PinholeCamera:
    """The camera turned about its optical axis."""
    a = np.radians(degrees)
    turn = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    return PinholeCamera(camera.K, turn @ camera.R, turn @ camera.t, camera.image_size)


def test_camera_through_an_outline_sees_it_exactly_with_stretched_pixels():
    camera = rolled(view("oblique"), 12.0)
    K = camera.K.copy()
    K[0, 0] *= 0.75  # an export squashed the photo's width
    stretched = PinholeCamera(K, camera.R, camera.t, camera.image_size)
    corners = true_outline(stretched)
    found = camera_through_outline(corners, stretched.image_size, SPEC)
    assert found is not None
    assert np.abs(true_outline(found) - corners).max() < 1e-6
    assert abs(found.K[0, 0] / found.K[1, 1] - 0.75) < 1e-6
    assert np.allclose(found.position, stretched.position, atol=1e-6)
    # the balls' plane follows: a point above the cloth lands where the true camera puts it
    p = np.array([1.1, 0.4, SPEC.ball_radius])
    assert np.abs(found.project(p) - stretched.project(p)).max() < 1e-6


def test_camera_through_an_outline_that_does_not_fix_both_focal_lengths_is_refused():
    top = standard_views(SPEC)["top"]  # square-on: no focal length at all
    assert camera_through_outline(true_outline(top), top.image_size, SPEC) is None
    level = view("oblique")  # no roll: a stretch along x looks like a turn of the table
    assert camera_through_outline(true_outline(level), level.image_size, SPEC) is None


def test_a_view_from_above_gets_a_believable_focal_length():
    """Seen straight down, the focal length is not in the picture: a camera a quarter as high with a lens four times
    as wide sees the cloth as the true one does, the cushion tops 3.6 cm above it a little larger. Moved onto the
    cloth outline alone, such a camera stays low and puts the cloth 19 px too small; with the focal-length floor it
    comes up to a believable height and the cloth lands within a few pixels."""
    from pix2pockets.vision.table.cloth_edge import MIN_FOCAL, camera_onto_outline

    true = standard_views(SPEC)["top"]
    w = max(true.image_size)
    K = true.K.copy()
    K[:2, :2] *= 0.25
    near = PinholeCamera(K, true.R, -true.R @ (true.position * np.array([1.0, 1.0, 0.25])), true.image_size)
    outline = true_outline(true)
    cloth = true.project_table(outline_rectangle(SPEC, 0.0), 0.0)
    assert near.K[1, 1] < MIN_FOCAL * w and corner_error(true_outline(near), outline) > 5.0
    moved = camera_onto_outline(near, SPEC, outline, MIN_FOCAL * w)
    assert moved is not None and moved.K[1, 1] >= 0.45 * w
    assert corner_error(true_outline(moved), outline) < 1.0
    assert corner_error(moved.project_table(outline_rectangle(SPEC, 0.0), 0.0), cloth) < 8.0


def banded_photo(
    truth: np.ndarray, size: tuple[int, int], rail: tuple[int, int, int], shade: bool = False, rail_out: float = 1.035
) -> np.ndarray:
    """A dark table body, a rail band round the cloth outline ``truth`` (4, 2) [px] out to ``truth`` grown by
    ``rail_out`` from its centre, a light blue-grey cloth inside it and, with ``shade``, the cloth in shadow along its
    edge (a cushion's dark face)."""
    img = np.zeros((size[1], size[0], 3), np.uint8)
    img[:] = (30, 24, 28)  # the table's dark body and the floor
    cv2.fillPoly(img, [np.round(grown(truth, rail_out) - 0.5).astype(np.int32)], rail)
    cv2.fillPoly(img, [np.round(truth - 0.5).astype(np.int32)], (150, 178, 196))
    if shade:
        cv2.fillPoly(img, [np.round(truth - 0.5).astype(np.int32)], (75, 89, 98))
        cv2.fillPoly(img, [np.round(grown(truth, 0.975) - 0.5).astype(np.int32)], (150, 178, 196))
    return img


def snap_banded(
    rail: tuple[int, int, int], start: float, rail_out: float = 1.035, shade: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """The true cloth outline of an oblique view of :func:`banded_photo` and that photo's outline snapped from the
    true one grown by ``start`` (16 px reach)."""
    camera = view("oblique")
    truth = true_outline(camera)
    img = banded_photo(truth, camera.image_size, rail=rail, shade=shade, rail_out=rail_out)
    colour = cloth_colour(img, region(grown(truth, 0.9), camera.image_size))
    return truth, snap_to_cloth_edge(img, grown(truth, start), colour, reach=16.0).corners_px


def test_a_light_rail_beside_a_light_cloth_is_not_taken_for_the_cloth():
    """White laminate beside a light cloth differs less from the cloth than the dark body beyond it: the snap keeps
    the innermost clear rise, the cloth's edge, not the steepest one, the rail's outer edge."""
    truth, snapped = snap_banded((230, 230, 235), start=0.985)
    assert corner_error(grown(truth, 0.985), truth) > 3.0
    assert corner_error(snapped, truth) < 1.5


def test_a_silver_rail_a_little_darker_than_the_cloth_is_no_shadow():
    """A grey rail nearly as light as the cloth (silver trim) is greyer and a shade darker, yet no cushion's shadow:
    its edge is the cloth's, not the dark body's beyond it."""
    truth, snapped = snap_banded((165, 166, 168), start=0.97)
    assert corner_error(snapped, truth) < 0.6 * corner_error(grown(truth, 1.035), truth)


def test_the_cloth_in_shadow_inside_its_edge_does_not_pull_the_line_in():
    # a wooden rail; the start inside the shadow, nearer its inner edge than the cloth's edge
    truth, snapped = snap_banded((120, 70, 40), start=0.97, shade=True)
    assert corner_error(grown(truth, 0.97), truth) > 3.0
    assert corner_error(snapped, truth) < 1.5


def test_an_outline_round_a_light_rail_moves_in_onto_the_cloth():
    """The model's outline on a white rail's outer edge: the band inside it is rail, not cloth, so the cloth's edge is
    the rail's inner edge, although the rail's outer edge is the nearer and the steeper."""
    truth, snapped = snap_banded((235, 235, 238), start=1.05, rail_out=1.05)
    assert corner_error(grown(truth, 1.05), truth) > 8.0
    assert corner_error(snapped, truth) < 1.5


def test_a_lit_band_of_the_cloths_hue_is_no_rail():
    """A band of the cloth's own hue, lighter (a cushion top in the light), inside an outline on its outer edge is
    cloth: the outline stays on the band's outer edge."""
    truth, snapped = snap_banded((175, 218, 245), start=1.05, rail_out=1.05)  # the cloth's blue-grey, lit
    assert corner_error(snapped, grown(truth, 1.05)) < 1.5


def pulled_banded(rail: tuple[int, int, int], start: float, rail_out: float) -> tuple[np.ndarray, np.ndarray, bool]:
    """The true cloth outline of an oblique view of :func:`banded_photo`, and that photo's outline pulled in from the
    true one grown by ``start`` (60 px reach) with whether any side moved."""
    camera = view("oblique")
    truth = true_outline(camera)
    img = banded_photo(truth, camera.image_size, rail=rail, rail_out=rail_out)
    colour = cloth_colour(img, region(grown(truth, 0.9), camera.image_size))
    pulled = pull_in_sides(img, grown(truth, start), colour, reach=60.0, sides=np.ones(4, dtype=bool))
    return truth, pulled.corners_px, bool(pulled.moved.any())


def test_an_outline_round_a_wide_dark_rail_is_pulled_in_onto_the_cloth():
    """The model's outline round a whole dark rail, further out than the snap searches: the band inside it is no
    cloth, so each side moves in to where the cloth starts."""
    truth, pulled, moved = pulled_banded((70, 45, 30), start=1.12, rail_out=1.12)
    assert moved and corner_error(grown(truth, 1.12), truth) > 20.0
    assert corner_error(pulled, truth) < 2.0


def test_an_outline_with_the_cloth_inside_it_is_not_pulled_in():
    truth, pulled, moved = pulled_banded((70, 45, 30), start=1.0, rail_out=1.12)
    assert not moved and corner_error(pulled, truth) < 1e-9
    # a lit band of the cloth's own hue (a cushion top) inside the outline is cloth too
    truth, pulled, moved = pulled_banded((175, 218, 245), start=1.12, rail_out=1.12)
    assert not moved


def test_cloth_hued_is_the_cloths_hue_in_other_light_only():
    cloth = np.array([50.0, -20.0, -10.0])  # a blue-green cloth, CIE Lab
    lab = np.array([[70.0, -26.0, -12.0], [30.0, -12.0, -7.0], [60.0, 0.0, 0.0], [50.0, 20.0, 10.0]])
    assert cloth_hued(lab, cloth).tolist() == [True, True, False, False]  # lit, shaded, grey, the opposite hue
    assert not cloth_hued(lab, np.array([50.0, 1.0, -1.0])).any()  # a grey cloth's hue says nothing


def test_a_dark_cloths_side_does_not_jump_out_onto_a_rail_as_dark(monkeypatch):
    """Black cloth, black rails, a light floor: the steepest step near a side is the rail's outer edge, and the fit on
    the cloth's edge keeps its sides there."""
    camera = view("oblique")
    img, boxes = draw_table_photo(camera, cloth=(20, 20, 22), player=False)
    size = camera.image_size
    truth = true_outline(camera)
    rail = camera.project_table(outline_rectangle(SPEC, 0.05 + 0.12), SPEC.cushion_height)
    img[region(rail, size) & ~region(truth, size)] = (24, 23, 23)
    fit = fit_outline(truth, size, SPEC, ball_boxes=boxes)
    mask = region(grown(truth, 0.9), size)

    def error(fitted):
        return corner_error(fitted.camera.project_table(outline_rectangle(SPEC), SPEC.cushion_height), truth)

    held = snap_fit(img, fit, mask, boxes)
    assert error(held) < 2.0
    assert held.cloth_edges == 0  # every side held where it was: none counted as moved onto the cloth's edge
    monkeypatch.setattr(cloth_edge, "DARK_CLOTH_L", 0.0)  # the cloth not counted dark: sides run out to the rail's edge
    assert error(snap_fit(img, fit, mask, boxes)) > 5.0


def test_the_photo_is_sampled_at_more_points_than_one_opencv_map_holds():
    rgb = np.random.default_rng(0).integers(0, 256, (60, 80, 3), dtype=np.uint8)
    pts = np.random.default_rng(1).uniform(0, 59, (40_000, 2, 2))
    lab = cloth_edge._lab_at(rgb, pts)
    assert lab.shape == (40_000, 2, 3)
    np.testing.assert_allclose(lab[[0, 39_999]], cloth_edge._lab_at(rgb, pts[[0, 39_999]]), atol=1e-5)

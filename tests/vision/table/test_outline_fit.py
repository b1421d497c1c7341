"""Camera from the cloth outline: exact outlines of analytic views, long/short rails, three cushions, table size."""

from __future__ import annotations

import numpy as np
import pytest

from pix2pockets.geometry import PinholeCamera, TableSpec, table_preset
from pix2pockets.geometry.homography import fit_homography
from pix2pockets.vision.detect.analytic import standard_views
from pix2pockets.vision.locate.balls import sphere_boxes
from pix2pockets.vision.table.errors import TableFitError
from pix2pockets.vision.table.outline_camera import (
    camera_from_outline,
    complete_three_lines,
    outline_rectangle,
    rectangle_cost,
)
from pix2pockets.vision.table.outline_fit import fit_outline, fit_two_cushions
from pix2pockets.vision.table.quad_geometry import quad_mask
from pix2pockets.vision.table.table_size import spec_of_length
from pix2pockets.vision.table.two_cushions import CushionMark
from tests.vision.table.test_two_cushions import across_view, seen

SPEC = TableSpec()
BALLS = np.array([[0.6, 0.4], [1.9, 0.9], [1.2, 0.6], [0.3, 1.0], [2.2, 0.2], [1.5, 1.1]])


def outline_of(camera: PinholeCamera, spec: TableSpec = SPEC) -> np.ndarray:
    return camera.project_table(outline_rectangle(spec), spec.cushion_height)


def ball_boxes(camera: PinholeCamera, spec: TableSpec = SPEC) -> np.ndarray:
    xy = BALLS * spec.size / SPEC.size
    return sphere_boxes(camera, np.column_stack([xy, np.full(len(xy), spec.ball_radius)]), spec.ball_radius)


def same_table(fit, camera: PinholeCamera, spec: TableSpec, tol_px: float) -> bool:
    """The fitted playing-surface corners are the true ones, up to the 180-degree turn (a wrong long/short choice
    turns them by 90 degrees)."""
    truth = camera.project_table(spec.corners, 0.0)
    return min(np.abs(np.roll(fit.corners_px, k, axis=0) - truth).max() for k in (0, 2)) < tol_px


@pytest.mark.parametrize("view", ["top", "45", "front"])
@pytest.mark.parametrize("order", ["as projected", "rolled", "reversed"])
def test_exact_outline_gives_the_table(view, order):
    camera = standard_views(SPEC)[view]
    corners = outline_of(camera)
    if order == "rolled":
        corners = np.roll(corners, 1, axis=0)
    elif order == "reversed":
        corners = corners[::-1]
    fit = fit_outline(corners, camera.image_size, SPEC, ball_boxes=ball_boxes(camera))
    assert fit.source == "cloth" and fit.size_source == "given" and fit.n_matched == 0
    assert same_table(fit, camera, SPEC, 1.0)
    assert fit.rms_px < 0.5
    # the head rail convention of the diamond fit: the head rail further left / lower than the foot rail
    head, foot = fit.table_to_image(np.array([[0.0, SPEC.width / 2], [SPEC.length, SPEC.width / 2]]))
    assert (head[0] - foot[0]) - (head[1] - foot[1]) <= 0


def test_long_and_short_rails_from_the_rectangle_alone():
    camera = standard_views(SPEC)["45"]
    corners = outline_of(camera)
    world = outline_rectangle(SPEC)
    right, _ = rectangle_cost(fit_homography(world, corners), camera.image_size, 1280)
    turned, _ = rectangle_cost(fit_homography(world, np.roll(corners, 1, axis=0)), camera.image_size, 1280)
    assert right < 1.0 < 100.0 < turned


def test_noisy_corners_still_fit():
    camera = standard_views(SPEC)["front"]
    rng = np.random.default_rng(4)
    corners = outline_of(camera) + rng.normal(0.0, 1.0, (4, 2))
    fit = fit_outline(corners, camera.image_size, SPEC, ball_boxes=ball_boxes(camera))
    assert same_table(fit, camera, SPEC, 6.0)


@pytest.mark.parametrize("name", ["9ft", "7ft"])
def test_size_from_the_balls(name):
    spec = table_preset(name)
    camera = standard_views(spec)["45"]
    fit = fit_outline(outline_of(camera, spec), camera.image_size, None, ball_boxes=ball_boxes(camera, spec))
    assert fit.spec.name == name and fit.size_source == "balls"
    assert same_table(fit, camera, spec, 1.0)


def test_size_without_balls_is_the_default():
    camera = standard_views(SPEC)["45"]
    fit = fit_outline(outline_of(camera), camera.image_size)
    assert fit.spec == SPEC and fit.size_source == "default"


def test_a_measured_size_far_from_the_presets():
    assert spec_of_length(2.0).name == "7ft"
    assert spec_of_length(2.85).name == "9ft"  # a table reads no larger than the largest preset's reach
    assert spec_of_length(9.0).name == "9ft" and spec_of_length(0.5).name == "6ft"  # misreads held at the range


def test_three_lines_and_a_focal_length_complete_the_rectangle():
    camera = standard_views(SPEC)["45"]
    corners = outline_of(camera)
    lines = np.array([np.cross([*corners[k], 1.0], [*corners[(k + 1) % 4], 1.0]) for k in range(4)])
    world = outline_rectangle(SPEC)
    made = complete_three_lines(
        lines[[3, 0, 1]], camera.focal_px, camera.image_size, world[1, 0] - world[0, 0], world[2, 1] - world[1, 1],
        corners.mean(axis=0),
    )  # fmt: skip
    np.testing.assert_allclose(made, corners, atol=1e-6)


def test_a_side_out_of_the_frame_is_completed():
    # the head cushion out of view: three cushions place it for a camera of the usual focal length (three lines leave
    # the focal length open; a prior of 0.9 image widths closes it)
    cam45 = standard_views(SPEC)["45"]
    camera = PinholeCamera.look_at(cam45.position, np.array([*SPEC.size / 2, 0.0]), 1150.0, cam45.image_size)
    corners = outline_of(camera)
    seen = np.array([True, True, True, False])  # side 3 runs from corner 3 to corner 0: the head
    # the frame edge, not the cushion, ends the two long cushions: their lines stay, their ends move along them
    garbage = corners.copy()
    garbage[0] = corners[0] + 0.2 * (corners[1] - corners[0])
    garbage[3] = corners[3] + 0.3 * (corners[2] - corners[3])
    fit = fit_outline(garbage, camera.image_size, SPEC, seen=seen, ball_boxes=ball_boxes(camera))
    assert same_table(fit, camera, SPEC, 0.02 * max(camera.image_size))


@pytest.mark.parametrize(
    ("corners", "match"),
    [
        (np.array([[0.0, 0.0], [100.0, 0.0], [200.0, 0.0], [300.0, 0.0]]), "no table found"),
        (np.array([[100.0, 100.0], [300.0, 100.0], [300.0, 300.0], [100.0, 300.0]]), "no table found"),
        (np.full((4, 2), np.nan), "no four corners"),
    ],
)
def test_no_table_from_degenerate_outlines(corners, match):
    with pytest.raises(TableFitError, match=match):
        fit_outline(corners, (640, 480), SPEC)


def test_a_rectangle_seen_square_on_needs_balls():
    # a window, a door or a picture seen straight on is a "table from above" without balls on it
    camera = standard_views(SPEC)["top"]
    with pytest.raises(TableFitError, match="straight above"):
        fit_outline(outline_of(camera), camera.image_size, SPEC)


def test_two_cushions_are_not_enough():
    camera = standard_views(SPEC)["45"]
    with pytest.raises(TableFitError, match="only 2 cushions"):
        fit_outline(outline_of(camera), camera.image_size, SPEC, seen=np.array([True, True, False, False]))


def test_squashed_export_with_the_aspect_the_balls_show():
    # a 16:9 frame stretched to a square: pixels 0.5625 times as wide as tall
    wide = standard_views(SPEC, (1280, 720))["45"]
    aspect = 640 / 1280 / (640 / 720)
    K = np.diag([640 / 1280, 640 / 720, 1.0]) @ wide.K
    camera = PinholeCamera(K, wide.R, wide.t, (640, 640))
    fit = fit_outline(outline_of(camera), (640, 640), SPEC, ball_boxes=ball_boxes(camera))
    assert fit.camera.K[0, 0] / fit.camera.K[1, 1] == pytest.approx(aspect, rel=1e-6)
    assert same_table(fit, camera, SPEC, 1.0)


def test_a_table_seen_from_far_above_through_a_long_lens_is_fitted():
    centre = np.array([SPEC.length / 2, SPEC.width / 2, 0.0])
    camera = PinholeCamera.look_at(centre + np.array([0.0, 3.0, 40.0]), centre, 12000.0, (1280, 720))
    fit = fit_outline(outline_of(camera), camera.image_size, SPEC, ball_boxes=ball_boxes(camera))
    assert same_table(fit, camera, SPEC, 4.0)  # 0.5 % of the table's length: square on, any long focal fits
    assert fit.camera.K[1, 1] <= 1.1 * 8.0 * 1280


def test_a_held_focal_length_stays_where_it_is_put():
    camera = standard_views(SPEC)["45"]
    free, _, _ = camera_from_outline(outline_of(camera), camera.image_size, SPEC, focal_px=3000.0)
    held, _, _ = camera_from_outline(outline_of(camera), camera.image_size, SPEC, focal_px=3000.0, focal_sigma=1e-3)
    assert abs(free.K[1, 1] - camera.K[1, 1]) < 0.01 * camera.K[1, 1]  # the corners pull a free one back
    assert abs(held.K[1, 1] - 3000.0) < 0.01 * 3000.0


def test_a_size_from_the_balls_snaps_to_a_table_for_balls_of_that_size():
    uk = table_preset("uk7")
    assert spec_of_length(2.10, uk).name == "uk7" and spec_of_length(1.85, uk).name == "uk6"
    assert spec_of_length(2.13).name == "7ft"  # American balls: the American presets only (uk7 is 2.13 m)


def test_two_long_cushions_with_their_pockets_and_a_corner_give_the_table():
    """A close view across the table: the two long cushions, both side pockets and a far corner fix the table and
    the focal length; the balls on it and the cloth agree."""
    camera = across_view()
    corners, near, far, pockets = seen(camera)
    marks = [
        CushionMark(pockets[0], 0, "pocket"),
        CushionMark(pockets[1], 1, "pocket"),
        CushionMark(corners[2], 1, "corner"),
    ]
    spec = TableSpec()
    xy = np.array([[1.2, 0.4], [1.9, 0.8], [2.3, 0.3]])
    boxes = sphere_boxes(camera, np.column_stack([xy, np.full(len(xy), spec.ball_radius)]), spec.ball_radius)
    mask = quad_mask(corners, (camera.image_size[1], camera.image_size[0]))
    fit = fit_two_cushions(
        np.array([near, far]),
        marks,
        camera.image_size,
        spec,
        ball_boxes=boxes,
        cloth_mask=mask,
        offset=0.0,
        plane_z=0.0,
    )
    got = fit.camera.project_table(spec.corners, 0.0)
    assert min(np.abs(np.roll(got, k, axis=0) - corners).max() for k in (0, 2)) < 1.0
    assert fit.camera.K[1, 1] == pytest.approx(camera.K[1, 1], rel=1e-3)


def test_two_cushions_without_a_side_pocket_and_a_second_mark_are_refused():
    camera = across_view()
    corners, near, far, pockets = seen(camera)
    for marks in ([CushionMark(pockets[0], 0, "pocket")], [CushionMark(corners[2], 1, "corner")] * 2):
        with pytest.raises(TableFitError, match="side pocket"):
            fit_two_cushions(np.array([near, far]), marks, camera.image_size, TableSpec(), offset=0.0, plane_z=0.0)

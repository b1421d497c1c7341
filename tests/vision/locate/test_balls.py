import numpy as np
import pytest

from pix2pockets.geometry import TableSpec
from pix2pockets.state import Ball, BallClass, TableLayout, random_layout
from pix2pockets.vision.detect.analytic import analytic_detections, standard_views
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.locate.balls import (
    LocateMethod,
    locate_balls,
    on_the_table,
    settle_positions,
    sphere_boxes,
    too_small,
)
from pix2pockets.vision.table.fit import fit_table

SPEC = TableSpec()
VIEWS = standard_views(SPEC)


def test_sphere_boxes_match_sampled_silhouette():
    cam = VIEWS["45"]
    centre = np.array([2.0, 1.0, SPEC.ball_radius])
    dirs = np.random.default_rng(0).normal(size=(100_000, 3))
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    uv = cam.project(centre + dirs * SPEC.ball_radius)
    box = sphere_boxes(cam, centre[None], SPEC.ball_radius)[0]
    np.testing.assert_allclose(box, [*uv.min(axis=0), *uv.max(axis=0)], atol=0.05)


@pytest.mark.parametrize("view", sorted(VIEWS))
def test_balls_within_one_cm_from_fitted_table(view):
    rng = np.random.default_rng(2)
    layout = random_layout(rng, list(range(16)), SPEC)
    cam = VIEWS[view]
    det = analytic_detections(cam, layout, rng, box_noise_px=0.5, diamond_noise_px=0.5)
    fit = fit_table(det, cam.image_size, SPEC)
    loc = locate_balls(fit.camera, det, SPEC, LocateMethod.SPHERE)
    assert len(loc.positions) == len(layout)
    err = np.linalg.norm(loc.positions - layout.positions, axis=1)
    assert err.max() < 0.01
    assert err.mean() < 0.004
    # contact points project back near the true ones
    np.testing.assert_allclose(loc.contact_px, cam.project_table(layout.positions, 0.0), atol=3.0)
    # the located layout is a valid TableLayout
    assert len(loc.to_layout(SPEC)) == len(layout)


def test_exact_method_beats_the_linear_baseline_in_a_front_view():
    rng = np.random.default_rng(4)
    layout = random_layout(rng, list(range(16)), SPEC)
    cam = VIEWS["front"]
    det = analytic_detections(cam, layout)
    fit = fit_table(det, cam.image_size, SPEC)
    errs = {}
    for m in LocateMethod:
        loc = locate_balls(fit.camera, det, SPEC, m)
        errs[m] = np.linalg.norm(loc.positions - layout.positions, axis=1).mean()
    assert errs[LocateMethod.SPHERE] < 0.003
    assert errs[LocateMethod.CONTACT] < 0.003
    assert errs[LocateMethod.LINEAR] > 3 * errs[LocateMethod.SPHERE]


def test_balls_off_table_or_in_pockets_are_dropped():
    cam = VIEWS["top"]
    layout = TableLayout((Ball(BallClass.CUE),), np.array([[1.0, 0.5]]), SPEC)
    det = analytic_detections(cam, layout)
    fit = fit_table(det, cam.image_size, SPEC)
    R = SPEC.ball_radius
    extra_pts = np.array([[SPEC.length / 2, -0.2, R], [0.0, 0.0, R]])  # on the rail; in a corner pocket
    boxes = sphere_boxes(cam, extra_pts, R)
    extra = Detections(boxes, np.ones(2), np.array([2, 3]))
    loc = locate_balls(fit.camera, Detections.concatenate([det, extra]), SPEC)
    assert loc.dropped == 2
    assert loc.detections.class_names == ["cue"]
    np.testing.assert_allclose(loc.positions, [[1.0, 0.5]], atol=0.005)
    assert loc.env_positions.shape == (1, 2)


def test_on_the_table_marks_every_entry_of_a_ball_in_play_and_every_diamond():
    cam = VIEWS["top"]
    layout = TableLayout((Ball(BallClass.CUE),), np.array([[1.0, 0.5]]), SPEC)
    det = analytic_detections(cam, layout)
    R = SPEC.ball_radius
    extra_pts = np.array([[1.0, 0.5, R], [SPEC.length / 2, -0.2, R], [0.0, 0.0, R]])  # same ball; rail; pocket
    extra = Detections(sphere_boxes(cam, extra_pts, R), np.ones(3), np.array([3, 1, 1]))
    mask = on_the_table(cam, Detections.concatenate([det, extra]), SPEC)
    n = len(det)
    assert mask[:n].all()  # the ball and the diamonds
    assert mask[n:].tolist() == [True, False, False]


def test_a_ball_seen_twice_is_kept_once_and_touching_balls_stay_two():
    cam = VIEWS["top"]
    R = SPEC.ball_radius
    layout = TableLayout(
        (Ball(BallClass.CUE), Ball(BallClass.SOLID)), np.array([[1.0, 0.5], [1.0 + 2 * R, 0.5]]), SPEC
    )  # touching
    det = analytic_detections(cam, layout)
    fit = fit_table(det, cam.image_size, SPEC)
    ghost = sphere_boxes(cam, np.array([[1.0 + 0.01, 0.5, R]]), R)  # the cue ball again, 1 cm off
    extra = Detections(ghost, np.array([0.3]), np.array([3]))
    loc = locate_balls(fit.camera, Detections.concatenate([det, extra]), SPEC)
    assert loc.detections.class_names == ["cue", "solid"] and loc.dropped == 1
    assert (
        len(locate_balls(fit.camera, Detections.concatenate([det, extra]), SPEC, same_ball_distance=0.0).positions) == 3
    )


def test_settle_positions_separates_touching_estimates():
    R = SPEC.ball_radius
    pos = settle_positions(np.array([[1.0, 0.5], [1.0 + 1.9 * R, 0.5], [R / 2, 0.3]]), SPEC)
    assert np.linalg.norm(pos[0] - pos[1]) >= 2 * R
    assert pos[2, 0] >= R


def test_unknown_method_is_rejected():
    with pytest.raises(ValueError):
        locate_balls(VIEWS["top"], Detections.empty(), SPEC, "magic")


def test_box_cut_by_the_image_border_keeps_its_inner_edge():
    cam = VIEWS["top"]
    R = SPEC.ball_radius
    # a ball whose image straddles the left border
    x = 0.1
    while cam.project_table(np.array([x, 0.6]), R)[0] > 2.0:
        x -= 0.005
    box = sphere_boxes(cam, np.array([[x, 0.6, R]]), R)[0]
    assert box[0] < 0 < box[2]
    cut = box.copy()
    cut[0] = 0.0
    from pix2pockets.vision.locate.balls import locate_sphere

    xy = locate_sphere(cam, cut[None], R)[0]
    assert abs(xy[0] - x) < 0.002 and abs(xy[1] - 0.6) < 0.002


def test_linear_baseline_follows_the_fitted_diamond_height():
    """After the camera is refitted for a measured rail height, the paper's heuristic must map through
    that plane; through the spec's default plane it lands somewhere else."""
    rng = np.random.default_rng(5)
    layout = random_layout(rng, list(range(8)), SPEC)
    cam = VIEWS["45"]
    det = analytic_detections(cam, layout)
    fit = fit_table(det, cam.image_size, SPEC)
    moved = fit.with_diamond_z(fit.diamond_z + 0.01)
    same = locate_balls(fit.camera, det, SPEC, LocateMethod.LINEAR).positions
    follows = locate_balls(moved.camera, det, SPEC, LocateMethod.LINEAR, diamond_z=moved.diamond_z).positions
    stale = locate_balls(moved.camera, det, SPEC, LocateMethod.LINEAR).positions
    np.testing.assert_allclose(follows, same, atol=1e-6)
    assert np.abs(stale - same).max() > 1e-3


def test_a_detection_too_small_for_a_ball_there_is_dropped():
    cam = VIEWS["45"]
    R = SPEC.ball_radius
    rng = np.random.default_rng(5)
    layout = random_layout(rng, list(range(8)), SPEC)
    det = analytic_detections(cam, layout)
    fit = fit_table(det, cam.image_size, SPEC)
    speck_box = sphere_boxes(cam, np.array([[1.5, 0.9, R]]), R)[0]
    centre, half = (speck_box[:2] + speck_box[2:]) / 2, (speck_box[2:] - speck_box[:2]) / 2
    speck = Detections(np.concatenate([centre - 0.4 * half, centre + 0.4 * half])[None], np.ones(1), np.array([2]))
    loc = locate_balls(fit.camera, Detections.concatenate([det, speck]), SPEC)
    assert len(loc.positions) == len(layout) and loc.dropped == 1
    kept = locate_balls(fit.camera, Detections.concatenate([det, speck]), SPEC, drop_small=False)
    assert len(kept.positions) == len(layout) + 1


def test_every_ball_looking_small_is_a_table_of_another_size_not_specks():
    cam = VIEWS["45"]
    rng = np.random.default_rng(6)
    layout = random_layout(rng, list(range(8)), SPEC)
    det = analytic_detections(cam, layout)
    fit = fit_table(det, cam.image_size, SPEC)
    balls = det[det.is_ball]
    centre, half = (balls.boxes[:, :2] + balls.boxes[:, 2:]) / 2, (balls.boxes[:, 2:] - balls.boxes[:, :2]) / 2
    small = Detections(np.hstack([centre - 0.5 * half, centre + 0.5 * half]), balls.confidence, balls.class_id)
    assert not too_small(fit.camera, small.boxes, layout.positions, SPEC).any()
    assert len(locate_balls(fit.camera, small, SPEC).positions) == len(layout)

"""One table estimate over every cue: the bundled example render, drawn photos, analytic views, model outlines, no
table."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest

from pix2pockets.data.examples import example_labels_path, example_photo_path
from pix2pockets.geometry import PinholeCamera, TableSpec, table_preset
from pix2pockets.pipeline.photo import load_image
from pix2pockets.state import Ball, TableLayout
from pix2pockets.vision.detect.analytic import analytic_detections, detections_from_synth_labels, standard_views
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.locate.balls import locate_balls
from pix2pockets.vision.table.errors import TableFitError
from pix2pockets.vision.table.estimate import (
    better_surface_fit,
    edge_sides,
    estimate_table,
    outline_used,
    surface_overlap,
)
from pix2pockets.vision.table.quad_geometry import quad_mask
from pix2pockets.vision.table.surface import SurfaceOutline, surface_outline
from tests.vision.table.test_cloth import BALLS, draw_table_photo, view

LABELS = json.loads(Path(example_labels_path()).read_text())
EXAMPLE_SPEC = table_preset(LABELS["table"]["name"])


@pytest.fixture(scope="module")
def example():
    return load_image(example_photo_path()), detections_from_synth_labels(LABELS)


def ball_errors(fit, det, spec: TableSpec) -> np.ndarray:
    """Distance [m] of each located ball to the nearest true ball, the fit's frame turned to the render's."""
    truth = np.array([b["centre_table_m"][:2] for b in LABELS["balls"] if b["labelled"]])
    xy = locate_balls(fit.camera, det, fit.spec).positions * (spec.length / fit.spec.length)
    turned = np.column_stack([spec.length - xy[:, 0], spec.width - xy[:, 1]])
    errors = [np.linalg.norm(p[:, None] - truth[None], axis=-1).min(axis=1) for p in (xy, turned)]
    return min(errors, key=lambda e: float(e.mean()))


def test_cloth_alone_locates_the_balls_of_the_example(example):
    rgb, det = example
    balls = det[det.is_ball]  # no diamonds: the table from its cloth alone, its size from the balls
    fit = estimate_table(rgb, balls)
    assert fit.source == "cloth" and fit.size_source == "balls" and fit.spec.name == EXAMPLE_SPEC.name
    err = ball_errors(fit, balls, EXAMPLE_SPEC)
    assert len(err) == len(balls)
    assert err.max() < 0.02


def test_diamonds_and_cloth_agree_on_the_example(example):
    rgb, det = example
    fit = estimate_table(rgb, det, spec=EXAMPLE_SPEC)
    assert fit.source == "diamonds+cloth" and fit.size_source == "given" and fit.n_matched >= 6
    truth = np.array([c["px_cloth"] for c in LABELS["corners"]])
    assert min(np.abs(np.roll(fit.corners_px, k, axis=0) - truth).max() for k in (0, 2)) < 4.0


def test_cues_select_the_fit(example):
    rgb, det = example
    assert estimate_table(rgb, det, cues="diamonds").source == "diamonds"
    assert estimate_table(rgb, det, cues="cloth").source == "cloth"
    with pytest.raises(ValueError, match="cues must be one of"):
        estimate_table(rgb, det, cues="pockets")


@pytest.mark.parametrize("kind", ["oblique", "end"])
def test_drawn_photo_long_and_short_rails(kind):
    camera = view(kind)
    img, boxes = draw_table_photo(camera)
    det = Detections(boxes, np.ones(len(boxes)), np.full(len(boxes), 2))
    fit = estimate_table(img, det)
    truth = camera.project_table(TableSpec().corners, 0.0)
    assert fit.spec.name == "9ft"
    assert min(np.abs(np.roll(fit.corners_px, k, axis=0) - truth).max() for k in (0, 2)) < 4.0


def test_diamonds_without_a_photo():
    spec = TableSpec()
    camera = standard_views(spec)["45"]
    layout = TableLayout((Ball.numbered(0), Ball.numbered(3)), BALLS[:2], spec)
    fit = estimate_table(None, analytic_detections(camera, layout), camera.image_size)
    assert fit.source == "diamonds" and fit.n_matched == 18
    with pytest.raises(ValueError, match="image_size"):
        estimate_table(None, analytic_detections(camera, layout))


def test_no_table_says_what_is_missing():
    img = np.zeros((360, 640, 3), np.uint8)
    img[:] = (200, 190, 170)  # a bare wall
    with pytest.raises(TableFitError, match=r"^no table found: diamonds: .*; cloth: .*show the whole table"):
        estimate_table(img, Detections.empty())


def outline_of(corners: np.ndarray, size: tuple[int, int], alternative: SurfaceOutline | None = None) -> SurfaceOutline:
    """A surface outline with these corners (4, 2) [px], all sides seen, its region the quadrilateral itself."""
    mask = np.zeros((size[1], size[0]), np.uint8)
    cv2.fillPoly(mask, [np.round(corners).astype(np.int32)], 1)
    ones = np.ones(4, dtype=bool)
    return SurfaceOutline(corners, ones, ones, np.zeros(4), mask.astype(bool), 0.9, alternative)


def test_the_corner_peaks_outline_fits_where_the_regions_cannot():
    """A region leaking onto a player gives a quadrilateral no camera sees a table as; the corner peaks' own outline,
    kept as the second hypothesis, gives the table."""
    spec = TableSpec()
    camera = view("oblique")
    truth = camera.project_table(spec.corners, 0.0)
    leaked = truth.copy()
    leaked[1] += 0.8 * (truth[1] - truth[0])  # one corner dragged far along its side
    det = Detections.empty()
    size = camera.image_size
    with pytest.raises(TableFitError):
        estimate_table(None, det, size, spec, cues="surface", surface=outline_of(leaked, size))
    surface = outline_of(leaked, size, alternative=outline_of(truth, size))
    fit = estimate_table(None, det, size, spec, cues="surface", surface=surface)
    assert min(np.abs(np.roll(fit.corners_px, k, axis=0) - truth).max() for k in (0, 2)) < 2.0
    assert outline_used(fit, surface) is surface.alternative
    alone = outline_of(truth, size)
    assert outline_used(fit, alone) is alone


def test_a_diamond_fit_far_off_the_surface_loses_to_the_surface():
    """Diamonds that fit a table where the model sees no cloth (false diamonds: a rack triangle, balls in a row) lose
    to the surface's table, though they are more cues than its four corners."""
    spec = TableSpec()
    camera = view("oblique")
    size = camera.image_size
    layout = TableLayout((Ball.numbered(0), Ball.numbered(3)), BALLS[:2], spec)
    det = analytic_detections(standard_views(spec, size)["45"], layout)  # the diamonds' (wrong) table
    truth = camera.project_table(spec.corners, 0.0)
    surface = outline_of(truth, size)
    assert estimate_table(None, det, size, spec, cues="diamonds").source == "diamonds"
    fit = estimate_table(None, det, size, spec, surface=surface)
    assert fit.source == "surface"
    assert min(np.abs(np.roll(fit.corners_px, k, axis=0) - truth).max() for k in (0, 2)) < 2.0
    assert surface_overlap(fit, surface.mask) > 0.95


def test_a_diamond_fit_a_sight_off_loses_to_the_surface():
    """Diamonds matched one sight along the table off give a table shifted by an eighth of its length: it still
    overlaps most of the model's surface region, but clearly less than the surface's own table, which wins."""
    spec = TableSpec()
    camera = view("oblique")
    size = camera.image_size
    shift = np.array([spec.length / 8, 0.0, 0.0])  # the shifted camera sees table point p where the true one sees p + s
    shifted = PinholeCamera(camera.K, camera.R, camera.t + camera.R @ shift, size)
    layout = TableLayout((Ball.numbered(0), Ball.numbered(3)), BALLS[:2], spec)
    det = analytic_detections(shifted, layout)
    truth = camera.project_table(spec.corners, 0.0)
    surface = outline_of(truth, size)
    diamonds = estimate_table(None, det, size, spec, cues="diamonds")
    assert 0.7 < surface_overlap(diamonds, surface.mask) < 0.93  # a table most of the way onto the cloth
    fit = estimate_table(None, det, size, spec, surface=surface)
    assert fit.source == "surface"
    assert min(np.abs(np.roll(fit.corners_px, k, axis=0) - truth).max() for k in (0, 2)) < 2.0


def test_a_top_view_with_the_models_corners_and_side_pockets_needs_no_balls():
    """A rectangle seen from straight above needs balls on it to be taken for a table (a window or a picture looks the
    same), unless the table model finds its four corners and both side pockets."""
    spec = TableSpec()
    camera = standard_views(spec)["top"]
    size = camera.image_size
    truth = camera.project_table(spec.corners, 0.0)
    plain = outline_of(truth, size)
    with pytest.raises(TableFitError, match="view from straight above needs 3 balls"):
        estimate_table(None, Detections.empty(), size, spec, cues="surface", surface=plain)
    pocketed = replace(plain, side_pocket=np.array([0.9, 0.0, 0.9, 0.0]))
    fit = estimate_table(None, Detections.empty(), size, spec, cues="surface", surface=pocketed)
    assert min(np.abs(np.roll(fit.corners_px, k, axis=0) - truth).max() for k in (0, 2)) < 2.0
    one_pocket = replace(plain, side_pocket=np.array([0.9, 0.0, 0.0, 0.0]))
    with pytest.raises(TableFitError, match="view from straight above"):
        estimate_table(None, Detections.empty(), size, spec, cues="surface", surface=one_pocket)


def test_a_view_from_just_above_the_rails_is_fitted():
    """A phone held at the rail's height (the lens 15 cm over the cloth, behind the head rail) still sees the table."""
    spec = TableSpec()
    centre = np.array([spec.length / 2, spec.width / 2, 0.0])
    camera = PinholeCamera.look_at(np.array([-0.5, spec.width / 2 + 0.3, 0.15]), centre, 900.0, (1280, 720))
    truth = camera.project_table(spec.corners, 0.0)
    surface = outline_of(truth, camera.image_size)
    fit = estimate_table(None, Detections.empty(), camera.image_size, spec, cues="surface", surface=surface)
    assert min(np.abs(np.roll(fit.corners_px, k, axis=0) - truth).max() for k in (0, 2)) < 2.0
    assert 0.1 < fit.camera.position[2] < 0.2


def _balls_at(centres: np.ndarray, size_px: float = 20.0) -> Detections:
    """Solid-ball detections (score 0.9) centred on ``centres`` (n, 2) [px]."""
    half = size_px / 2
    boxes = np.column_stack([centres - half, centres + half])
    return Detections(boxes, np.full(len(centres), 0.9), np.full(len(centres), 2))


def test_a_surface_fit_holding_none_of_the_balls_is_refused():
    """A table that none of three sure balls lies on is not the one in the photo (a sliver fitted to one cushion seen
    close up); the same outline with the balls on its cloth is the table."""
    spec = TableSpec()
    camera = view("oblique")
    size = camera.image_size
    truth = camera.project_table(spec.corners, 0.0)
    surface = outline_of(truth, size)
    on_cloth = camera.project_table(np.array([[0.6, 0.4], [1.2, 0.6], [1.9, 0.8]]), spec.ball_radius)
    fit = estimate_table(None, _balls_at(on_cloth), size, spec, cues="surface", surface=surface)
    assert min(np.abs(np.roll(fit.corners_px, k, axis=0) - truth).max() for k in (0, 2)) < 2.0
    off_table = np.array([[30.0, 30.0], [60.0, 40.0], [90.0, 30.0]])
    assert not quad_mask(truth, (size[1], size[0]))[off_table[:, 1].astype(int), off_table[:, 0].astype(int)].any()
    with pytest.raises(TableFitError, match="holds none of the 3 balls"):
        estimate_table(None, _balls_at(off_table), size, spec, cues="surface", surface=surface)
    two = estimate_table(None, _balls_at(off_table[:2]), size, spec, cues="surface", surface=surface)
    assert two.source == "surface"  # two stray balls are too few to overrule the outline


def _shifted_and_true_outlines(camera: PinholeCamera, spec: TableSpec) -> tuple[np.ndarray, np.ndarray]:
    """The playing surface's corners in the photo [px], and the same table moved 0.45 m towards the foot (a surface
    region that leaked onto the foot rail, short of the head cushion)."""
    return camera.project_table(spec.corners + np.array([0.45, 0.0]), 0.0), camera.project_table(spec.corners, 0.0)


def test_of_two_surface_outlines_the_one_on_the_cloth_edges_wins():
    """A table shifted along its length is a rectangle a camera sees, but only its long sides lie on the cloth's edge
    in the photo. The corner peaks' outline, whose four sides all do, wins though it comes second; without the photo
    the first outline's fit stays."""
    spec = TableSpec()
    camera = view("oblique")
    size = camera.image_size
    rgb, boxes = draw_table_photo(camera, spec)
    shifted, truth = _shifted_and_true_outlines(camera, spec)
    det = Detections(boxes, np.full(len(boxes), 0.9), np.full(len(boxes), 2))
    alone = estimate_table(rgb, det, size, spec, cues="surface", surface=outline_of(shifted, size))
    assert min(np.abs(np.roll(alone.corners_px, k, axis=0) - truth).max() for k in (0, 2)) > 20.0
    surface = outline_of(shifted, size, alternative=outline_of(truth, size))
    fit = estimate_table(rgb, det, size, spec, cues="surface", surface=surface)
    assert edge_sides(rgb, fit, surface.mask, boxes) == 4
    assert edge_sides(rgb, alone, surface.mask, boxes) < 4
    assert min(np.abs(np.roll(fit.corners_px, k, axis=0) - truth).max() for k in (0, 2)) < 3.0
    assert outline_used(fit, surface) is surface.alternative
    blind = estimate_table(None, det, size, spec, cues="surface", surface=surface)
    assert outline_used(blind, surface) is surface


def test_a_surface_fit_on_more_cloth_edges_but_fewer_balls_loses():
    """The second outline's fit wins on the cloth's edges only while it holds as many balls: a table drawn 15 cm
    wider all round lies on the rails, yet it holds two balls off the true one's cloth, and stays."""
    spec = TableSpec()
    camera = view("oblique")
    size = camera.image_size
    rgb, boxes = draw_table_photo(camera, spec)
    truth = estimate_table(
        rgb,
        Detections.empty(),
        size,
        spec,
        cues="surface",
        surface=outline_of(camera.project_table(spec.corners, 0.0), size),
    )
    grow = 0.15
    wider = replace(spec, length=spec.length + 2 * grow, width=spec.width + 2 * grow)
    moved = PinholeCamera(camera.K, camera.R, camera.t - camera.R @ np.array([grow, grow, 0.0]), size)
    wide = replace(truth, spec=wider, camera=moved)
    assert (
        np.abs(
            wide.camera.project_table(np.array([[grow, grow]]), 0.0) - camera.project_table(np.zeros((1, 2)), 0.0)
        ).max()
        < 1e-6
    )
    mask = quad_mask(truth.corners_px, (size[1], size[0]))
    assert edge_sides(rgb, truth, mask, boxes) > edge_sides(rgb, wide, mask, boxes)
    assert better_surface_fit([wide, truth], rgb, mask, boxes) is truth
    on_rails = camera.project_table(np.array([[-0.08, 0.5], [-0.08, 0.8]]), spec.ball_radius)
    more = np.concatenate([boxes, np.column_stack([on_rails - 8, on_rails + 8])])
    assert better_surface_fit([wide, truth], rgb, mask, more) is wide
    assert better_surface_fit([truth, wide], rgb, mask, more) is truth
    assert better_surface_fit([wide, truth], None, mask, boxes) is wide
    assert better_surface_fit([], rgb, mask, boxes) is None


def test_a_close_view_across_the_table_is_fitted_from_its_two_long_cushions():
    """Only the two long cushions are in view, each with its side pocket: the surface outline shows two cushions
    (no rectangle from it), and the table comes from the two lines and the pockets."""
    from tests.vision.table.test_surface import IMAGE, _with_peaks, cues_of

    spec = TableSpec()
    camera = PinholeCamera.look_at(np.array([1.2, -0.7, 0.6]), np.array([1.25, 0.5, 0.0]), 0.9 * IMAGE[0], IMAGE)
    corners = camera.project_table(spec.corners, 0.0)
    pockets_xy = np.array([[spec.length / 2, 0.0], [spec.length / 2, spec.width]])
    pockets = camera.project_table(pockets_xy, 0.0)
    assert not any(0 <= x <= IMAGE[0] and 0 <= y <= IMAGE[1] for x, y in corners)
    surface = surface_outline(_with_peaks(cues_of(corners), np.zeros((0, 2)), pockets))
    with pytest.raises(TableFitError, match="2 cushions"):
        estimate_table(None, Detections.empty(), IMAGE, spec, cues="surface", surface=replace(surface, cues=None))
    fit = estimate_table(None, Detections.empty(), IMAGE, spec, cues="surface", surface=surface)
    assert fit.source == "surface"
    probes = np.array([[spec.length / 2, 0.0], [spec.length / 2, spec.width], [1.0, 0.6], [1.6, 0.9]])
    xy = fit.image_to_table(camera.project_table(probes, 0.0), 0.0)
    turned = np.column_stack([spec.length - xy[:, 0], spec.width - xy[:, 1]])
    assert min(np.abs(xy - probes).max(), np.abs(turned - probes).max()) < 0.03

"""Diamond-plane height from the cushion nose edges (vision/table/rail_height.py)."""

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from pix2pockets.data.examples import example_labels_path, example_photo_path
from pix2pockets.geometry import TableSpec, table_preset
from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.pipeline.photo import load_image
from pix2pockets.vision.detect.analytic import detections_from_synth_labels, standard_views
from pix2pockets.vision.table.fit import diamond_height, fit_table
from pix2pockets.vision.table.rail_height import estimate_rail_height, refine_fit_height

SPEC = TableSpec()


SS = 8  # supersampling of the painted images


def _poly(cam: PinholeCamera, xy: np.ndarray, z: float) -> np.ndarray:
    # supersampled pixel j has its centre at (j + 0.5) / SS in camera pixels; cv2 puts it on the integer j
    return np.round((cam.project_table(xy, z) * SS - 0.5) * 16).astype(np.int32)


def painted_table(cam: PinholeCamera, rise: float) -> np.ndarray:
    """A flat-shaded table: dark rail cap (at the diamonds), bright cushion tops, mid cloth inside the noses
    (area-sampled edges, a little lens blur and noise)."""
    w, h = cam.image_size
    big = np.full((h * SS, w * SS), 50, np.uint8)
    L, W = SPEC.length, SPEC.width
    hc = SPEC.cushion_height

    def rect(m: float) -> np.ndarray:
        return np.array([[-m, -m], [L + m, -m], [L + m, W + m], [-m, W + m]])

    for xy, z, grey in ((rect(0.16), hc + rise, 35), (rect(0.05), hc, 170), (rect(0.0), hc, 105)):
        cv2.fillPoly(big, [_poly(cam, xy, z)], grey, shift=4)
    img = cv2.resize(big.astype(np.float32), (w, h), interpolation=cv2.INTER_AREA)
    img = cv2.GaussianBlur(img, (0, 0), 0.7)
    rng = np.random.default_rng(0)
    img = np.clip(img + rng.normal(0, 2.0, img.shape), 0, 255).astype(np.uint8)
    return np.repeat(img[:, :, None], 3, axis=2)


@pytest.mark.parametrize("view", ["45", "front"])
@pytest.mark.parametrize("rise", [0.004, 0.013])
def test_recovers_the_rise_of_a_painted_table(view, rise):
    cam = standard_views(SPEC, (960, 540))[view]
    diamonds = cam.project_table(SPEC.diamonds, SPEC.cushion_height + rise)
    fit = fit_table(diamonds, cam.image_size, SPEC)  # assumes the typical height
    assert fit.diamond_z == pytest.approx(diamond_height(SPEC))
    est = estimate_rail_height(painted_table(cam, rise), fit)
    assert est.measured, est.reason
    assert est.rise == pytest.approx(rise, abs=0.001)
    refined, _ = refine_fit_height(painted_table(cam, rise), fit)
    assert refined.diamond_z == pytest.approx(SPEC.cushion_height + rise, abs=0.001)
    # the cloth homography now matches the true camera's
    truth = cam.project_table(SPEC.corners, 0.0)
    assert np.abs(refined.corners_px - truth).max() < 0.5
    assert np.abs(fit.corners_px - truth).max() > 0.5 or view == "45"


def test_featureless_image_keeps_the_fit():
    cam = standard_views(SPEC)["front"]
    fit = fit_table(cam.project_table(SPEC.diamonds, diamond_height(SPEC)), cam.image_size, SPEC)
    blank = np.full((cam.image_size[1], cam.image_size[0], 3), 90, np.uint8)
    refined, est = refine_fit_height(blank, fit)
    assert not est.measured and est.reason
    assert refined is fit


def test_table_out_of_view_keeps_the_fit():
    cam = standard_views(SPEC)["top"]
    fit = fit_table(cam.project_table(SPEC.diamonds, diamond_height(SPEC)), cam.image_size, SPEC)
    tiny = np.full((40, 60, 3), 90, np.uint8)  # every nose sample falls outside this image
    est = estimate_rail_height(tiny, fit)
    assert not est.measured
    assert est.diamond_z == fit.diamond_z


def test_with_diamond_z_equals_a_fit_at_that_height():
    cam = standard_views(SPEC)["front"]
    diamonds = cam.project_table(SPEC.diamonds, diamond_height(SPEC))
    a = fit_table(diamonds, cam.image_size, SPEC).with_diamond_z(0.05)
    b = fit_table(diamonds, cam.image_size, SPEC, diamond_z=0.05)
    assert a.diamond_z == b.diamond_z == 0.05
    assert np.allclose(a.camera.t, b.camera.t, atol=1e-6)
    assert np.allclose(a.corners_px, b.corners_px, atol=1e-3)


def test_rendered_example_height_within_a_few_mm():
    labels = json.loads(Path(example_labels_path()).read_text())
    spec = table_preset(labels["table"]["name"])
    det = detections_from_synth_labels(labels)
    fit = fit_table(det, tuple(labels["image_size"]), spec)
    refined, est = refine_fit_height(load_image(example_photo_path()), fit, det[det.is_ball].boxes)
    true_z = labels["heights_m"]["diamonds"]
    assert abs(refined.diamond_z - true_z) <= abs(fit.diamond_z - true_z) + 0.001
    if est.measured:
        assert abs(refined.diamond_z - true_z) < 0.004

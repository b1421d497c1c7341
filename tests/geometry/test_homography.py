import math

import cv2
import numpy as np
import pytest

from pix2pockets.geometry import PinholeCamera, TableSpec
from pix2pockets.geometry.homography import (
    apply_homography,
    camera_from_homography,
    camera_tilt,
    fit_homography,
    image_to_table,
    rotated_points_jacobian,
)


def oblique_camera() -> PinholeCamera:
    return PinholeCamera.look_at(np.array([-0.8, -1.0, 2.2]), np.array([1.27, 0.635, 0.0]), 950.0, (1280, 720))


def test_fit_homography_recovers_exact_map():
    cam = oblique_camera()
    H = cam.table_homography(0.0)
    xy = np.random.default_rng(0).uniform([0, 0], [2.5, 1.2], (10, 2))
    Hf = fit_homography(xy, cam.project_table(xy))
    np.testing.assert_allclose(Hf / Hf[2, 2], H / H[2, 2], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(apply_homography(Hf, xy), cam.project_table(xy), atol=1e-6)


@pytest.mark.parametrize(
    ("src", "dst"),
    [
        (np.zeros((3, 2)), np.zeros((3, 2))),  # too few
        (np.array([[0, 0], [1, 1], [2, 2], [3, 3.0]]), np.array([[0, 0], [1, 0], [0, 1], [1, 1.0]])),  # collinear
    ],
)
def test_fit_homography_rejects_bad_input(src, dst):
    with pytest.raises(ValueError):
        fit_homography(src, dst)


def test_camera_from_homography_oblique():
    cam = oblique_camera()
    spec = TableSpec()
    z = spec.cushion_height
    rec = camera_from_homography(cam.table_homography(z), cam.image_size, z=z)
    assert rec.focal_px == pytest.approx(950.0, rel=1e-3)
    np.testing.assert_allclose(rec.position, cam.position, atol=1e-3)
    # the recovered camera gives the cloth homography too
    np.testing.assert_allclose(rec.project_table(spec.corners, 0.0), cam.project_table(spec.corners, 0.0), atol=0.05)


def test_camera_from_homography_refines_on_points_with_prior_for_top_view():
    spec = TableSpec()
    centre = np.array([*spec.size / 2, 0.0])
    cam = PinholeCamera.look_at(centre + np.array([0, 0, 3.0]), centre, 1200.0, (1280, 720))
    z = spec.cushion_height
    world = np.column_stack([spec.diamonds, np.full(18, z)])
    rec = camera_from_homography(
        cam.table_homography(z), cam.image_size, z=z, world_points=world, image_points=cam.project(world)
    )
    # focal length is not observable from a fronto-parallel plane: the image of that plane must still match
    np.testing.assert_allclose(rec.project(world), cam.project(world), atol=0.05)
    assert camera_tilt(rec) == pytest.approx(0.0, abs=1e-3)


@pytest.mark.parametrize("rvec", [[0.3, -1.2, 2.0], [1e-7, 0.0, -2e-7], [0.0, 0.0, 0.0], [0.0, 3.1, 0.1]])
def test_rotated_points_jacobian_matches_finite_differences(rvec):
    rvec = np.array(rvec, dtype=float)
    points = np.random.default_rng(1).normal(size=(5, 3))

    def rotation(w: np.ndarray) -> np.ndarray:
        return cv2.Rodrigues(w.reshape(3, 1))[0]

    jac = rotated_points_jacobian(rvec, rotation(rvec), points)
    step = 1e-6
    for k in range(3):
        dw = np.zeros(3)
        dw[k] = step
        numeric = (points @ rotation(rvec + dw).T - points @ rotation(rvec - dw).T) / (2 * step)
        np.testing.assert_allclose(jac[:, :, k], numeric, atol=1e-5)


def test_camera_from_homography_refines_an_oblique_view_from_noisy_points():
    cam = oblique_camera()
    spec = TableSpec()
    z = spec.cushion_height
    world = np.column_stack([spec.diamonds, np.full(18, z)])
    noisy = cam.project(world) + np.random.default_rng(2).normal(0.0, 0.3, (18, 2))
    H = fit_homography(spec.diamonds, noisy)
    rec = camera_from_homography(H, cam.image_size, z=z, world_points=world, image_points=noisy)
    assert rec.focal_px == pytest.approx(950.0, rel=0.02)
    np.testing.assert_allclose(rec.position, cam.position, atol=0.02)
    assert np.abs(rec.project(world) - noisy).max() < 1.5


def test_image_to_table_inverts_projection():
    cam = oblique_camera()
    xy = np.array([[0.3, 0.2], [2.0, 1.1]])
    np.testing.assert_allclose(image_to_table(cam, cam.project_table(xy, 0.02), 0.02), xy, atol=1e-9)
    assert camera_tilt(cam) == pytest.approx(math.atan2(math.hypot(2.07, 1.635), 2.2), abs=1e-6)

import numpy as np
import pytest

from pix2pockets.geometry import PinholeCamera, TableSpec


def make_camera(eye=(1.27, -1.5, 2.0)) -> PinholeCamera:
    spec = TableSpec()
    return PinholeCamera.look_at(np.array(eye), np.array([*(spec.size / 2), 0.0]), 900.0, (1280, 720))


def test_target_projects_to_image_centre():
    cam = make_camera()
    uv = cam.project_table(TableSpec().size / 2)
    np.testing.assert_allclose(uv, [640, 360], atol=1e-9)


def test_homography_matches_projection():
    cam = make_camera()
    H = cam.table_homography()
    xy = np.array([[0.1, 0.2], [2.0, 1.0], [1.27, 0.635]])
    h = np.column_stack([xy, np.ones(3)]) @ H.T
    np.testing.assert_allclose(h[:, :2] / h[:, 2:], cam.project_table(xy), atol=1e-9)


def test_position_and_behind():
    cam = make_camera()
    np.testing.assert_allclose(cam.position, [1.27, -1.5, 2.0])
    assert np.isnan(cam.project(np.array([1.27, -5.0, 5.0]))).all()


def test_top_down_view_keeps_x_right():
    spec = TableSpec()
    cam = PinholeCamera.look_at(np.array([*(spec.size / 2), 3.0]), np.array([*(spec.size / 2), 0.0]), 500, (800, 600))
    a, b = cam.project_table(np.array([[1.0, 0.6], [1.5, 0.6]]))
    assert b[0] > a[0]


def test_bad_camera():
    with pytest.raises(ValueError):
        PinholeCamera.look_at(np.zeros(3), np.zeros(3), 500, (10, 10))


def test_a_scaled_camera_sees_the_resized_photo():
    cam = make_camera()
    xy = np.array([[0.1, 0.2], [2.0, 1.0], [1.27, 0.635]])
    big = cam.scaled(3.0, 2.5, (3840, 1800))
    assert big.image_size == (3840, 1800)
    np.testing.assert_allclose(big.project_table(xy), cam.project_table(xy) * [3.0, 2.5], atol=1e-9)
    np.testing.assert_allclose(big.position, cam.position)

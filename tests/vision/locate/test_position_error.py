"""Each ball's position error: the image error mapped through the fitted camera, widened by a shaky fit."""

from __future__ import annotations

import numpy as np
import pytest

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.table import TableSpec
from pix2pockets.vision.locate.position_error import (
    BALL_CENTRE_SIGMA_PX,
    FIT_ERROR_SHARE,
    MAX_POSITION_SIGMA,
    POSITION_FLOOR,
    position_covariances,
    position_sigmas,
)

SPEC = TableSpec()
R = SPEC.ball_radius
SIZE = (1280, 720)
CENTRE = np.array([SPEC.length / 2, SPEC.width / 2, 0.0])
BALLS = np.array([[0.3, 0.6], [1.27, 0.6], [2.3, 0.6]])  # near, middle and far end seen from behind the foot rail


def top_view() -> PinholeCamera:
    return PinholeCamera.look_at(CENTRE + np.array([0, 0, 3.0]), CENTRE, 1100.0, SIZE)


def low_view() -> PinholeCamera:
    return PinholeCamera.look_at(np.array([-0.8, SPEC.width / 2, 1.5]), CENTRE, 1000.0, SIZE)


def numeric_covariance(camera: PinholeCamera, xy: np.ndarray, pixel_sigma: float) -> np.ndarray:
    """The same covariance from a finite-difference Jacobian of the camera's projection."""
    eps = 1e-6
    p = camera.project_table(xy, R)
    jac = np.stack([(camera.project_table(xy + eps * e, R) - p) / eps for e in np.eye(2)], axis=-1)
    m = np.linalg.inv(jac)
    return pixel_sigma**2 * m @ np.transpose(m, (0, 2, 1)) + np.eye(2) * POSITION_FLOOR**2


@pytest.mark.parametrize("camera", [top_view(), low_view()])
@pytest.mark.parametrize("rms_px", [0.0, 2.5])
def test_the_image_error_is_mapped_through_the_camera(camera, rms_px):
    cov = position_covariances(camera, BALLS, R, rms_px)
    expected = numeric_covariance(camera, BALLS, np.hypot(BALL_CENTRE_SIGMA_PX, FIT_ERROR_SHARE * rms_px))
    np.testing.assert_allclose(cov, expected, rtol=1e-5)


def test_far_balls_of_a_low_view_are_less_sure_and_a_top_view_is_even():
    low = position_sigmas(position_covariances(low_view(), BALLS, R, 0.0))
    assert low[0] < low[1] < low[2]
    assert low[2] > 2 * low[0]
    top = position_sigmas(position_covariances(top_view(), BALLS, R, 0.0))
    np.testing.assert_allclose(top, top[0], rtol=0.05)
    # a 2.5 mm pixel from 3 m: about 3 mm per axis
    assert 0.002 < top[0] < 0.004


def test_a_shaky_fit_widens_every_ball():
    sure = position_sigmas(position_covariances(low_view(), BALLS, R, 0.5))
    shaky = position_sigmas(position_covariances(low_view(), BALLS, R, 12.0))
    assert np.all(shaky > 2 * sure)


def test_no_fit_error_is_none_and_errors_are_capped():
    cam = low_view()
    np.testing.assert_array_equal(position_covariances(cam, BALLS, R, None), position_covariances(cam, BALLS, R, 0.0))
    np.testing.assert_array_equal(
        position_covariances(cam, BALLS, R, float("nan")), position_covariances(cam, BALLS, R, 0.0)
    )
    huge = position_sigmas(position_covariances(cam, BALLS, R, 1e4))
    np.testing.assert_allclose(huge, MAX_POSITION_SIGMA)
    assert position_covariances(cam, np.zeros((0, 2)), R, 1.0).shape == (0, 2, 2)


def test_a_box_cut_by_something_unseen_widens_its_ball_along_that_axis():
    cam = top_view()  # image y runs across the table here
    cov = position_covariances(cam, BALLS, R, 0.0)
    cut = position_covariances(cam, BALLS, R, 0.0, np.array([[0.0, 0.0], [0.0, 8.0], [0.0, 0.0]]))
    np.testing.assert_allclose(cut[[0, 2]], cov[[0, 2]])
    expected = numeric_covariance(cam, BALLS[1:2], np.hypot(BALL_CENTRE_SIGMA_PX, 0.0))
    m = np.linalg.inv(
        np.stack(
            [
                (cam.project_table(BALLS[1:2] + 1e-6 * e, R) - cam.project_table(BALLS[1:2], R)) / 1e-6
                for e in np.eye(2)
            ],
            axis=-1,
        )
    )[0]
    expected = expected[0] + m @ np.diag([0.0, 4.0**2]) @ m.T
    np.testing.assert_allclose(cut[1], expected, rtol=1e-4)
    assert position_sigmas(cut)[1] > 3 * position_sigmas(cov)[1]

import numpy as np
import pytest

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.pipeline.unseen_pockets import (
    MAX_POCKET_SIGMA,
    distances_out_of_photo,
    pocket_hit_share,
    pocket_sigmas,
    pockets_in_photo,
)
from pix2pockets.testing import SPEC

SIZE = (960, 540)


def top_view(shift: float, height: float = 2.0) -> PinholeCamera:
    """A top view over the table's centre moved ``shift`` [m] toward its foot, from ``height`` [m] above."""
    target = np.array([SPEC.length / 2 + shift, SPEC.width / 2, 0.0])
    return PinholeCamera.look_at(target + np.array([0.0, 0.0, height]), target, 700.0, SIZE)


def test_a_whole_table_shows_every_pocket():
    cam = top_view(0.0, 3.5)
    assert pockets_in_photo(cam, SPEC, SIZE).all()
    assert np.all(pocket_sigmas(cam, SPEC, SIZE) == 0.0)
    assert np.all(distances_out_of_photo(cam, SPEC, SIZE, SPEC.corners) < 0.02)


def test_the_head_pockets_of_a_table_cut_by_the_frame_are_unsure():
    cam = top_view(0.6)  # the head end out of the photo
    head = np.array([p.centre[0] < 0.1 for p in SPEC.pockets])
    seen = pockets_in_photo(cam, SPEC, SIZE)
    assert not seen[head].any() and seen[~head].all()
    sigmas = pocket_sigmas(cam, SPEC, SIZE)
    assert np.all(sigmas[head] > 0) and np.all(sigmas[~head] == 0)
    assert np.all(sigmas <= MAX_POCKET_SIGMA)
    # the further a point lies from the part of the table in the photo, the further it is
    far = distances_out_of_photo(cam, SPEC, SIZE, np.array([[0.0, 0.6], [0.3, 0.6], [2.0, 0.6]]))
    assert far[0] > far[1] > 0.0 == far[2]


def test_a_camera_that_sees_no_table_puts_every_point_infinitely_far():
    cam = PinholeCamera.look_at(np.array([10.0, 10.0, 2.0]), np.array([20.0, 20.0, 0.0]), 700.0, SIZE)
    assert np.all(np.isinf(distances_out_of_photo(cam, SPEC, SIZE, SPEC.corners)))
    assert not pockets_in_photo(cam, SPEC, SIZE).any()


def test_a_pocket_takes_fewer_errors_the_larger_they_are():
    shares = [pocket_hit_share(SPEC, 0, sigma) for sigma in (0.0, 0.01, 0.05, 0.15)]
    assert shares[0] == 1.0
    assert shares[0] > shares[1] > shares[2] > shares[3] > 0.0
    # a 2 cm free half-width against 15 cm of error: about a sixth
    assert shares[3] == pytest.approx(0.15, abs=0.08)

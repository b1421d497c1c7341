"""Cameras from a table's cloth outline: corners outside the photo weigh less than the ones it shows."""

from __future__ import annotations

import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.table import TableSpec
from pix2pockets.vision.table.outline_camera import (
    CUSHION_WIDTH,
    camera_from_outline,
    off_frame_weights,
    outline_rectangle,
)

SPEC = TableSpec()
SIZE = (960, 540)


def test_corners_inside_the_photo_weigh_one_and_outside_less_the_further_out():
    corners = np.array([[10.0, 10.0], [950.0, 530.0], [-110.0, 300.0], [960.0 + 1100.0, 300.0]])
    weights = off_frame_weights(corners, SIZE)
    assert weights[0] == weights[1] == 1.0
    assert weights[3] < weights[2] < 0.5  # 0.1 and 1.0 of the image diagonal out
    assert weights[3] < 0.1


def test_a_far_off_corner_read_badly_does_not_pull_the_corners_in_the_photo():
    """A low view at a corner: one cloth corner lies far outside the photo, where two cushion lines meeting at a
    glancing angle put it; read a few hundred pixels wrong, the camera still sees the three corners in the photo
    where they are."""
    centre = np.array([*SPEC.size / 2, 0.0])
    camera = PinholeCamera.look_at(np.array([-0.6, -0.6, 0.4]), centre + np.array([0.6, 0.0, 0.0]), 800.0, SIZE)
    world = outline_rectangle(SPEC, CUSHION_WIDTH)
    exact = camera.project_table(world, SPEC.cushion_height)
    inside = (exact[:, 0] >= 0) & (exact[:, 0] <= SIZE[0]) & (exact[:, 1] >= 0) & (exact[:, 1] <= SIZE[1])
    assert inside.sum() == 3, exact
    read = exact.copy()
    read[~inside] += np.array([-300.0, 60.0])
    fitted, _, _ = camera_from_outline(read, SIZE, SPEC)
    seen = fitted.project_table(world, SPEC.cushion_height)
    assert np.linalg.norm(seen[inside] - exact[inside], axis=1).max() < 1.5

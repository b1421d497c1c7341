"""Quadrilaterals in the image: the share of a table's outline inside the photo."""

from __future__ import annotations

import numpy as np
import pytest

from pix2pockets.vision.table.quad_geometry import share_in_frame

SIZE = (200, 100)


@pytest.mark.parametrize(
    "quad, share",
    [
        ([[20, 10], [180, 10], [180, 90], [20, 90]], 1.0),  # inside
        ([[100, 10], [300, 10], [300, 90], [100, 90]], 0.5),  # half past the right edge
        ([[-50, -50], [-10, -50], [-10, -10], [-50, -10]], 0.0),  # wholly outside
        ([[-100, -100], [300, -100], [300, 200], [-100, 200]], 200 * 100 / (400 * 300)),  # around the frame
    ],
)
def test_share_of_a_quad_inside_the_frame(quad, share):
    assert share_in_frame(np.array(quad, dtype=float), SIZE) == pytest.approx(share, abs=1e-3)


def test_a_corner_behind_the_camera_or_no_area_is_nothing_in_view():
    quad = np.array([[20, 10], [180, 10], [np.nan, np.nan], [20, 90]])
    assert share_in_frame(quad, SIZE) == 0.0
    assert share_in_frame(np.array([[10, 10], [20, 20], [30, 30], [40, 40]], dtype=float), SIZE) == 0.0

"""The pixel aspect of a stretched photo, read from its ball boxes."""

import numpy as np
import pytest

from pix2pockets.vision.pixel_aspect import pixel_aspect_of_balls, snapped_aspect


def test_pixel_aspect_of_balls_reads_a_common_stretch_and_ignores_small_or_doubtful_ones():
    round_boxes = np.array([[0, 0, 10, 10], [20, 0, 31, 10], [40, 0, 49, 10], [60, 0, 66, 10.0]])
    assert pixel_aspect_of_balls(round_boxes) == 1.0  # median 1.0; the half-hidden ball does not count
    squashed = round_boxes * np.array([0.5625, 1, 0.5625, 1])
    assert pixel_aspect_of_balls(squashed) == pytest.approx(0.5625, rel=0.05)
    assert pixel_aspect_of_balls(squashed[:2]) == 1.0  # too few balls to tell
    assert pixel_aspect_of_balls(squashed, np.array([0.9, 0.1, 0.1, 0.9])) == 1.0  # too few confident ones


def test_snapped_aspect_takes_a_nearby_export_stretch():
    assert snapped_aspect(0.58) == 0.5625
    assert snapped_aspect(1.03) == 1.0
    assert snapped_aspect(0.65) == 0.65  # between 0.5625 and 0.75: kept as measured

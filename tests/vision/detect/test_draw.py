"""Detections drawn on a photo: boxes, labels, and ball numbers when known."""

import numpy as np

from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.draw import draw_detections


def _one_solid() -> Detections:
    return Detections(np.array([[40.0, 40, 60, 60]]), np.array([0.9]), np.array([2]))


def test_draws_a_copy_and_leaves_faint_detections_out():
    image = np.zeros((100, 100, 3), np.uint8)
    drawn = draw_detections(image, _one_solid())
    assert drawn.shape == image.shape and drawn.any() and not image.any()
    assert not draw_detections(image, _one_solid(), min_confidence=0.95).any()


def test_a_known_number_changes_the_label_an_unknown_one_does_not():
    image = np.zeros((100, 100, 3), np.uint8)
    plain = draw_detections(image, _one_solid())
    assert np.array_equal(draw_detections(image, _one_solid(), numbers=np.array([-1])), plain)
    assert not np.array_equal(draw_detections(image, _one_solid(), numbers=np.array([3])), plain)

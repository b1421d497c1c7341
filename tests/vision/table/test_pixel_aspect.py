"""The pixel aspect of a stretched photo, read from its ball boxes."""

import cv2
import numpy as np
import pytest

from pix2pockets.vision.table.pixel_aspect import (
    ball_outline_aspect,
    boxes_in_aspect,
    pixel_aspect_of_balls,
    pixel_aspect_of_photo,
    snapped_aspect,
)


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


def _squashed_balls(aspect: float, size=(300, 300), n=5):
    """A cloth-green photo with n white balls (radius 10 rows) squashed to ``aspect``; round boxes as a
    detector that ignores the stretch would give."""
    img = np.zeros((*size, 3), np.uint8)
    img[:] = (30, 110, 60)
    centres = [(40 + 50 * k, 60 + 35 * k) for k in range(n)]
    for cx, cy in centres:
        cv2.ellipse(img, (cx, cy), (round(10 * aspect), 10), 0, 0, 360, (235, 235, 230), -1)
    half = 10 * (1 + aspect) / 2
    boxes = np.array([[cx - half, cy - half, cx + half, cy + half] for cx, cy in centres])
    return img, boxes, np.full(n, 0.9)


@pytest.mark.parametrize("aspect", [0.5625, 0.75, 1.0])
def test_ball_outline_aspect_measures_the_squash(aspect):
    img, boxes, _ = _squashed_balls(aspect)
    assert ball_outline_aspect(img, boxes[0]) == pytest.approx(aspect, rel=0.08)


def test_square_photo_with_round_boxes_gets_its_aspect_from_the_outlines():
    img, boxes, scores = _squashed_balls(0.5625)
    assert pixel_aspect_of_balls(boxes, scores) == 1.0  # the boxes do not show it
    assert pixel_aspect_of_photo(img, boxes, scores) == 0.5625
    round_img, round_boxes, _ = _squashed_balls(1.0)
    assert pixel_aspect_of_photo(round_img, round_boxes, scores) == 1.0
    wide, wide_boxes, _ = _squashed_balls(0.5625, size=(300, 420))
    assert pixel_aspect_of_photo(wide, wide_boxes, scores) == 1.0  # only square photos are suspected


def test_ball_outline_aspect_is_nan_at_the_border_or_on_plain_cloth():
    img, boxes, _ = _squashed_balls(1.0)
    assert np.isnan(ball_outline_aspect(img, np.array([0.0, 0.0, 12.0, 12.0])))
    cloth = np.full_like(img, 90)
    assert np.isnan(ball_outline_aspect(cloth, boxes[2]))


def test_boxes_in_aspect_keeps_centres_and_areas():
    boxes = np.array([[10, 10, 30, 30], [50, 40, 70, 62], [100, 100, 118, 118.0]])
    scores = np.full(3, 0.9)
    out = boxes_in_aspect(boxes, scores, 0.5625)
    w, h = out[:, 2] - out[:, 0], out[:, 3] - out[:, 1]
    assert np.median(w / h) == pytest.approx(0.5625)
    np.testing.assert_allclose(out[:, :2] + out[:, 2:], boxes[:, :2] + boxes[:, 2:])
    np.testing.assert_allclose(w * h, (boxes[:, 2] - boxes[:, 0]) * (boxes[:, 3] - boxes[:, 1]))
    assert np.array_equal(boxes_in_aspect(boxes, scores, 1.0), boxes)  # a photo as taken keeps its boxes

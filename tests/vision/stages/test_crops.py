"""Scale-normalised ball crops: centred, the same size whatever the ball size, edges repeated."""

import cv2
import numpy as np
import pytest

from pix2pockets.vision.stages.crops import CROP_CONTEXT, CROP_SIZE, ball_diameters, crop_balls


def _disc_image(cx: float, cy: float, r: float, shape=(200, 300)) -> np.ndarray:
    yy, xx = np.mgrid[: shape[0], : shape[1]]
    inside = (xx + 0.5 - cx) ** 2 + (yy + 0.5 - cy) ** 2 <= r * r
    img = np.zeros((*shape, 3), np.uint8)
    img[inside] = 255
    return img


@pytest.mark.parametrize("r", [4.0, 10.0, 40.0])
def test_a_ball_fills_the_same_part_of_the_crop_at_any_size(r):
    img = _disc_image(150, 100, r, shape=(300, 300))
    crop = crop_balls(img, np.array([[150.0, 100.0]]), np.array([2 * r]))[0]
    assert crop.shape == (CROP_SIZE, CROP_SIZE, 3)
    bright = crop[..., 0] > 127
    expected = np.pi * (CROP_SIZE / CROP_CONTEXT / 2) ** 2
    assert bright.sum() == pytest.approx(expected, rel=0.2)
    ys, xs = np.nonzero(bright)
    assert xs.mean() == pytest.approx(CROP_SIZE / 2 - 0.5, abs=1.0)
    assert ys.mean() == pytest.approx(CROP_SIZE / 2 - 0.5, abs=1.0)


def test_crops_past_the_edge_repeat_edge_pixels():
    img = np.zeros((50, 50, 3), np.uint8)
    img[:, 0] = 200
    crop = crop_balls(img, np.array([[0.0, 25.0]]), np.array([20.0]))[0]
    assert np.all(crop[:, 0, 0] == 200)  # left half repeats the bright first column


def test_diameters_and_bad_input():
    assert ball_diameters(np.array([[0, 0, 10, 14]])).tolist() == [12.0]
    assert ball_diameters(np.array([[5, 5, 5, 5]])).tolist() == [2.0]
    with pytest.raises(ValueError, match="centres"):
        crop_balls(np.zeros((10, 10, 3), np.uint8), np.zeros((2, 2)), np.ones(3))
    assert crop_balls(np.zeros((10, 10, 3), np.uint8), np.zeros((0, 2)), np.zeros(0)).shape == (0, 32, 32, 3)


def test_a_ball_in_a_stretched_photo_comes_out_round():
    """A 16:9 frame squashed to a square: a ball 20 rows tall is 11 columns wide; the crop undoes that."""
    aspect = 0.5625
    img = _disc_image(150, 100, 10.0, shape=(300, 300))
    squashed = cv2.resize(img, (round(300 * aspect), 300), interpolation=cv2.INTER_AREA)
    box = np.array([[150 * aspect - 10 * aspect, 90.0, 150 * aspect + 10 * aspect, 110.0]])
    d = ball_diameters(box, aspect)
    assert d[0] == pytest.approx(20.0)
    crop = crop_balls(squashed, np.array([[150 * aspect, 100.0]]), d, aspect=aspect)[0]
    ys, xs = np.nonzero(crop[..., 0] > 127)
    assert (xs.max() - xs.min()) == pytest.approx(ys.max() - ys.min(), rel=0.15)
    plain = crop_balls(squashed, np.array([[150 * aspect, 100.0]]), ball_diameters(box))[0]
    ys, xs = np.nonzero(plain[..., 0] > 127)
    assert (ys.max() - ys.min()) > 1.5 * (xs.max() - xs.min())  # without the aspect the ball stays squashed

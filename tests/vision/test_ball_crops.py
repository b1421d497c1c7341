"""Scale-normalised ball crops: centred, the same size whatever the ball size, edges repeated."""

import numpy as np
import pytest

from pix2pockets.vision.ball_crops import CROP_CONTEXT, CROP_SIZE, ball_diameters, crop_balls


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

"""Flat ball icons for "no ball" crops: shape, determinism, a disc in the middle sized like a ball crop's."""

import numpy as np

from pix2pockets.vision.stages.crops import CROP_SIZE
from pix2pockets.vision.train.icon_crops import ball_icon_crops


def test_icon_crops_are_uint8_crops_and_repeat_with_the_seed():
    a = ball_icon_crops(6, np.random.default_rng(3))
    assert a.shape == (6, CROP_SIZE, CROP_SIZE, 3) and a.dtype == np.uint8
    assert np.array_equal(a, ball_icon_crops(6, np.random.default_rng(3)))
    assert not np.array_equal(a, ball_icon_crops(6, np.random.default_rng(4)))
    assert ball_icon_crops(2, np.random.default_rng(0), crop_size=48).shape == (2, 48, 48, 3)


def test_an_icon_fills_the_middle_of_its_crop_as_a_ball_does():
    crops = ball_icon_crops(200, np.random.default_rng(1)).astype(float)
    yy, xx = np.mgrid[0:CROP_SIZE, 0:CROP_SIZE] + 0.5
    r = np.hypot(xx - CROP_SIZE / 2, yy - CROP_SIZE / 2) / CROP_SIZE  # in crop sides
    inner, corners = r < 0.25, r > 0.62  # the disc is 1 / 1.5 of the crop wide; corners are panel
    # an icon differs from its panel: the middle and the corners are far apart in colour on most crops
    gap = np.linalg.norm(crops[:, inner].mean(axis=1) - crops[:, corners].mean(axis=1), axis=1)
    assert np.median(gap) > 40
    # and the panel is flat or graded: its corners vary little within a crop
    assert np.median(crops[:, corners].std(axis=1).mean(axis=1)) < np.median(crops[:, inner].std(axis=1).mean(axis=1))

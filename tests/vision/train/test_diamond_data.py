"""Refiner training crops: each diamond gives shifted crops whose target points at the diamond."""

from pathlib import Path

import numpy as np
import pytest

from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.stages.diamond_refiner import DIAMOND_CROP_SIZE
from pix2pockets.vision.train.diamond_data import (
    DiamondCropConfig,
    collect_diamond_crops,
    detector_like_boxes,
    image_diamond_crops,
)

IDENTITY = {k: k for k in range(5)}
DIAMONDS = [[100, 100, 104, 104], [160, 100, 164, 104], [220, 100, 224, 104]]


def _item(boxes, classes) -> LabelledImage:
    b = np.asarray(boxes, float).reshape(-1, 4)
    return LabelledImage(Path("x.png"), b, np.asarray(classes), np.full((len(b), 2), np.nan), (320, 240))


def _image_with_diamonds(boxes) -> np.ndarray:
    image = np.full((240, 320, 3), 40, np.uint8)
    for x0, y0, x1, y1 in boxes:
        image[int(y0) : int(y1), int(x0) : int(x1)] = 250
    return image


def test_each_diamond_gives_shifted_crops_whose_target_is_the_bright_square():
    cfg = DiamondCropConfig(copies=2, low_res=0.0)
    crops, targets = image_diamond_crops(
        _image_with_diamonds(DIAMONDS),
        _item([*DIAMONDS, [10, 10, 30, 30]], [4, 4, 4, 2]),
        IDENTITY,
        np.random.default_rng(0),
        cfg,
    )
    assert crops.shape == (6, DIAMOND_CROP_SIZE, DIAMOND_CROP_SIZE, 3) and targets.shape == (6, 4)
    for crop, t in zip(crops, targets, strict=True):
        cx, cy = (t[:2] + 0.5) * DIAMOND_CROP_SIZE
        assert crop[int(cy), int(cx), 0] > 200  # the target falls on the diamond
        assert np.all(np.abs(t[:2]) <= 0.6 * 4 / 16 + 0.05)  # shifted by at most 0.6 box sides (+ rounding)
        assert np.allclose(t[2:], t[2]) and 4 / (16 * 1.3) - 1e-6 <= t[2] <= 4 / (16 * 0.85) + 1e-6  # 4 px box
    assert np.abs(targets[:, :2]).max() > 0.02  # and shifted at all


def test_detector_like_boxes_shorten_only_the_long_side_about_the_same_centre():
    boxes = np.array([[100.0, 50.0, 112.0, 54.0], [10.0, 10.0, 15.0, 15.0], [0.0, 0.0, 4.0, 10.0]])
    out = detector_like_boxes(boxes, np.random.default_rng(0), (0.5, 0.5))
    assert np.allclose(out[0], [102.0, 50.0, 110.0, 54.0])  # 12 x 4: the 8 px excess read as 4
    assert np.allclose(out[1], boxes[1])  # a square box is its own detector box
    assert np.allclose(out[2], [0.0, 1.5, 4.0, 8.5])  # tall boxes shorten in height
    assert np.allclose(detector_like_boxes(boxes, np.random.default_rng(0), (1.0, 1.0)), boxes)


def test_wide_diamonds_get_crops_that_do_not_give_their_width_away():
    wide = [[100, 100, 116, 104]]
    cfg = DiamondCropConfig(copies=200, low_res=0.0, side_jitter=(1.0, 1.0))
    _, targets = image_diamond_crops(
        _image_with_diamonds(wide), _item(wide, [4]), IDENTITY, np.random.default_rng(0), cfg
    )
    assert np.allclose(targets[:, 2] / targets[:, 3], 4.0)  # the targets keep the label's 16 x 4 box
    assert targets[:, 2].max() / targets[:, 2].min() > 1.5  # crop sides vary with the detector's reading
    assert targets[:, 2].max() <= 1.0  # the whole sight stays inside the crop


def test_images_without_diamonds_give_nothing_and_same_seed_same_crops():
    crops, targets = image_diamond_crops(
        _image_with_diamonds([]),
        _item([[10, 10, 30, 30]], [0]),
        IDENTITY,
        np.random.default_rng(0),
        DiamondCropConfig(),
    )
    assert len(crops) == len(targets) == 0
    a = image_diamond_crops(
        _image_with_diamonds(DIAMONDS),
        _item(DIAMONDS, [4, 4, 4]),
        IDENTITY,
        np.random.default_rng(3),
        DiamondCropConfig(),
    )
    b = image_diamond_crops(
        _image_with_diamonds(DIAMONDS),
        _item(DIAMONDS, [4, 4, 4]),
        IDENTITY,
        np.random.default_rng(3),
        DiamondCropConfig(),
    )
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


def test_datasets_without_diamonds_are_refused():
    sources = [(_item([[10, 10, 30, 30]], [0]), IDENTITY)]
    with pytest.raises(ValueError, match="no labelled diamonds"):
        collect_diamond_crops(sources, lambda _path: _image_with_diamonds([]), seed=0)

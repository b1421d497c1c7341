"""Ball refiner training crops: each ball gives jittered crops whose target is the labelled box."""

from pathlib import Path

import numpy as np
import pytest

from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.stages.ball_refiner import BALL_REFINE_CROP_SIZE
from pix2pockets.vision.train.ball_box_data import (
    BallBoxCropConfig,
    collect_ball_box_crops,
    image_ball_box_crops,
    jittered_boxes,
)

IDENTITY = {k: k for k in range(5)}
BALLS = [[60, 60, 76, 76], [150, 100, 166, 116]]
S = BALL_REFINE_CROP_SIZE


def _item(boxes, classes) -> LabelledImage:
    b = np.asarray(boxes, float).reshape(-1, 4)
    return LabelledImage(Path("x.png"), b, np.asarray(classes), np.full((len(b), 2), np.nan), (320, 240))


def _image_with_balls(boxes) -> np.ndarray:
    image = np.full((240, 320, 3), 40, np.uint8)
    yy, xx = np.mgrid[:240, :320]
    for x0, y0, x1, y1 in boxes:
        r = 0.5 * (x1 - x0)
        image[(xx + 0.5 - 0.5 * (x0 + x1)) ** 2 + (yy + 0.5 - 0.5 * (y0 + y1)) ** 2 <= r * r] = 250
    return image


def test_each_ball_gives_jittered_crops_whose_target_is_the_disc():
    cfg = BallBoxCropConfig(copies=3, low_res=0.0)
    item = _item([*BALLS, [10, 10, 14, 14]], [0, 3, 4])  # the diamond gives no crop
    crops, targets = image_ball_box_crops(_image_with_balls(BALLS), item, IDENTITY, np.random.default_rng(0), cfg)
    assert crops.shape == (6, S, S, 3) and targets.shape == (6, 4)
    for crop, t in zip(crops, targets, strict=True):
        cx, cy = (t[:2] + 0.5) * S
        assert crop[int(cy), int(cx), 0] > 200  # the centre falls on the ball
        lit = np.argwhere(crop[:, :, 0] > 145)
        width = (lit[:, 1].max() - lit[:, 1].min() + 1) / S
        assert t[2] == pytest.approx(width, abs=2.5 / S)  # the width is the disc's
    assert np.abs(targets[:, :2]).max() > 0.01 and np.ptp(targets[:, 2]) > 0.03  # jittered at all


def test_jitter_stays_within_its_bounds():
    cfg = BallBoxCropConfig(centre_jitter=0.1, size_jitter=(0.7, 1.4))
    truth = np.tile([[50.0, 50.0, 60.0, 60.0]], (2000, 1))
    boxes = jittered_boxes(truth, np.random.default_rng(1), cfg)
    shift = 0.5 * (boxes[:, :2] + boxes[:, 2:]) - 55.0
    size = boxes[:, 2:] - boxes[:, :2]
    assert np.abs(shift).max() <= 3.0 + 1e-9 and 0.5 < np.abs(shift).mean() < 1.0
    assert size.min() >= 7.0 - 1e-9 and size.max() <= 14.0 + 1e-9


def test_images_without_balls_give_nothing_and_same_seed_same_crops():
    crops, targets = image_ball_box_crops(
        _image_with_balls([]), _item([[10, 10, 14, 14]], [4]), IDENTITY, np.random.default_rng(0), BallBoxCropConfig()
    )
    assert len(crops) == len(targets) == 0
    a = image_ball_box_crops(
        _image_with_balls(BALLS), _item(BALLS, [1, 2]), IDENTITY, np.random.default_rng(3), BallBoxCropConfig()
    )
    b = image_ball_box_crops(
        _image_with_balls(BALLS), _item(BALLS, [1, 2]), IDENTITY, np.random.default_rng(3), BallBoxCropConfig()
    )
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


def test_datasets_without_balls_are_refused():
    sources = [(_item([[10, 10, 14, 14]], [4]), IDENTITY)]
    with pytest.raises(ValueError, match="no labelled balls"):
        collect_ball_box_crops(sources, lambda _path: _image_with_balls([]), seed=0)


def test_stretched_crops_squash_the_ball_and_its_target_alike():
    cfg = BallBoxCropConfig(copies=4, low_res=0.0, stretch=1.0, centre_jitter=0.0, size_jitter=(1.0, 1.0))
    crops, targets = image_ball_box_crops(
        _image_with_balls(BALLS), _item(BALLS, [0, 3]), IDENTITY, np.random.default_rng(2), cfg
    )
    ratios = targets[:, 2] / targets[:, 3]
    assert np.ptp(ratios) > 0.2  # balls come out squashed by different amounts
    for crop, t in zip(crops, targets, strict=True):
        lit = np.argwhere(crop[:, :, 0] > 145)
        width, height = (lit.max(axis=0) - lit.min(axis=0) + 1)[::-1] / S
        assert t[2] == pytest.approx(width, abs=2.5 / S) and t[3] == pytest.approx(height, abs=2.5 / S)

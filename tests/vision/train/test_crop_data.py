"""Classifier training crops: labels follow the boxes, "no ball" crops keep clear of balls."""

from pathlib import Path

import numpy as np

from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.train.crop_data import NO_BALL, CropConfig, image_crops

IDENTITY = {k: k for k in range(5)}


def _item(boxes, classes) -> LabelledImage:
    b = np.asarray(boxes, float)
    return LabelledImage(Path("x.png"), b, np.asarray(classes), np.full((len(b), 2), np.nan), (320, 240))


def test_each_labelled_ball_gives_its_class_and_diamonds_give_no_ball():
    item = _item([[100, 100, 120, 120], [200, 100, 220, 120], [50, 50, 54, 54]], [0, 3, 4])
    cfg = CropConfig(copies=2, low_res=0.0, random_negatives=0.0, off_centre_negatives=0.0)
    crops, labels = image_crops(np.zeros((240, 320, 3), np.uint8), item, IDENTITY, np.random.default_rng(0), cfg)
    assert len(crops) == len(labels)
    assert sorted(labels.tolist()) == [0, 0, 3, 3, NO_BALL]  # 2 copies per ball, 1 for the diamond


def test_no_ball_crops_avoid_balls_and_are_dark_on_a_black_image():
    item = _item([[100, 100, 120, 120]], [2])
    image = np.zeros((240, 320, 3), np.uint8)
    image[100:120, 100:120] = 255
    cfg = CropConfig(copies=0, low_res=0.0, random_negatives=30.0, off_centre_negatives=0.0)
    crops, labels = image_crops(image, item, IDENTITY, np.random.default_rng(1), cfg)
    assert np.all(labels == NO_BALL) and len(labels) > 10
    # every crop centre lies > 0.6 ball diameters from the ball centre, so off the ball
    assert crops[:, 15:17, 15:17].max() < 255


def test_ball_only_sets_give_no_positive_crops():
    item = _item([[100, 100, 120, 120]], [0])
    _, labels = image_crops(np.zeros((240, 320, 3), np.uint8), item, None, np.random.default_rng(0))
    assert np.all(labels == NO_BALL)


def test_same_seed_same_crops():
    item = _item([[100, 100, 120, 120], [50, 50, 54, 54]], [1, 4])
    image = np.random.default_rng(5).integers(0, 255, (240, 320, 3), dtype=np.uint8)
    a = image_crops(image, item, IDENTITY, np.random.default_rng(3))
    b = image_crops(image, item, IDENTITY, np.random.default_rng(3))
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


def test_crops_have_the_configured_side():
    item = _item([[100, 100, 120, 120], [50, 50, 54, 54]], [2, 4])
    for size in (32, 48):
        crops, _ = image_crops(
            np.zeros((240, 320, 3), np.uint8), item, IDENTITY, np.random.default_rng(0), CropConfig(crop_size=size)
        )
        assert crops.shape[1:] == (size, size, 3)

"""Training targets: the per-object ball class used by the class cross-entropy."""

from pathlib import Path

import numpy as np

from pix2pockets.vision.train.targets import AugmentConfig, make_sample
from pix2pockets.vision.yolo_data import LabelledImage


def _item() -> LabelledImage:
    boxes = np.array([[100.0, 100.0, 120.0, 120.0], [200.0, 150.0, 204.0, 154.0], [300.0, 200.0, 318.0, 218.0]])
    return LabelledImage(Path("x.png"), boxes, np.array([0, 4, 3]), np.full((3, 2), np.nan), (640, 480))


def test_ball_class_is_labelled_for_balls_only():
    cfg = AugmentConfig(crop=640, scale_range=(1.0, 1.0), flip=False, colour=0.0)
    image = np.zeros((480, 640, 3), np.uint8)
    s = make_sample(image, _item(), {k: k for k in range(5)}, False, cfg, np.random.default_rng(0))
    n = int(s.reg_mask.sum())
    assert n == 3
    # objects are stored largest first: stripe (18 px), cue (20 px) ... dot last
    assert sorted(s.ball_class[:n].tolist()) == [-1, 0, 3]
    assert np.all(s.ball_class[n:] == -1)


def test_ball_only_photos_have_no_ball_class():
    cfg = AugmentConfig(crop=640, scale_range=(1.0, 1.0), flip=False, colour=0.0)
    image = np.zeros((480, 640, 3), np.uint8)
    s = make_sample(image, _item(), {0: 0, 3: 0}, True, cfg, np.random.default_rng(0))
    assert s.reg_mask.sum() == 2
    assert np.all(s.ball_class == -1)

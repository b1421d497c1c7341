"""Training targets: the per-object ball class used by the class cross-entropy."""

from pathlib import Path

import numpy as np
import pytest

from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.train.detector_targets import AugmentConfig, make_sample


def _item() -> LabelledImage:
    boxes = np.array([[100.0, 100.0, 120.0, 120.0], [200.0, 150.0, 204.0, 154.0], [300.0, 200.0, 318.0, 218.0]])
    return LabelledImage(Path("x.png"), boxes, np.array([0, 4, 3]), np.full((3, 2), np.nan), (640, 480))


def test_ball_class_is_labelled_for_balls_only():
    cfg = AugmentConfig(crop=640, scale_range=(1.0, 1.0), flip=False, colour=0.0)
    image = np.zeros((480, 640, 3), np.uint8)
    s = make_sample(image, _item(), {k: k for k in range(5)}, False, cfg, np.random.default_rng(0))
    n = int(s.reg_mask.sum())
    assert n == 3
    # objects are stored largest first: stripe (18 px), cue (20 px) ... diamond last
    assert sorted(s.ball_class[:n].tolist()) == [-1, 0, 3]
    assert np.all(s.ball_class[n:] == -1)


def test_ball_only_photos_have_no_ball_class():
    cfg = AugmentConfig(crop=640, scale_range=(1.0, 1.0), flip=False, colour=0.0)
    image = np.zeros((480, 640, 3), np.uint8)
    s = make_sample(image, _item(), {0: 0, 3: 0}, True, cfg, np.random.default_rng(0))
    assert s.reg_mask.sum() == 2
    assert np.all(s.ball_class == -1)


def test_off_table_mask_covers_cells_outside_the_widened_box():
    from pix2pockets.vision.train.detector_targets import off_table_mask

    m = off_table_mask(np.array([[40.0, 40.0, 120.0, 80.0]]), 40, margin=0.0)
    assert m.shape == (40, 40)
    assert m[15, 15] == 0 and m[0, 0] == 1 and m[25, 15] == 1  # (row, col): inside, corner, below the box
    wide = off_table_mask(np.array([[40.0, 40.0, 120.0, 80.0]]), 40, margin=0.1)
    assert wide.sum() < m.sum()


def test_ball_only_photo_with_a_table_box_supervises_diamonds_off_the_table():
    cfg = AugmentConfig(crop=640, scale_range=(1.0, 1.0), flip=False, colour=0.0)
    boxes = np.array([[100.0, 100.0, 120.0, 120.0], [50.0, 60.0, 500.0, 400.0]])
    item = LabelledImage(Path("x.png"), boxes, np.array([0, 1]), np.full((2, 2), np.nan), (640, 480))
    image = np.zeros((480, 640, 3), np.uint8)
    with_table = make_sample(image, item, {0: 0}, True, cfg, np.random.default_rng(0), table_class=1)
    assert with_table.off_table[75, 75] == 0  # inside the table box wherever the crop lands
    assert with_table.off_table[5, 5] == 1 and with_table.off_table[150, 150] == 1
    without = make_sample(image, item, {0: 0}, True, cfg, np.random.default_rng(0))
    assert without.off_table.sum() == 0


def test_stretched_sample_scales_image_and_boxes_by_the_same_aspect():
    """A stretch of aspect 0.5 halves widths against heights: the stored box size and the pixels agree."""
    cfg = AugmentConfig(
        crop=640, scale_range=(1.0, 1.0), flip=False, colour=0.0, stretch_range=(0.5, 0.5), stretch_fraction=1.0
    )
    image = np.zeros((480, 640, 3), np.uint8)
    image[100:120, 100:120] = 255  # the cue ball's box, drawn white
    s = make_sample(image, _item(), {k: k for k in range(5)}, False, cfg, np.random.default_rng(0))
    n = int(s.reg_mask.sum())
    cue = int(np.flatnonzero(s.ball_class[:n] == 0)[0])
    w, h = np.exp(s.size[cue]) * 4  # log(w/4), log(h/4) in crop pixels
    assert np.isclose(h / w, 2.0)
    ys, xs = np.nonzero(s.image[0] > 0.5)
    assert np.isclose((ys.max() - ys.min() + 1) / (xs.max() - xs.min() + 1), h / w, rtol=0.15)


def test_no_stretch_draws_nothing_from_the_random_stream():
    """stretch_fraction 0 keeps older augmentation settings byte-identical."""
    image = np.random.default_rng(1).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    plain = AugmentConfig()
    a = make_sample(image, _item(), {k: k for k in range(5)}, False, plain, np.random.default_rng(3))
    b = make_sample(
        image,
        _item(),
        {k: k for k in range(5)},
        False,
        AugmentConfig(stretch_range=(0.5, 2.0)),
        np.random.default_rng(3),
    )
    assert np.array_equal(a.image, b.image) and np.array_equal(a.size, b.size)


def test_stretch_settings_are_checked():
    with pytest.raises(ValueError, match="stretch range"):
        AugmentConfig(stretch_range=(2.0, 0.5))
    with pytest.raises(ValueError, match="stretch fraction"):
        AugmentConfig(stretch_fraction=1.5)

"""Detector losses: the ball-class cross-entropy makes the class heads compete."""

import pytest

torch = pytest.importorskip("torch")

from pix2pockets.vision.detect.heads import N_OUT  # noqa: E402
from pix2pockets.vision.train.detector_loss import ball_class_loss  # noqa: E402


def _batch(label: int) -> dict:
    index = torch.tensor([[5 * 8 + 3, 0]])
    return {"index": index, "ball_class": torch.tensor([[label, -1]])}


def test_class_loss_is_low_for_the_right_class_and_high_for_a_wrong_one():
    out = torch.zeros(1, N_OUT, 8, 8)
    out[0, 2, 5, 3] = 6.0  # solid head fires at the ball centre
    assert float(ball_class_loss(out, _batch(2))) < 0.05
    assert float(ball_class_loss(out, _batch(0))) > 5.0


def test_class_loss_is_zero_without_labelled_balls():
    out = torch.randn(1, N_OUT, 8, 8)
    assert float(ball_class_loss(out, _batch(-1))) == 0.0


def test_heat_mask_adds_the_off_table_diamond_cells():
    import torch

    from pix2pockets.vision.classes import DIAMOND_ID
    from pix2pockets.vision.detect.heads import N_HEAT
    from pix2pockets.vision.train.detector_loss import heat_mask

    kind = torch.ones(2, N_HEAT)
    kind[1, :5] = 0  # the second sample is a ball-only photo
    off = torch.zeros(2, 4, 4)
    off[1, 0, 0] = 1
    m = heat_mask({"kind_mask": kind, "heat": torch.zeros(2, N_HEAT, 4, 4), "off_table": off})
    assert m.shape == (2, N_HEAT, 4, 4)
    assert m[0].min() == 1
    assert m[1, DIAMOND_ID].sum() == 1 and m[1, DIAMOND_ID, 0, 0] == 1
    assert m[1, 0].sum() == 0 and m[1, 5].min() == 1

"""The refiners' shared training pieces: the box loss and the held-out report."""

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from pix2pockets.vision.train.refiner import box_loss, centre_size_boxes, held_out_report  # noqa: E402


def test_box_loss_is_the_l1_distance_in_crop_pixels():
    out = torch.tensor([[0.0, 0.0, 0.5, 0.5], [0.1, 0.0, 0.5, 0.25]])
    targets = torch.tensor([[0.0, 0.0, 0.5, 0.5], [0.0, 0.0, 0.5, 0.5]])
    assert box_loss(out, targets, 32).item() == pytest.approx((0.1 + 0.25) * 32 / 2)


def test_centre_size_rows_become_corner_boxes():
    assert np.allclose(centre_size_boxes(np.array([[0.1, -0.1, 0.2, 0.4]])), [[0.0, -0.3, 0.2, 0.1]])


def test_held_out_report_measures_centres_and_boxes_before_and_after():
    targets = np.array([[0.1, 0.0, 0.5, 0.5], [0.0, -0.05, 0.5, 0.5]])
    report = held_out_report(targets.copy(), targets, context=2.0)  # a perfect refiner
    assert report["centre"]["error_median"] == 0 and report["centre"]["offset_median"] == pytest.approx(0.075)
    assert report["after"]["iou_median"] == 1 and report["after"]["at_iou_75"] == 1
    assert report["before"]["iou_median"] < 1  # the crop's middle is off-centre
    shifted = targets + np.array([0.2, 0, 0, 0])
    worse = held_out_report(shifted, targets, context=2.0)
    assert worse["after"]["iou_median"] < report["after"]["iou_median"]
    assert worse["centre"]["error_median"] == pytest.approx(0.2)

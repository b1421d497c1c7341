"""Shared crop-network helpers: predictions in chunks equal one pass."""

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from pix2pockets.vision.train.ball_classifier import CropNet  # noqa: E402
from pix2pockets.vision.train.crop_fit import predict_crops  # noqa: E402


def test_predictions_in_chunks_match_one_pass_and_leave_the_model_in_eval_mode():
    torch.manual_seed(0)
    net = CropNet((4, 8, 8), "grid", 32, 3)
    crops = np.random.default_rng(0).integers(0, 256, (7, 32, 32, 3), dtype=np.uint8)
    whole = predict_crops(net, crops)
    assert whole.shape == (7, 3) and not net.training
    assert np.allclose(predict_crops(net, crops, chunk=3), whole, atol=1e-5)

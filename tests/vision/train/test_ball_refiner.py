"""The ball refiner's training: augmentation moves box targets with the pixels, the loss learns a box, and the
exported model runs in onnxruntime."""

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from pix2pockets.vision.stages.ball_refiner import BALL_REFINE_CROP_SIZE, BallRefiner  # noqa: E402
from pix2pockets.vision.train.ball_classifier import CropNet  # noqa: E402
from pix2pockets.vision.train.ball_refiner import (  # noqa: E402
    BallRefinerTrainConfig,
    export_ball_refiner,
)
from pix2pockets.vision.train.crop_fit import flip_rotate  # noqa: E402
from pix2pockets.vision.train.refiner import box_loss  # noqa: E402

S = BALL_REFINE_CROP_SIZE


def _rectangles(n: int, rng: np.random.Generator) -> tuple[torch.Tensor, torch.Tensor]:
    """Bright rectangles of random size and place on a dark crop, with their box targets."""
    x = torch.full((n, 3, S, S), 40.0)
    t = torch.zeros(n, 4)
    for i in range(n):
        w, h = rng.integers(6, 16, 2)
        c, r = rng.integers(4, S - 4 - w), rng.integers(4, S - 4 - h)
        x[i, :, r : r + h, c : c + w] = 240.0
        t[i] = torch.tensor([(c + w / 2) / S - 0.5, (r + h / 2) / S - 0.5, w / S, h / S])
    return x, t


@pytest.mark.parametrize("seed", range(8))
def test_flips_and_quarter_turns_move_and_turn_the_box(seed):
    x, t = _rectangles(1, np.random.default_rng(seed))
    y, t2 = flip_rotate(x, t, torch.Generator().manual_seed(seed))
    lit = np.argwhere(y[0, 0].numpy() > 100)
    (r0, c0), (r1, c1) = lit.min(axis=0), lit.max(axis=0) + 1
    expected = [(c0 + c1) / 2 / S - 0.5, (r0 + r1) / 2 / S - 0.5, (c1 - c0) / S, (r1 - r0) / S]
    assert np.allclose(t2[0].numpy(), expected, atol=1e-6)


def test_the_loss_teaches_a_network_where_the_ball_is():
    torch.manual_seed(0)
    x, t = _rectangles(96, np.random.default_rng(0))
    net = CropNet((4, 8, 8), "grid", S, 4)
    opt = torch.optim.Adam(net.parameters(), lr=1e-2)
    for _ in range(200):
        loss = box_loss(net(x), t, S)
        opt.zero_grad()
        loss.backward()
        opt.step()
    net.eval()
    xt, tt = _rectangles(32, np.random.default_rng(1))
    with torch.no_grad():
        err = (net(xt) - tt).abs().sum(dim=1) * S  # [crop px]
    baseline = (tt - tt.mean(dim=0)).abs().sum(dim=1) * S  # always answering the average box
    assert err.median().item() < 0.5 * baseline.median().item()


def test_bad_settings_are_refused():
    with pytest.raises(ValueError, match="--data"):
        BallRefinerTrainConfig(data=(), out="o")
    with pytest.raises(ValueError, match="copies"):
        BallRefinerTrainConfig(data=("d",), out="o", copies=0)
    with pytest.raises(ValueError, match="centre_jitter"):
        BallRefinerTrainConfig(data=("d",), out="o", centre_jitter=0.5)
    with pytest.raises(ValueError, match="stretch"):
        BallRefinerTrainConfig(data=("d",), out="o", stretch=1.5)


def test_exported_refiner_runs_in_onnxruntime(tmp_path):
    net = CropNet((4, 8, 8), "grid", S, 4).eval()
    refiner = BallRefiner(export_ball_refiner(net, tmp_path / "ball.onnx"))
    image = np.full((120, 160, 3), 90, np.uint8)
    boxes = refiner.boxes(image, np.array([[40, 40, 50, 50], [80, 60, 92, 72.0]]))
    with torch.no_grad():
        out = net(torch.full((1, 3, S, S), 90.0))[0].numpy()
    # the first box's crop is 20 px wide with its top-left corner at (35, 35)
    centre = 35 + 20 * (0.5 + np.clip(out[:2], -0.5, 0.5))
    assert np.allclose(0.5 * (boxes[0, :2] + boxes[0, 2:]), centre, atol=1e-3)

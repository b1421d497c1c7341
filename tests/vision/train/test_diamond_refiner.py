"""The diamond refiner's training: augmentation moves targets with the pixels, the loss learns a box, and
the exported model runs in onnxruntime."""

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from pix2pockets.vision.stages.diamond_refiner import DIAMOND_CROP_SIZE, DiamondRefiner  # noqa: E402
from pix2pockets.vision.train.ball_classifier import CropNet  # noqa: E402
from pix2pockets.vision.train.crop_fit import flip_rotate  # noqa: E402
from pix2pockets.vision.train.diamond_refiner import (  # noqa: E402
    DiamondTrainConfig,
    export_diamond_refiner,
)
from pix2pockets.vision.train.refiner import box_loss  # noqa: E402

S = DIAMOND_CROP_SIZE


def _centre_fraction(index: int) -> float:
    return (index + 0.5) / S - 0.5


@pytest.mark.parametrize("seed", range(8))
def test_flips_and_quarter_turns_move_the_target_with_the_pixel(seed):
    rng = np.random.default_rng(seed)
    row, col = rng.integers(0, S, 2)
    x = torch.zeros(1, 3, S, S)
    x[0, :, row, col] = 1.0
    t = torch.tensor([[_centre_fraction(col), _centre_fraction(row)]])
    y, t2 = flip_rotate(x, t, torch.Generator().manual_seed(seed))
    row2, col2 = np.argwhere(y[0, 0].numpy() > 0)[0]
    assert t2[0, 0].item() == pytest.approx(_centre_fraction(col2))
    assert t2[0, 1].item() == pytest.approx(_centre_fraction(row2))


def _blobs(n: int, rng: np.random.Generator) -> tuple[torch.Tensor, torch.Tensor]:
    """Bright rectangles (4-8 px wide, 4 px tall) at random offsets on a dark crop, with their box targets."""
    x = torch.full((n, 3, S, S), 40.0)
    t = torch.zeros(n, 4)
    for i in range(n):
        r, c = rng.integers(S // 2 - 6, S // 2 + 3, 2)
        w = int(rng.integers(4, 9))
        x[i, :, r : r + 4, c : c + w] = 240.0
        t[i] = torch.tensor([(c + w / 2) / S - 0.5, (r + 2) / S - 0.5, w / S, 4 / S])
    return x, t


def test_the_loss_teaches_a_network_where_the_diamond_is_and_how_wide():
    torch.manual_seed(0)
    rng = np.random.default_rng(0)
    x, t = _blobs(64, rng)
    net = CropNet((4, 8, 8), "grid", S, 4)
    opt = torch.optim.Adam(net.parameters(), lr=1e-2)
    for _ in range(300):
        loss = box_loss(net(x), t, S)
        opt.zero_grad()
        loss.backward()
        opt.step()
    net.eval()
    xt, tt = _blobs(32, np.random.default_rng(1))
    with torch.no_grad():
        out = net(xt)
    err = (out[:, :2] - tt[:, :2]).norm(dim=1) * S  # [crop px]
    assert err.median().item() < 0.35 * (tt[:, :2].norm(dim=1) * S).median().item()
    width_err = (out[:, 2] - tt[:, 2]).abs().median().item()
    guess_err = (tt[:, 2] - tt[:, 2].mean()).abs().median().item()  # one width for every diamond
    assert width_err < 0.6 * guess_err


def test_bad_settings_are_refused():
    with pytest.raises(ValueError, match="--data"):
        DiamondTrainConfig(data=(), out="o")
    with pytest.raises(ValueError, match="copies"):
        DiamondTrainConfig(data=("d",), out="o", copies=0)
    with pytest.raises(ValueError, match="centre_jitter"):
        DiamondTrainConfig(data=("d",), out="o", centre_jitter=-1)


def test_exported_refiner_runs_in_onnxruntime(tmp_path):
    net = CropNet((4, 8, 8), "grid", S, 4).eval()
    refiner = DiamondRefiner(export_diamond_refiner(net, tmp_path / "dot.onnx"))
    image = np.full((120, 160, 3), 90, np.uint8)
    boxes = refiner.boxes(image, np.array([[10, 10, 14, 14], [50, 40, 55, 44.0]]))
    with torch.no_grad():
        out = net(torch.full((1, 3, S, S), 90.0))[0].numpy()
    # the first box's crop is 16 px wide with its top-left corner at (4, 4)
    assert np.allclose(0.5 * (boxes[0, :2] + boxes[0, 2:]), 4 + 16 * (0.5 + out[:2]), atol=1e-3)
    assert np.allclose(boxes[0, 2:] - boxes[0, :2], np.clip(16 * out[2:], 4, 16), atol=1e-3)

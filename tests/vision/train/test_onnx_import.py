"""Loading a detector ONNX file back into the trainable network."""

import numpy as np
import pytest

torch = pytest.importorskip("torch")
pytest.importorskip("onnx", reason="reading ONNX weights needs the onnx package (train extra)")

from pix2pockets.data.models import __file__ as models_init  # noqa: E402
from pix2pockets.vision.detect.heads import N_HEAT  # noqa: E402
from pix2pockets.vision.detect.onnx_session import open_session  # noqa: E402
from pix2pockets.vision.train.detector import export_onnx  # noqa: E402
from pix2pockets.vision.train.detector_model import CenterNet, ExportWrapper  # noqa: E402
from pix2pockets.vision.train.onnx_import import load_onnx_into  # noqa: E402


def _images(n: int, seed: int = 0) -> torch.Tensor:
    return torch.from_numpy(np.random.default_rng(seed).random((n, 3, 64, 96), dtype=np.float32))


def _perturbed_net() -> CenterNet:
    """A network whose batch norms are far from identity, as after training."""
    torch.manual_seed(0)
    net = CenterNet(pretrained=False)
    with torch.no_grad():
        for m in net.modules():
            if isinstance(m, torch.nn.BatchNorm2d):
                m.running_mean.uniform_(-0.5, 0.5)
                m.running_var.uniform_(0.5, 2.0)
                m.weight.uniform_(0.5, 1.5)
                m.bias.uniform_(-0.2, 0.2)
        net.head[-1].weight.normal_(0.0, 0.3)  # distinct heatmap peaks, no near-ties
    return net.eval()


def test_imported_network_computes_the_onnx_function(tmp_path):
    path = export_onnx(_perturbed_net(), tmp_path / "d.onnx", example_hw=(64, 96))
    net = load_onnx_into(CenterNet(pretrained=False), path, _images(4))
    x = _images(2, seed=1)
    ref = open_session(path, 1, "detector").run(None, {"image": x.numpy()})[0]
    with torch.no_grad():
        got = ExportWrapper(net.eval())(x).numpy()
    np.testing.assert_allclose(got[:, N_HEAT:], ref[:, N_HEAT:], atol=2e-4)
    # heat cells: the 3x3 peak test may flip on float near-ties, nothing more
    assert np.count_nonzero(ref[:, :N_HEAT]) > 20
    assert np.mean(np.abs(got[:, :N_HEAT] - ref[:, :N_HEAT]) > 2e-4) < 0.002


def test_norm_statistics_come_from_the_calibration_images(tmp_path):
    path = export_onnx(_perturbed_net(), tmp_path / "d.onnx", example_hw=(64, 96))
    net = load_onnx_into(CenterNet(pretrained=False), path, _images(4))
    norms = [m for m in net.modules() if isinstance(m, torch.nn.BatchNorm2d)]
    # measured statistics, not the identity placeholder
    assert all(float(m.running_var.max()) != pytest.approx(1.0 - m.eps) for m in norms)
    # train mode on the calibration images normalises like eval mode
    x = _images(4)
    with torch.no_grad():
        a, b = net.train()(x), net.eval()(x)
    assert float((a - b).abs().max()) < 0.05 * float(b.abs().max())


def test_shipped_detector_loads(tmp_path):
    from pathlib import Path

    path = Path(models_init).parent / "detector.onnx"
    net = load_onnx_into(CenterNet(pretrained=False), path, _images(2))
    assert sum(p.numel() for p in net.parameters()) > 400_000


def test_foreign_or_quantised_file_is_refused(tmp_path):
    from pathlib import Path

    int8 = Path(models_init).parent / "detector-int8.onnx"
    with pytest.raises(ValueError):
        load_onnx_into(CenterNet(pretrained=False), int8, _images(2))
    small = export_onnx(CenterNet(width=32, pretrained=False).eval(), tmp_path / "w32.onnx", example_hw=(64, 96))
    with pytest.raises(ValueError, match="shape"):
        load_onnx_into(CenterNet(pretrained=False), small, _images(2))

"""Starting the table model's training from a shipped ONNX file."""

from pathlib import Path

import numpy as np
import pytest

torch = pytest.importorskip("torch")
pytest.importorskip("onnx", reason="reading ONNX weights needs the onnx package (train extra)")

from pix2pockets.data.models import __file__ as models_init  # noqa: E402
from pix2pockets.vision.detect.onnx_session import open_session  # noqa: E402
from pix2pockets.vision.train.table import export_table, init_network, is_table_export  # noqa: E402

MODELS = Path(models_init).parent


def test_table_export_is_told_from_a_detector() -> None:
    assert is_table_export(MODELS / "table.onnx")
    assert not is_table_export(MODELS / "detector.onnx")


def test_fine_tuning_starts_at_the_shipped_table_model(tmp_path: Path) -> None:
    net = init_network(str(MODELS / "table.onnx")).eval()
    path = export_table(net, tmp_path / "table.onnx")
    x = np.random.default_rng(0).random((1, 3, 96, 160), dtype=np.float32)
    shipped = open_session(MODELS / "table.onnx", 1, "table model").run(None, {"image": x})[0]
    again = open_session(path, 1, "table model").run(None, {"image": x})[0]
    assert np.abs(shipped - again).max() < 1e-4


def test_a_detector_starts_only_the_trunk_and_neck() -> None:
    net = init_network(str(MODELS / "detector.onnx")).eval()
    with torch.no_grad():
        out = torch.sigmoid(net(torch.zeros(1, 3, 64, 64)))
    assert out.shape[1] == 3
    assert float(out[0, 1:].max()) < 0.05  # fresh keypoint head: biased towards no peak


def test_fine_tuning_trains_with_the_shipped_norm_statistics() -> None:
    from pix2pockets.vision.train.table import set_train_mode

    net = init_network(str(MODELS / "table.onnx"))
    x = torch.from_numpy(np.random.default_rng(1).random((2, 3, 96, 160), dtype=np.float32))
    with torch.no_grad():
        shipped = net.eval()(x)
        set_train_mode(net)
        training = net(x)
    assert net.training
    assert torch.allclose(shipped, training, atol=1e-4)  # a batch's own statistics would move every layer

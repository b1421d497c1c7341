"""int8 quantisation keeps the detector's output form and, roughly, its values."""

import cv2
import numpy as np
import pytest

torch = pytest.importorskip("torch")
onnx = pytest.importorskip("onnx")

import onnxruntime as ort  # noqa: E402

from pix2pockets.vision.detect.heads import N_OUT  # noqa: E402
from pix2pockets.vision.train.detector import export_onnx  # noqa: E402
from pix2pockets.vision.train.detector_model import CenterNet  # noqa: E402
from pix2pockets.vision.train.quantize import FP32_PREFIXES, fp32_nodes, quantize_detector  # noqa: E402


def _run(path, x):
    return ort.InferenceSession(str(path), providers=["CPUExecutionProvider"]).run(None, {"image": x})[0]


def test_int8_model_matches_fp32_shape_and_roughly_its_values(tmp_path):
    torch.manual_seed(0)
    net = CenterNet(pretrained=False).eval()
    torch.nn.init.normal_(net.head[-1].weight, std=30.0)  # untrained features are tiny: outputs ~0.1
    fp32 = export_onnx(net, tmp_path / "d.onnx", (96, 128))
    rng = np.random.default_rng(0)
    images = []
    for i in range(3):
        p = tmp_path / f"c{i}.png"
        cv2.imwrite(str(p), rng.integers(0, 256, (96, 128, 3), dtype=np.uint8))
        images.append(p)
    int8 = quantize_detector(fp32, tmp_path / "d-int8.onnx", images, long_side=128)
    assert int8.stat().st_size < fp32.stat().st_size / 2
    x = rng.random((1, 3, 96, 128), dtype=np.float32)
    a, b = _run(fp32, x), _run(int8, x)
    assert a.shape == b.shape == (1, N_OUT, 24, 32)
    reg_a, reg_b = a[0, 6:].ravel(), b[0, 6:].ravel()  # size, offset, contact regressions
    assert np.corrcoef(reg_a, reg_b)[0, 1] > 0.9
    # the trunk's weights are quantised, the output head's are not
    nodes = onnx.load(str(int8)).graph.node
    quantised_inputs = {o for n in nodes if n.op_type == "DequantizeLinear" for o in n.output}
    convs = [n for n in nodes if n.op_type == "Conv"]
    head = [n for n in convs if n.name.startswith(FP32_PREFIXES)]
    trunk = [n for n in convs if not n.name.startswith(FP32_PREFIXES)]
    assert head and trunk
    assert all(n.input[1] in quantised_inputs for n in trunk)
    assert not any(n.input[1] in quantised_inputs for n in head)


def test_quantize_needs_calibration_images(tmp_path):
    with pytest.raises(ValueError, match="calibration"):
        quantize_detector(tmp_path / "missing.onnx", tmp_path / "out.onnx", [])


def test_fp32_nodes_are_the_head_and_the_decoding():
    names = ["/net/backbone/features.0/Conv", "/net/head/head.1/Conv", "/Sigmoid", "/net/smooth4/Conv"]
    assert fp32_nodes(names) == ["/net/head/head.1/Conv", "/Sigmoid"]

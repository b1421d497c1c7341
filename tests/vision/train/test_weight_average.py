import numpy as np
import pytest

onnx = pytest.importorskip("onnx", reason="weight averaging reads ONNX files (train extra)")
from onnx import helper, numpy_helper  # noqa: E402

from pix2pockets.vision.train.weight_average import average_onnx_weights  # noqa: E402


def _linear_model(path, w: np.ndarray, op: str = "MatMul") -> str:
    weight = numpy_helper.from_array(w.astype(np.float32), "w")
    shape = numpy_helper.from_array(np.array([2, 2], np.int64), "shape")
    nodes = [helper.make_node(op, ["x", "w"], ["y"]), helper.make_node("Reshape", ["y", "shape"], ["z"])]
    graph = helper.make_graph(
        nodes,
        "g",
        [helper.make_tensor_value_info("x", onnx.TensorProto.FLOAT, [2, 2])],
        [helper.make_tensor_value_info("z", onnx.TensorProto.FLOAT, [2, 2])],
        [weight, shape],
    )
    onnx.save(helper.make_model(graph), str(path))
    return str(path)


def _weights(path) -> np.ndarray:
    return numpy_helper.to_array(next(t for t in onnx.load(str(path)).graph.initializer if t.name == "w"))


def test_average_is_the_weighted_mean_of_float_weights(tmp_path):
    a = _linear_model(tmp_path / "a.onnx", np.zeros((2, 2)))
    b = _linear_model(tmp_path / "b.onnx", np.full((2, 2), 4.0))
    for weight, expected in ((0.0, 0.0), (0.25, 1.0), (1.0, 4.0)):
        out = average_onnx_weights(a, b, tmp_path / "m.onnx", weight)
        np.testing.assert_allclose(_weights(out), expected)
    assert numpy_helper.to_array(onnx.load(str(out)).graph.initializer[1]).tolist() == [2, 2]


def test_average_refuses_different_networks_and_bad_weights(tmp_path):
    a = _linear_model(tmp_path / "a.onnx", np.zeros((2, 2)))
    other_op = _linear_model(tmp_path / "b.onnx", np.zeros((2, 2)), op="Add")
    other_shape = _linear_model(tmp_path / "c.onnx", np.zeros((2, 1)))
    with pytest.raises(ValueError, match="different networks"):
        average_onnx_weights(a, other_op, tmp_path / "m.onnx")
    with pytest.raises(ValueError, match="same shape"):
        average_onnx_weights(a, other_shape, tmp_path / "m.onnx")
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        average_onnx_weights(a, a, tmp_path / "m.onnx", weight=1.5)
    with pytest.raises(ValueError, match="does not exist"):
        average_onnx_weights(a, a, tmp_path / "missing" / "m.onnx")
    assert not (tmp_path / "m.onnx").exists()

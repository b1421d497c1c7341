"""Post-training int8 quantisation of the exported detector (onnxruntime static QDQ, per-channel weights).

About 1.7x faster on one CPU thread for about one point of AP50 (``docs/benchmarks-detector.md``). Needs the ``onnx``
package (the ``train`` extra); the quantised model runs on plain onnxruntime.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from pix2pockets.vision.detect.letterbox import network_input
from pix2pockets.vision.image_io import read_image_rgb

CALIBRATION_LONG_SIDE = 640
NETWORK_PREFIX = "/net/"
"""ONNX node-name prefix of the network inside the exported wrapper; nodes outside it are the peak decoding."""
FP32_PREFIXES = ("/net/head",)
"""Node-name prefixes kept in fp32: the output head. Quantising the heatmap logits cost 7-9 points of
real-photo ball AP50 for no speed (the head is a small share of the compute)."""


def fp32_nodes(node_names: Sequence[str]) -> list[str]:
    """Nodes to keep in fp32: the output head and the peak decoding after the network."""
    return [n for n in node_names if not n.startswith(NETWORK_PREFIX) or n.startswith(FP32_PREFIXES)]


def _calibration_inputs(images: Sequence[Path], long_side: int) -> Iterator[dict[str, np.ndarray]]:
    for path in images:
        yield {"image": network_input(read_image_rgb(path), long_side, 32)[0]}


def quantize_detector(
    model: str | Path, out: str | Path, images: Sequence[str | Path], long_side: int = CALIBRATION_LONG_SIDE
) -> Path:
    """Write an int8 copy of an fp32 detector, calibrated on ``images`` (a few dozen training images).

    The trunk and neck are quantised (static, QDQ, per-channel weights); the head and decoding stay fp32.

    Raises:
        ValueError: without calibration images or when one cannot be read.
    """
    import onnx
    from onnxruntime.quantization import CalibrationDataReader, QuantFormat, QuantType, quantize_static
    from onnxruntime.quantization.shape_inference import quant_pre_process

    if not images:
        raise ValueError("int8 quantisation needs calibration images")
    inputs = _calibration_inputs([Path(p) for p in images], long_side)

    class _Reader(CalibrationDataReader):
        def get_next(self) -> dict[str, np.ndarray] | None:
            return next(inputs, None)

    out = Path(out)
    with tempfile.TemporaryDirectory() as tmp:
        pre = Path(tmp) / "pre.onnx"
        quant_pre_process(str(model), str(pre), skip_symbolic_shape=True)
        staged = Path(tmp) / "int8.onnx"
        keep_fp32 = fp32_nodes([node.name for node in onnx.load(str(pre)).graph.node])
        quantize_static(
            str(pre),
            str(staged),
            _Reader(),
            quant_format=QuantFormat.QDQ,
            per_channel=True,
            activation_type=QuantType.QUInt8,
            weight_type=QuantType.QInt8,
            nodes_to_exclude=keep_fp32,
        )
        partial = out.with_name(out.name + ".tmp")
        partial.write_bytes(staged.read_bytes())
        os.replace(partial, out)
    return out


def calibration_images(
    datasets: Sequence[str | Path], n: int = 32, split: str = "train", exclude: Sequence[str] = ()
) -> list[Path]:
    """``n`` images spread evenly over the ``split`` images of YOLO datasets (deterministic).

    ``exclude`` holds file-name glob patterns to leave out (e.g. frames of a validation video).
    """
    from pix2pockets.vision.metrics.yolo_data import load_splits

    items = [it.image_path for it in load_splits(datasets, split, exclude)]
    if not items:
        return []
    pick = np.unique(np.linspace(0, len(items) - 1, min(n, len(items))).round().astype(int))
    return [items[i] for i in pick]

"""Weight averaging of two ONNX models with the same graph (a "model soup", Wortsman et al. 2022).

Fine-tuning the detector on more renders raises its synthetic scores but can cost real-photo accuracy; the
average of the weights of the starting and the fine-tuned model keeps both (``docs/detector.md``). The exported
detector folds batch norm into its convolutions, so the average is taken over the folded weights: the result is a
network between the two, not the average of their outputs.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pix2pockets.files import write_atomic
from pix2pockets.vision.train.onnx_file import load_onnx_model


def average_onnx_weights(first: str | Path, second: str | Path, out: str | Path, weight: float = 0.5) -> Path:
    """Write ``(1 - weight) * first + weight * second`` for every floating-point initializer.

    Args:
        first, second: fp32 ONNX files of the same network (same graph, initializer names and shapes).
        out: where to write the averaged model (whole file or nothing).
        weight: share of ``second`` in [0, 1].

    Raises:
        ValueError: if the weight is outside [0, 1], the output folder is missing, an input is not an ONNX
            file, or the two models differ in structure.
    """
    from onnx import numpy_helper

    if not 0.0 <= weight <= 1.0:
        raise ValueError(f"weight must be in [0, 1], got {weight}")
    out = Path(out)
    if not out.parent.is_dir():
        raise ValueError(f"output folder {out.parent} does not exist")
    a, b = load_onnx_model(first), load_onnx_model(second)
    if [n.op_type for n in a.graph.node] != [n.op_type for n in b.graph.node]:
        raise ValueError(f"{first} and {second} are different networks (their graphs differ)")
    other = {t.name: numpy_helper.to_array(t) for t in b.graph.initializer}
    for init in a.graph.initializer:
        x = numpy_helper.to_array(init)
        y = other.get(init.name)
        if y is None or y.shape != x.shape:
            raise ValueError(f"initializer {init.name!r} of {first} has no match of the same shape in {second}")
        if np.issubdtype(x.dtype, np.floating):
            mixed = ((1.0 - weight) * x.astype(np.float64) + weight * y.astype(np.float64)).astype(x.dtype)
            init.CopyFrom(numpy_helper.from_array(mixed, init.name))
        elif not np.array_equal(x, y):
            raise ValueError(f"integer initializer {init.name!r} differs between the two models")
    write_atomic(out, a.SerializeToString())
    return out

"""Open an ONNX model with onnxruntime on the CPU, with one-line errors for missing or broken files."""

from __future__ import annotations

from pathlib import Path


def open_session(path: str | Path, threads: int, what: str):
    """An ``onnxruntime.InferenceSession`` for ``path`` with ``threads`` intra-op threads.

    Args:
        path: the ``.onnx`` file.
        threads: onnxruntime intra-op threads (0 lets onnxruntime choose).
        what: what the model is, for error messages ("detector model", "ball classifier").

    Raises:
        ValueError: if the file does not exist or onnxruntime cannot load it.
    """
    import onnxruntime as ort

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{what} not found: {path}")
    opts = ort.SessionOptions()
    opts.intra_op_num_threads = threads
    opts.inter_op_num_threads = 1
    opts.log_severity_level = 3
    try:
        return ort.InferenceSession(str(path), opts, providers=["CPUExecutionProvider"])
    except Exception as err:  # onnxruntime raises its own exception types
        raise ValueError(f"cannot load {what} {path}: {err}") from err

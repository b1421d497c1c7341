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


def open_crop_model(path: str | Path, threads: int, what: str, crop_size: int | None, output_name: str, n_outputs: int):
    """A session for a second-stage model that reads uint8 crops (n, crop_size, crop_size, 3) and returns
    (n, n_outputs) as ``output_name``; the ball classifier and the diamond refiner share that input, so the output
    tells them apart. ``crop_size`` None accepts any square crop side (read it from the session's input shape).

    Raises:
        ValueError: if the file does not exist, cannot be loaded, or is another kind of model.
    """
    session = open_session(path, threads, what)
    shape = session.get_inputs()[0].shape
    output = session.get_outputs()[0]
    side = crop_size
    if side is None and len(shape) == 4 and isinstance(shape[1], int):
        side = shape[1]  # any square side: the model's own
    if len(shape) != 4 or shape[1:] != [side, side, 3] or output.shape[-1] != n_outputs or output.name != output_name:
        want = side if side is not None else "S"
        raise ValueError(
            f"{path} is not a {what}: input {shape}, output {output.name!r} {output.shape} (expected input "
            f"[n, {want}, {want}, 3], output {output_name!r} [n, {n_outputs}])"
        )
    return session

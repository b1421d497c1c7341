"""Reading ONNX files for the training tools (needs the ``train`` extra's onnx package)."""

from __future__ import annotations

from pathlib import Path
from typing import Any


def load_onnx_model(path: str | Path) -> Any:
    """The ``onnx.ModelProto`` stored in ``path``.

    Raises:
        ValueError: if the file is missing or not an ONNX model.
    """
    import onnx

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"no file {path}")
    try:
        return onnx.load(str(path))
    except Exception as err:  # protobuf raises its own DecodeError for anything that is not ONNX
        raise ValueError(f"{path} is not a readable ONNX file: {err}") from err

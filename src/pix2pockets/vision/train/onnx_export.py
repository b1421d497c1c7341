"""Write a torch module to an ONNX file atomically (opset 17, TorchScript exporter, dynamic axes)."""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import torch


def write_onnx(
    module: torch.nn.Module,
    example: torch.Tensor,
    path: Path,
    input_name: str,
    output_name: str,
    dynamic_axes: dict[str, dict[int, str]],
) -> Path:
    """Export ``module`` (in eval mode, no gradients) traced on ``example``; the file appears only when complete."""
    tmp = path.with_name(path.name + ".tmp")
    with torch.no_grad(), warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # the TorchScript exporter needs no onnxscript
        torch.onnx.export(
            module.eval(),
            (example,),
            str(tmp),
            input_names=[input_name],
            output_names=[output_name],
            dynamic_axes=dynamic_axes,
            opset_version=17,
            dynamo=False,
        )
    os.replace(tmp, path)
    return path

"""Load a shipped ONNX file (detector or table model) back into its trainable network (needs torch and onnx).

The exporter folds every batch norm into the convolution before it, so the ONNX file holds one weight and one
bias per convolution. This module walks the network's convolutions in the order they run, takes the matching
ONNX convolution's tensors, and gives each batch norm back the statistics it would see on real inputs:
with ``mean`` and ``var`` the per-channel statistics of the folded convolution's output on calibration
images, the norm gets ``running_mean = mean``, ``running_var = var``, ``weight = sqrt(var + eps)`` and
``bias = mean + b``. In eval mode that is exactly the ONNX function; in train mode the batch statistics are
close to the stored ones, so fine-tuning starts where the shipped model is instead of from a rescaled net.

This is what lets training continue from the shipped weights when no ``last.pt`` checkpoint is at hand.
"""

from __future__ import annotations

import itertools
from pathlib import Path
from typing import TypeVar

import numpy as np
import torch
from torch import nn

from pix2pockets.vision.train.onnx_file import load_onnx_model

NetT = TypeVar("NetT", bound=nn.Module)


def _convs_in_run_order(model: nn.Module, example: torch.Tensor) -> list[nn.Conv2d]:
    order: list[nn.Conv2d] = []
    hooks = [
        m.register_forward_pre_hook(lambda mod, _inp: order.append(mod))
        for m in model.modules()
        if isinstance(m, nn.Conv2d)
    ]
    try:
        with torch.no_grad():
            model.eval()(example)
    finally:
        for h in hooks:
            h.remove()
    return order


def _norm_after(model: nn.Module) -> dict[nn.Conv2d, nn.BatchNorm2d]:
    """Each convolution that a batch norm directly follows inside an ``nn.Sequential``."""
    pairs: dict[nn.Conv2d, nn.BatchNorm2d] = {}
    for m in model.modules():
        if isinstance(m, nn.Sequential):
            kids = list(m.children())
            for a, b in itertools.pairwise(kids):
                if isinstance(a, nn.Conv2d) and isinstance(b, nn.BatchNorm2d):
                    pairs[a] = b
    return pairs


def _onnx_convs(path: Path) -> list[tuple[np.ndarray, np.ndarray | None]]:
    from onnx import numpy_helper

    graph = load_onnx_model(path).graph
    tensors = {t.name: numpy_helper.to_array(t) for t in graph.initializer}
    convs = []
    for node in graph.node:
        if node.op_type != "Conv":
            continue
        if node.input[1] not in tensors:
            raise ValueError(f"{path}: convolution {node.name} has no stored weight (a quantised model?)")
        bias = tensors.get(node.input[2]) if len(node.input) > 2 and node.input[2] else None
        convs.append((tensors[node.input[1]], bias))
    return convs


def load_onnx_into(model: NetT, path: str | Path, calibration: torch.Tensor) -> NetT:
    """Set ``model``'s weights from an ONNX file it was exported to (fp32; a detector or a table model).

    Args:
        model: a freshly built network of the same kind and width as the exported one.
        path: the fp32 ONNX file.
        calibration: images (N, 3, H, W) in [0, 1] on which batch-norm statistics are measured; a few
            training crops are enough.

    Raises:
        ValueError: when the file does not fit the network (another width, a quantised or foreign model).
    """
    path = Path(path)
    convs = _convs_in_run_order(model, calibration[:1])
    stored = _onnx_convs(path)
    if len(convs) != len(stored):
        raise ValueError(f"{path}: {len(stored)} convolutions, the network has {len(convs)}; not an export of it")
    norms = _norm_after(model)
    folded_bias: dict[nn.BatchNorm2d, torch.Tensor] = {}
    with torch.no_grad():
        for i, (conv, (w, b)) in enumerate(zip(convs, stored, strict=True)):
            if tuple(conv.weight.shape) != w.shape:
                raise ValueError(f"{path}: convolution {i} has shape {w.shape}, the network {tuple(conv.weight.shape)}")
            conv.weight.copy_(torch.from_numpy(np.array(w)))
            bias = torch.zeros(w.shape[0]) if b is None else torch.from_numpy(np.array(b)).float()
            bn = norms.get(conv)
            if bn is None:
                if conv.bias is None:
                    if b is not None and np.any(b != 0):
                        raise ValueError(f"{path}: convolution {i} has a bias the network cannot hold")
                else:
                    conv.bias.copy_(bias)
                continue
            # identity norm plus the folded bias: the eval-mode network now computes the ONNX function
            bn.running_mean.zero_()
            bn.running_var.fill_(1.0 - bn.eps)
            bn.weight.fill_(1.0)
            bn.bias.copy_(bias)
            folded_bias[bn] = bias
    _calibrate_norms(model, folded_bias, calibration)
    return model


def _calibrate_norms(model: nn.Module, folded_bias: dict[nn.BatchNorm2d, torch.Tensor], images: torch.Tensor) -> None:
    """Re-express each identity norm through the statistics of its input (eval-mode output unchanged)."""
    sums: dict[nn.BatchNorm2d, list[torch.Tensor]] = {bn: [] for bn in folded_bias}

    def record(mod: nn.BatchNorm2d, inp: tuple[torch.Tensor, ...]) -> None:
        x = inp[0].transpose(0, 1).reshape(inp[0].shape[1], -1)
        sums[mod].append(torch.stack([x.mean(1), (x * x).mean(1)]))

    hooks = [bn.register_forward_pre_hook(record) for bn in folded_bias]
    try:
        with torch.no_grad():
            model.eval()
            for k in range(0, len(images), 4):
                model(images[k : k + 4])
    finally:
        for h in hooks:
            h.remove()
    with torch.no_grad():
        for bn, b in folded_bias.items():
            m1, m2 = torch.stack(sums[bn]).mean(0)
            var = (m2 - m1 * m1).clamp_min(1e-6)
            bn.running_mean.copy_(m1)
            bn.running_var.copy_(var)
            bn.weight.copy_(torch.sqrt(var + bn.eps))
            bn.bias.copy_(m1 + b)

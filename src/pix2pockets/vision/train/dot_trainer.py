"""Train the diamond refiner (a diamond's box from a 32 px crop around a detection) and export it to ONNX.

The network is the ball classifier's :class:`~pix2pockets.vision.train.crop_classifier.CropNet` with its grid
head (which keeps where things sit in the crop) and four outputs, trained with an L1 loss on the box
(the run and its held-out report: :func:`~pix2pockets.vision.train.refiner_trainer.train_refiner`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
from torch import nn

from pix2pockets.vision.dot_refiner import (
    DEFAULT_DOT_REFINER,
    DOT_CROP_CONTEXT,
    DOT_CROP_SIZE,
    OUTPUT_NAME,
)
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.train.crop_fit import CropTrainSettings
from pix2pockets.vision.train.dot_data import DotCropConfig, collect_dot_crops
from pix2pockets.vision.train.refiner_trainer import (
    RefinerSpec,
    export_refiner,
    train_refiner,
)

SPEC = RefinerSpec(
    "diamond refiner", "train-dot-refiner", DOT_CROP_SIZE, DOT_CROP_CONTEXT, OUTPUT_NAME, DEFAULT_DOT_REFINER
)


@dataclass(frozen=True, slots=True)
class DotTrainConfig(CropTrainSettings):
    """Settings of ``pix2pockets train-dot-refiner``.

    Attributes (besides the shared :class:`~pix2pockets.vision.train.crop_fit.CropTrainSettings`):
        copies: shifted crops per labelled diamond and image.
        centre_jitter: largest crop centre shift per axis, in diamond box sides.
    """

    command: ClassVar[str] = SPEC.command

    epochs: int = 10
    copies: int = 3
    centre_jitter: float = DotCropConfig().centre_jitter

    def check(self) -> None:
        if not 0 <= self.centre_jitter <= 2:
            raise ValueError(f"centre_jitter must be in [0, 2] diamond sides, got {self.centre_jitter}")


def export_dot_refiner(model: nn.Module, path: Path) -> Path:
    """Write the refiner (uint8 NHWC crops in, (N, 4) boxes out) as ONNX with a dynamic batch."""
    return export_refiner(model, path, SPEC)


def train_dot_refiner(cfg: DotTrainConfig, progress: bool = True) -> Path:
    """Collect crops, train, report held-out centre errors and box IoUs in ``metrics.json``, export; returns the
    ONNX path."""
    crop_cfg = DotCropConfig(copies=cfg.copies, centre_jitter=cfg.centre_jitter)

    def collect(sources, seed: int) -> tuple[np.ndarray, np.ndarray]:
        return collect_dot_crops(sources, read_image_rgb, seed, crop_cfg, progress)

    return train_refiner(cfg, SPEC, collect, progress)

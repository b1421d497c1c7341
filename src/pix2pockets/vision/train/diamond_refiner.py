"""Train the diamond refiner (a diamond's box from a 32 px crop around a detection) and export it to ONNX.

The network is the ball classifier's :class:`~pix2pockets.vision.train.ball_classifier.CropNet` with its grid
head (which keeps where things sit in the crop) and four outputs, trained with an L1 loss on the box
(the run and its held-out report: :func:`~pix2pockets.vision.train.refiner.train_refiner`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
from torch import nn

from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.stages.diamond_refiner import (
    DEFAULT_DIAMOND_REFINER,
    DIAMOND_CROP_CONTEXT,
    DIAMOND_CROP_SIZE,
    OUTPUT_NAME,
)
from pix2pockets.vision.train.crop_fit import CropTrainSettings
from pix2pockets.vision.train.diamond_data import DiamondCropConfig, collect_diamond_crops
from pix2pockets.vision.train.refiner import (
    RefinerSpec,
    export_refiner,
    train_refiner,
)

SPEC = RefinerSpec(
    "diamond refiner",
    "train-diamond-refiner",
    DIAMOND_CROP_SIZE,
    DIAMOND_CROP_CONTEXT,
    OUTPUT_NAME,
    DEFAULT_DIAMOND_REFINER,
)


@dataclass(frozen=True, slots=True)
class DiamondTrainConfig(CropTrainSettings):
    """Settings of ``pix2pockets train-diamond-refiner``.

    Attributes (besides the shared :class:`~pix2pockets.vision.train.crop_fit.CropTrainSettings`):
        copies: shifted crops per labelled diamond and image.
        centre_jitter: largest crop centre shift per axis, in diamond box sides.
    """

    command: ClassVar[str] = SPEC.command

    epochs: int = 10
    copies: int = 3
    centre_jitter: float = DiamondCropConfig().centre_jitter

    def check(self) -> None:
        if not 0 <= self.centre_jitter <= 2:
            raise ValueError(f"centre_jitter must be in [0, 2] diamond sides, got {self.centre_jitter}")


def export_diamond_refiner(model: nn.Module, path: Path) -> Path:
    """Write the refiner (uint8 NHWC crops in, (N, 4) boxes out) as ONNX with a dynamic batch."""
    return export_refiner(model, path, SPEC)


def train_diamond_refiner(cfg: DiamondTrainConfig, progress: bool = True) -> Path:
    """Collect crops, train, report held-out centre errors and box IoUs in ``metrics.json``, export; returns the
    ONNX path."""
    crop_cfg = DiamondCropConfig(copies=cfg.copies, centre_jitter=cfg.centre_jitter)

    def collect(sources, seed: int) -> tuple[np.ndarray, np.ndarray]:
        return collect_diamond_crops(sources, read_image_rgb, seed, crop_cfg, progress)

    return train_refiner(cfg, SPEC, collect, progress)

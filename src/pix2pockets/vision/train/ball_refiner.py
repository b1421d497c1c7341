"""Train the ball box refiner (a ball's box from a 32 px crop around a detection) and export it to ONNX.

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
from pix2pockets.vision.stages.ball_refiner import (
    BALL_REFINE_CONTEXT,
    BALL_REFINE_CROP_SIZE,
    DEFAULT_BALL_REFINER,
    OUTPUT_NAME,
)
from pix2pockets.vision.train.ball_box_data import BallBoxCropConfig, collect_ball_box_crops
from pix2pockets.vision.train.crop_fit import CropTrainSettings
from pix2pockets.vision.train.refiner import (
    RefinerSpec,
    export_refiner,
    train_refiner,
)

SPEC = RefinerSpec(
    "ball refiner", "train-ball-refiner", BALL_REFINE_CROP_SIZE, BALL_REFINE_CONTEXT, OUTPUT_NAME, DEFAULT_BALL_REFINER
)


@dataclass(frozen=True, slots=True)
class BallRefinerTrainConfig(CropTrainSettings):
    """Settings of ``pix2pockets train-ball-refiner``.

    Attributes (besides the shared :class:`~pix2pockets.vision.train.crop_fit.CropTrainSettings`):
        copies: jittered crops per labelled ball and image.
        centre_jitter: standard deviation of the crop centre shift per axis, in ball diameters.
        stretch: share of the crops cut with a window of another aspect, the ball squashed in them
            (:class:`~pix2pockets.vision.train.ball_box_data.BallBoxCropConfig`).
    """

    command: ClassVar[str] = SPEC.command

    copies: int = 3
    centre_jitter: float = BallBoxCropConfig().centre_jitter
    stretch: float = BallBoxCropConfig().stretch

    def check(self) -> None:
        if not 0 <= self.centre_jitter <= 0.3:
            raise ValueError(f"centre_jitter must be in [0, 0.3] ball diameters, got {self.centre_jitter}")
        if not 0 <= self.stretch <= 1:
            raise ValueError(f"stretch must be a share in [0, 1], got {self.stretch}")


def export_ball_refiner(model: nn.Module, path: Path) -> Path:
    """Write the refiner (uint8 NHWC crops in, (N, 4) boxes out) as ONNX with a dynamic batch."""
    return export_refiner(model, path, SPEC)


def train_ball_refiner(cfg: BallRefinerTrainConfig, progress: bool = True) -> Path:
    """Collect crops, train, report held-out box IoUs in ``metrics.json``, export; returns the ONNX path."""
    crop_cfg = BallBoxCropConfig(copies=cfg.copies, centre_jitter=cfg.centre_jitter, stretch=cfg.stretch)

    def collect(sources, seed: int) -> tuple[np.ndarray, np.ndarray]:
        return collect_ball_box_crops(sources, read_image_rgb, seed, crop_cfg, progress)

    return train_refiner(cfg, SPEC, collect, progress)

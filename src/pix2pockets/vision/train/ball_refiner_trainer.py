"""Train the ball box refiner (a ball's box from a 32 px crop around a detection) and export it to ONNX.

The network is the ball classifier's :class:`~pix2pockets.vision.train.crop_classifier.CropNet` with its grid
head (which keeps where things sit in the crop) and four outputs, trained with an L1 loss on the box.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import torch
from torch import nn

from pix2pockets.vision.ball_refiner import (
    BALL_REFINE_CONTEXT,
    BALL_REFINE_CROP_SIZE,
    DEFAULT_BALL_REFINER,
    N_OUTPUTS,
    OUTPUT_NAME,
)
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.postprocess import paired_box_iou
from pix2pockets.vision.train.ball_box_data import BallBoxCropConfig, collect_ball_box_crops
from pix2pockets.vision.train.crop_classifier import CropNet, photometric
from pix2pockets.vision.train.crop_fit import RawOutputs, fit_crops, flip_rotate, labelled_sources
from pix2pockets.vision.train.onnx_export import write_onnx


@dataclass(frozen=True, slots=True)
class BallRefinerTrainConfig:
    """Settings of ``pix2pockets train-ball-refiner``.

    Attributes:
        data: YOLO datasets with ball labels (classes cue, black, solid, stripe).
        out: output folder (``ball-refiner.onnx``, ``metrics.json``).
        epochs: passes over the crops.
        seed: seed for crops, order, augmentation and initialisation.
        batch: crops per step.
        lr: peak learning rate (AdamW, cosine decay).
        threads: torch CPU threads.
        widths: channels of the network's three stages.
        copies: jittered crops per labelled ball and image.
        centre_jitter: standard deviation of the crop centre shift per axis, in ball diameters.
        stretch: share of the crops cut with a window of another aspect, the ball squashed in them
            (:class:`~pix2pockets.vision.train.ball_box_data.BallBoxCropConfig`).
    """

    data: tuple[str, ...]
    out: str
    epochs: int = 6
    seed: int = 0
    batch: int = 256
    lr: float = 3e-3
    threads: int = 1
    widths: tuple[int, int, int] = (16, 32, 64)
    copies: int = 3
    centre_jitter: float = BallBoxCropConfig().centre_jitter
    stretch: float = BallBoxCropConfig().stretch

    def __post_init__(self) -> None:
        if not self.data:
            raise ValueError("train-ball-refiner needs at least one --data folder")
        if min(self.epochs, self.batch, self.threads, self.copies) < 1 or not self.lr > 0:
            raise ValueError("epochs, batch, threads and copies must be >= 1 and lr > 0")
        if len(self.widths) != 3 or min(self.widths) < 1:
            raise ValueError(f"widths must be three positive channel counts, got {self.widths}")
        if not 0 <= self.centre_jitter <= 0.3:
            raise ValueError(f"centre_jitter must be in [0, 0.3] ball diameters, got {self.centre_jitter}")
        if not 0 <= self.stretch <= 1:
            raise ValueError(f"stretch must be a share in [0, 1], got {self.stretch}")


def box_loss(out: torch.Tensor, targets: torch.Tensor) -> torch.Tensor:
    """Mean L1 distance between predicted and true boxes (centre x, y, width, height), in crop pixels."""
    return (out - targets).abs().sum(dim=1).mean() * BALL_REFINE_CROP_SIZE


def _boxes(t: np.ndarray) -> np.ndarray:
    """xyxy boxes in crop-side units from targets (n, 4)."""
    return np.hstack([t[:, :2] - 0.5 * t[:, 2:], t[:, :2] + 0.5 * t[:, 2:]])


def _held_out(model: CropNet, crops: np.ndarray, targets: np.ndarray) -> dict:
    """IoU of the held-out crops' boxes with their labels before (a square as wide as the jittered box's mean side
    at the crop's middle) and after refinement."""
    model.eval()
    outs = []
    with torch.no_grad():
        for i in range(0, len(crops), 1024):
            outs.append(model(torch.from_numpy(crops[i : i + 1024]).permute(0, 3, 1, 2).float()).numpy())
    truth = _boxes(targets)
    half = 0.5 / BALL_REFINE_CONTEXT  # a square of the jittered diameter at the crop's middle
    start = np.tile([-half, -half, half, half], (len(targets), 1))
    before, after = paired_box_iou(start, truth), paired_box_iou(_boxes(np.concatenate(outs)), truth)
    report = {"crops": len(targets)}
    for tag, iou in (("before", before), ("after", after)):
        report[tag] = {
            "iou_median": round(float(np.median(iou)), 4),
            "iou_p10": round(float(np.percentile(iou, 10)), 4),
            "at_iou_50": round(float(np.mean(iou >= 0.5)), 4),
            "at_iou_75": round(float(np.mean(iou >= 0.75)), 4),
        }
    return report


def export_ball_refiner(model: CropNet, path: Path) -> Path:
    """Write the refiner (uint8 NHWC crops in, (N, 4) boxes out) as ONNX with a dynamic batch."""
    example = torch.zeros(2, BALL_REFINE_CROP_SIZE, BALL_REFINE_CROP_SIZE, 3, dtype=torch.uint8)
    axes = {"crops": {0: "n"}, OUTPUT_NAME: {0: "n"}}
    return write_onnx(RawOutputs(model), example, path, "crops", OUTPUT_NAME, axes)


def train_ball_refiner(cfg: BallRefinerTrainConfig, progress: bool = True) -> Path:
    """Collect crops, train, report held-out box IoUs in ``metrics.json``, export; returns the ONNX path."""

    torch.set_num_threads(cfg.threads)
    torch.manual_seed(cfg.seed)
    out = Path(cfg.out)
    out.mkdir(parents=True, exist_ok=True)
    crop_cfg = BallBoxCropConfig(copies=cfg.copies, centre_jitter=cfg.centre_jitter, stretch=cfg.stretch)
    crops, targets = collect_ball_box_crops(
        labelled_sources(cfg.data, "train"), read_image_rgb, cfg.seed, crop_cfg, progress
    )
    test = labelled_sources(cfg.data, "test")

    model = CropNet(cfg.widths, "grid", BALL_REFINE_CROP_SIZE, N_OUTPUTS)

    def batch_loss(net: nn.Module, x: torch.Tensor, t: torch.Tensor, gen: torch.Generator) -> torch.Tensor:
        x, t = flip_rotate(x, t, gen)
        return box_loss(net(photometric(x, gen)), t)

    fit_crops(
        model,
        crops,
        torch.from_numpy(targets),
        batch_loss,
        epochs=cfg.epochs,
        batch=cfg.batch,
        lr=cfg.lr,
        seed=cfg.seed,
        desc="train ball refiner",
        progress=progress,
    )

    metrics = {"config": asdict(cfg), "train_crops": len(targets)}
    if test:
        held = collect_ball_box_crops(test, read_image_rgb, cfg.seed + 1, crop_cfg, progress)
        metrics["test"] = _held_out(model, *held)
    (out / "metrics.json").write_text(json.dumps(metrics, indent=2) + "\n")
    torch.save({"model": model.state_dict(), "config": asdict(cfg)}, out / "last.pt")
    return export_ball_refiner(model, out / DEFAULT_BALL_REFINER)

"""Train the diamond refiner (a diamond's centre from a 32 px crop around a detection) and export it to ONNX.

The network is the ball classifier's :class:`~pix2pockets.vision.train.crop_classifier.CropNet` with its grid
head (which keeps where things sit in the crop) and two outputs, trained with an L1 loss on the centre.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import torch
from torch import nn

from pix2pockets.vision.dot_refiner import DEFAULT_DOT_REFINER, DOT_CROP_SIZE, N_OUTPUTS, OUTPUT_NAME
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.train.crop_classifier import CropNet, photometric
from pix2pockets.vision.train.crop_fit import RawOutputs, fit_crops, flip_rotate, labelled_sources
from pix2pockets.vision.train.dot_data import DotCropConfig, collect_dot_crops
from pix2pockets.vision.train.onnx_export import write_onnx


@dataclass(frozen=True, slots=True)
class DotTrainConfig:
    """Settings of ``pix2pockets train-dot-refiner``.

    Attributes:
        data: YOLO datasets with diamond labels (the ``dot`` class).
        out: output folder (``dot-refiner.onnx``, ``metrics.json``).
        epochs: passes over the crops.
        seed: seed for crops, order, augmentation and initialisation.
        batch: crops per step.
        lr: peak learning rate (AdamW, cosine decay).
        threads: torch CPU threads.
        widths: channels of the network's three stages.
        copies: shifted crops per labelled diamond and image.
        centre_jitter: largest crop centre shift per axis, in diamond box sides.
    """

    data: tuple[str, ...]
    out: str
    epochs: int = 10
    seed: int = 0
    batch: int = 256
    lr: float = 3e-3
    threads: int = 1
    widths: tuple[int, int, int] = (16, 32, 64)
    copies: int = 3
    centre_jitter: float = DotCropConfig().centre_jitter

    def __post_init__(self) -> None:
        if not self.data:
            raise ValueError("train-dot-refiner needs at least one --data folder")
        if min(self.epochs, self.batch, self.threads, self.copies) < 1 or not self.lr > 0:
            raise ValueError("epochs, batch, threads and copies must be >= 1 and lr > 0")
        if len(self.widths) != 3 or min(self.widths) < 1:
            raise ValueError(f"widths must be three positive channel counts, got {self.widths}")
        if not 0 <= self.centre_jitter <= 2:
            raise ValueError(f"centre_jitter must be in [0, 2] diamond sides, got {self.centre_jitter}")


def centre_loss(out: torch.Tensor, targets: torch.Tensor) -> torch.Tensor:
    """Mean L1 distance between predicted and true centres, in crop pixels."""
    return (out - targets).abs().sum(dim=1).mean() * DOT_CROP_SIZE


def _held_out(model: CropNet, crops: np.ndarray, targets: np.ndarray) -> dict:
    """Centre errors of the held-out crops before (the crop's middle) and after refinement [crop sides]."""
    model.eval()
    outs = []
    with torch.no_grad():
        for i in range(0, len(crops), 1024):
            outs.append(model(torch.from_numpy(crops[i : i + 1024]).permute(0, 3, 1, 2).float()).numpy())
    err = np.linalg.norm(np.concatenate(outs) - targets, axis=1)
    start = np.linalg.norm(targets, axis=1)
    return {
        "crops": len(targets),
        "offset_median": round(float(np.median(start)), 5),
        "offset_p90": round(float(np.percentile(start, 90)), 5),
        "error_median": round(float(np.median(err)), 5),
        "error_p90": round(float(np.percentile(err, 90)), 5),
    }


def export_dot_refiner(model: CropNet, path: Path) -> Path:
    """Write the refiner (uint8 NHWC crops in, (N, 2) centres out) as ONNX with a dynamic batch."""
    example = torch.zeros(2, DOT_CROP_SIZE, DOT_CROP_SIZE, 3, dtype=torch.uint8)
    axes = {"crops": {0: "n"}, OUTPUT_NAME: {0: "n"}}
    return write_onnx(RawOutputs(model), example, path, "crops", OUTPUT_NAME, axes)


def train_dot_refiner(cfg: DotTrainConfig, progress: bool = True) -> Path:
    """Collect crops, train, report held-out centre errors in ``metrics.json``, export; returns the ONNX path."""

    torch.set_num_threads(cfg.threads)
    torch.manual_seed(cfg.seed)
    out = Path(cfg.out)
    out.mkdir(parents=True, exist_ok=True)
    crop_cfg = DotCropConfig(copies=cfg.copies, centre_jitter=cfg.centre_jitter)
    crops, targets = collect_dot_crops(
        labelled_sources(cfg.data, "train"), read_image_rgb, cfg.seed, crop_cfg, progress
    )
    test = labelled_sources(cfg.data, "test")

    model = CropNet(cfg.widths, "grid", DOT_CROP_SIZE, N_OUTPUTS)

    def batch_loss(net: nn.Module, x: torch.Tensor, t: torch.Tensor, gen: torch.Generator) -> torch.Tensor:
        x, t = flip_rotate(x, t, gen)
        return centre_loss(net(photometric(x, gen)), t)

    fit_crops(
        model,
        crops,
        torch.from_numpy(targets),
        batch_loss,
        epochs=cfg.epochs,
        batch=cfg.batch,
        lr=cfg.lr,
        seed=cfg.seed,
        desc="train diamond refiner",
        progress=progress,
    )

    metrics = {"config": asdict(cfg), "train_crops": len(targets)}
    if test:
        metrics["test"] = _held_out(model, *collect_dot_crops(test, read_image_rgb, cfg.seed + 1, crop_cfg, progress))
    (out / "metrics.json").write_text(json.dumps(metrics, indent=2) + "\n")
    torch.save({"model": model.state_dict(), "config": asdict(cfg)}, out / "last.pt")
    return export_dot_refiner(model, out / DEFAULT_DOT_REFINER)

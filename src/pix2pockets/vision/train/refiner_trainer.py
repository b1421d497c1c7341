"""The training run the crop refiners share (diamond boxes, ball boxes): collect crops, train the classifier's
:class:`~pix2pockets.vision.train.crop_classifier.CropNet` (grid head) with flips, quarter turns and photometric
noise, report held-out errors in ``metrics.json``, save ``last.pt`` and export ONNX."""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import torch
from torch import nn

from pix2pockets.vision.train.crop_classifier import CropNet, photometric
from pix2pockets.vision.train.crop_fit import RawOutputs, fit_crops, flip_rotate, labelled_sources, predict_crops
from pix2pockets.vision.train.onnx_export import write_onnx
from pix2pockets.vision.yolo_data import LabelledImage

Sources = Sequence[tuple[LabelledImage, dict[int, int]]]
CollectCrops = Callable[[Sources, int], tuple[np.ndarray, np.ndarray]]
"""(labelled images, seed) -> (uint8 crops (N, S, S, 3), float32 targets (N, k))."""


def crop_l1_loss(out: torch.Tensor, targets: torch.Tensor, crop_size: int) -> torch.Tensor:
    """Mean L1 distance between predicted and true outputs given as fractions of the crop side, in crop pixels."""
    return (out - targets).abs().sum(dim=1).mean() * crop_size


def centre_size_boxes(t: np.ndarray) -> np.ndarray:
    """xyxy boxes from (centre x, centre y, width, height) rows (n, 4), in the same units."""
    return np.hstack([t[:, :2] - 0.5 * t[:, 2:], t[:, :2] + 0.5 * t[:, 2:]])


@dataclass(frozen=True, slots=True)
class RefinerSpec:
    """What tells one refiner from another.

    Attributes:
        name: what it refines, for messages and the progress bar ("diamond refiner").
        command: its training command, for error messages ("train-dot-refiner").
        crop_size: crop side [px].
        n_outputs: outputs per crop.
        output_name: name of the ONNX output.
        file_name: ONNX file written into the output folder.
    """

    name: str
    command: str
    crop_size: int
    n_outputs: int
    output_name: str
    file_name: str


def check_training_settings(cfg, spec: RefinerSpec) -> None:
    """The checks every refiner config shares (``data``, ``epochs``, ``batch``, ``threads``, ``copies``, ``lr``,
    ``widths``); raises ValueError."""
    if not cfg.data:
        raise ValueError(f"{spec.command} needs at least one --data folder")
    if min(cfg.epochs, cfg.batch, cfg.threads, cfg.copies) < 1 or not cfg.lr > 0:
        raise ValueError("epochs, batch, threads and copies must be >= 1 and lr > 0")
    if len(cfg.widths) != 3 or min(cfg.widths) < 1:
        raise ValueError(f"widths must be three positive channel counts, got {cfg.widths}")


def export_refiner(model: nn.Module, path: Path, spec: RefinerSpec) -> Path:
    """Write a refiner (uint8 NHWC crops in, (N, k) outputs out) as ONNX with a dynamic batch."""
    example = torch.zeros(2, spec.crop_size, spec.crop_size, 3, dtype=torch.uint8)
    axes = {"crops": {0: "n"}, spec.output_name: {0: "n"}}
    return write_onnx(RawOutputs(model), example, path, "crops", spec.output_name, axes)


def train_refiner(
    cfg,
    spec: RefinerSpec,
    collect: CollectCrops,
    loss: Callable[[torch.Tensor, torch.Tensor], torch.Tensor],
    held_out: Callable[[np.ndarray, np.ndarray], dict],
    progress: bool = True,
) -> Path:
    """Train a refiner as ``cfg`` says (a frozen dataclass with ``data``, ``out``, ``epochs``, ``seed``, ``batch``,
    ``lr``, ``threads``, ``widths``) and export it; returns the ONNX path.

    Args:
        cfg: the command's settings; written into ``metrics.json`` and ``last.pt``.
        spec: the refiner's shape and names.
        collect: crops and targets from labelled images with a seed (train split: ``cfg.seed``, test: + 1).
        loss: (outputs, targets) -> scalar loss.
        held_out: (outputs, targets) of the test crops -> the report in ``metrics.json["test"]``.
        progress: show progress bars.
    """
    torch.set_num_threads(cfg.threads)
    torch.manual_seed(cfg.seed)
    out = Path(cfg.out)
    out.mkdir(parents=True, exist_ok=True)
    crops, targets = collect(labelled_sources(cfg.data, "train"), cfg.seed)
    test = labelled_sources(cfg.data, "test")
    model = CropNet(cfg.widths, "grid", spec.crop_size, spec.n_outputs)

    def batch_loss(net: nn.Module, x: torch.Tensor, t: torch.Tensor, gen: torch.Generator) -> torch.Tensor:
        x, t = flip_rotate(x, t, gen)
        return loss(net(photometric(x, gen)), t)

    fit_crops(
        model,
        crops,
        torch.from_numpy(targets),
        batch_loss,
        epochs=cfg.epochs,
        batch=cfg.batch,
        lr=cfg.lr,
        seed=cfg.seed,
        desc=f"train {spec.name}",
        progress=progress,
    )
    metrics = {"config": asdict(cfg), "train_crops": len(targets)}
    if test:
        test_crops, test_targets = collect(test, cfg.seed + 1)
        metrics["test"] = {"crops": len(test_targets), **held_out(predict_crops(model, test_crops), test_targets)}
    (out / "metrics.json").write_text(json.dumps(metrics, indent=2) + "\n")
    torch.save({"model": model.state_dict(), "config": asdict(cfg)}, out / "last.pt")
    return export_refiner(model, out / spec.file_name, spec)

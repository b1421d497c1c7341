"""The training run the crop refiners share (diamond boxes, ball boxes): collect crops, train the classifier's
:class:`~pix2pockets.vision.train.ball_classifier.CropNet` (grid head) on box targets (centre x, y, width,
height as fractions of the crop side) with an L1 loss, flips, quarter turns and photometric noise, report
held-out centre errors and box IoUs in ``metrics.json``, save ``last.pt`` and export ONNX."""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import torch
from torch import nn

from pix2pockets.vision.detect.postprocess import paired_box_iou
from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.train.ball_classifier import CropNet, photometric
from pix2pockets.vision.train.crop_fit import RawOutputs, fit_crops, flip_rotate, labelled_sources, predict_crops
from pix2pockets.vision.train.onnx_export import write_onnx

Sources = Sequence[tuple[LabelledImage, dict[int, int]]]
CollectCrops = Callable[[Sources, int], tuple[np.ndarray, np.ndarray]]
"""(labelled images, seed) -> (uint8 crops (N, S, S, 3), float32 box targets (N, 4))."""
N_BOX_OUTPUTS = 4
"""Outputs of every refiner: the box's centre x, y, width and height as fractions of the crop side."""


def box_loss(out: torch.Tensor, targets: torch.Tensor, crop_size: int) -> torch.Tensor:
    """Mean L1 distance between predicted and true boxes (centre x, y, width, height as fractions of the crop
    side), in crop pixels."""
    return (out - targets).abs().sum(dim=1).mean() * crop_size


def centre_size_boxes(t: np.ndarray) -> np.ndarray:
    """xyxy boxes from (centre x, centre y, width, height) rows (n, 4), in the same units."""
    return np.hstack([t[:, :2] - 0.5 * t[:, 2:], t[:, :2] + 0.5 * t[:, 2:]])


def held_out_report(outputs: np.ndarray, targets: np.ndarray, context: float) -> dict:
    """How far the held-out crops' boxes are from their labels [crop sides]: centre offset of the crop's middle
    and centre error after refinement; box IoU before (a square of one box side, the crop side over `context`,
    at the crop's middle) and after."""
    truth = centre_size_boxes(targets)
    start = np.linalg.norm(targets[:, :2], axis=1)
    err = np.linalg.norm(outputs[:, :2] - targets[:, :2], axis=1)
    report = {
        "centre": {
            "offset_median": round(float(np.median(start)), 5),
            "offset_p90": round(float(np.percentile(start, 90)), 5),
            "error_median": round(float(np.median(err)), 5),
            "error_p90": round(float(np.percentile(err, 90)), 5),
        }
    }
    half = 0.5 / context
    before = paired_box_iou(np.tile([-half, -half, half, half], (len(targets), 1)), truth)
    for tag, iou in (("before", before), ("after", paired_box_iou(centre_size_boxes(outputs), truth))):
        report[tag] = {
            "iou_median": round(float(np.median(iou)), 4),
            "iou_p10": round(float(np.percentile(iou, 10)), 4),
            "at_iou_50": round(float(np.mean(iou >= 0.5)), 4),
            "at_iou_75": round(float(np.mean(iou >= 0.75)), 4),
        }
    return report


@dataclass(frozen=True, slots=True)
class RefinerSpec:
    """What tells one refiner from another.

    Attributes:
        name: what it refines, for messages and the progress bar ("diamond refiner").
        command: its training command, for error messages ("train-diamond-refiner").
        crop_size: crop side [px].
        context: crop side over the detected box's side (for the held-out "before" box).
        output_name: name of the ONNX output.
        file_name: ONNX file written into the output folder.
    """

    name: str
    command: str
    crop_size: int
    context: float
    output_name: str
    file_name: str


def export_refiner(model: nn.Module, path: Path, spec: RefinerSpec) -> Path:
    """Write a refiner (uint8 NHWC crops in, (N, k) outputs out) as ONNX with a dynamic batch."""
    example = torch.zeros(2, spec.crop_size, spec.crop_size, 3, dtype=torch.uint8)
    axes = {"crops": {0: "n"}, spec.output_name: {0: "n"}}
    return write_onnx(RawOutputs(model), example, path, "crops", spec.output_name, axes)


def train_refiner(
    cfg,
    spec: RefinerSpec,
    collect: CollectCrops,
    progress: bool = True,
) -> Path:
    """Train a refiner as ``cfg`` says (a frozen dataclass with ``data``, ``out``, ``epochs``, ``seed``, ``batch``,
    ``lr``, ``threads``, ``widths``) and export it; returns the ONNX path.

    Args:
        cfg: the command's settings; written into ``metrics.json`` and ``last.pt``.
        spec: the refiner's shape and names.
        collect: crops and box targets from labelled images with a seed (train split: ``cfg.seed``, test: + 1).
        progress: show progress bars.
    """
    torch.set_num_threads(cfg.threads)
    torch.manual_seed(cfg.seed)
    out = Path(cfg.out)
    out.mkdir(parents=True, exist_ok=True)
    crops, targets = collect(labelled_sources(cfg.data, "train"), cfg.seed)
    test = labelled_sources(cfg.data, "test")
    model = CropNet(cfg.widths, "grid", spec.crop_size, N_BOX_OUTPUTS)

    def batch_loss(net: nn.Module, x: torch.Tensor, t: torch.Tensor, gen: torch.Generator) -> torch.Tensor:
        x, t = flip_rotate(x, t, gen)
        return box_loss(net(photometric(x, gen)), t, spec.crop_size)

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
        outputs = predict_crops(model, test_crops)
        metrics["test"] = {"crops": len(test_targets), **held_out_report(outputs, test_targets, spec.context)}
    (out / "metrics.json").write_text(json.dumps(metrics, indent=2) + "\n")
    torch.save({"model": model.state_dict(), "config": asdict(cfg)}, out / "last.pt")
    return export_refiner(model, out / spec.file_name, spec)

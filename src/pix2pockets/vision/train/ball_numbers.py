"""Train the ball-number reader (which of the 16 balls a crop shows) on render crops and export it to ONNX.

The network is the ball classifier's (:class:`~pix2pockets.vision.train.ball_classifier.CropNet`, grid head)
with 16 outputs. At run time a ball's class is already known, so the reader only has to tell the colours of one
group apart (:func:`pix2pockets.vision.stages.ball_numbers.assign_numbers`); ``metrics.json`` reports both the plain
accuracy and the accuracy within the true class on the datasets' test splits.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
import torch
from torch import nn

from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.stages.ball_numbers import CLASS_ID_OF_NUMBER, N_NUMBERS, class_mask
from pix2pockets.vision.stages.crops import CROP_SIZE
from pix2pockets.vision.train.ball_classifier import CropNet, augment, export_crop_classifier
from pix2pockets.vision.train.crop_data import CropConfig
from pix2pockets.vision.train.crop_fit import CropTrainSettings, fit_crops, labelled_sources, predict_crops
from pix2pockets.vision.train.number_data import collect_number_crops

ONNX_NAME = "ball-numbers.onnx"


@dataclass(frozen=True, slots=True)
class NumberTrainConfig(CropTrainSettings):
    """Settings of ``pix2pockets train-ball-numbers``.

    Attributes (besides the shared :class:`~pix2pockets.vision.train.crop_fit.CropTrainSettings`):
        copies: jittered crops per labelled ball and image.
        centre_jitter: largest crop centre shift, in ball diameters.
        min_visible: balls showing less of their outline are left out of training.
    """

    command: ClassVar[str] = "train-ball-numbers"

    centre_jitter: float = CropConfig().centre_jitter
    min_visible: float = 0.3

    def check(self) -> None:
        if not 0 <= self.centre_jitter < 0.5 or not 0 <= self.min_visible <= 1:
            raise ValueError(
                f"centre_jitter must be in [0, 0.5) and min_visible in [0, 1], got "
                f"{self.centre_jitter} and {self.min_visible}"
            )


def number_accuracy(probs: np.ndarray, numbers: np.ndarray) -> dict:
    """Accuracy of the most likely number overall and within each ball's true class, and per number within
    its class (numbers with no crops left out)."""
    if len(numbers) == 0:
        return {"n": 0}
    within = np.where(class_mask(CLASS_ID_OF_NUMBER[numbers]), probs, -np.inf).argmax(axis=1)
    per_number = {
        str(n): round(float(np.mean(within[numbers == n] == n)), 4) for n in range(N_NUMBERS) if np.any(numbers == n)
    }
    return {
        "n": len(numbers),
        "accuracy": round(float(np.mean(probs.argmax(axis=1) == numbers)), 4),
        "accuracy_within_class": round(float(np.mean(within == numbers)), 4),
        "within_class_by_number": per_number,
    }


def train_number_reader(cfg: NumberTrainConfig, progress: bool = True) -> Path:
    """Collect crops, train, write held-out accuracies to ``metrics.json``, export; returns the ONNX path."""
    torch.set_num_threads(cfg.threads)
    torch.manual_seed(cfg.seed)
    out = Path(cfg.out)
    out.mkdir(parents=True, exist_ok=True)
    crop_cfg = CropConfig(copies=cfg.copies, centre_jitter=cfg.centre_jitter)
    train_items = [item for item, _ in labelled_sources(cfg.data, "train")]
    crops, numbers = collect_number_crops(train_items, read_image_rgb, cfg.seed, crop_cfg, cfg.min_visible, progress)
    if len(crops) == 0:
        raise ValueError(f"no labelled balls to train on in the train splits of {', '.join(cfg.data)}")
    test_items = [item for item, _ in labelled_sources(cfg.data, "test")]
    test_cfg = CropConfig(low_res=0.0)  # every held-out ball as the detector's box shows it, none left out
    test = collect_number_crops(test_items, read_image_rgb, cfg.seed + 1, test_cfg) if test_items else None

    model = CropNet(cfg.widths, "grid", CROP_SIZE, n_outputs=N_NUMBERS)

    def batch_loss(net: nn.Module, x: torch.Tensor, y: torch.Tensor, gen: torch.Generator) -> torch.Tensor:
        return nn.functional.cross_entropy(net(augment(x, gen)), y)

    fit_crops(
        model,
        crops,
        torch.from_numpy(numbers),
        batch_loss,
        epochs=cfg.epochs,
        batch=cfg.batch,
        lr=cfg.lr,
        seed=cfg.seed,
        desc="train ball-number reader",
        progress=progress,
    )
    metrics = {"config": asdict(cfg), "train_counts": np.bincount(numbers, minlength=N_NUMBERS).tolist()}
    if test is not None and len(test[0]):
        logits = predict_crops(model, test[0])
        metrics["test"] = number_accuracy(logits, test[1])
    (out / "metrics.json").write_text(json.dumps(metrics, indent=2) + "\n")
    torch.save({"model": model.state_dict(), "config": asdict(cfg)}, out / "last.pt")
    return export_crop_classifier(model, out / ONNX_NAME, CROP_SIZE)

"""What the crop networks' training shares (ball classifier, ball-number reader, diamond and ball refiners): the
settings and their checks, AdamW with a cosine learning rate, shuffled batches, a progress bar; the labelled
datasets they read; the refiners' flips and turns and their exported form."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import torch
from torch import nn

from pix2pockets.vision.metrics.yolo_data import LabelledImage, dataset_class_map, load_split

BatchLoss = Callable[[nn.Module, torch.Tensor, torch.Tensor, torch.Generator], torch.Tensor]
"""(model, crops (B, 3, S, S) float 0-255, targets (B, ...), generator) -> loss; augments the batch itself."""


@dataclass(frozen=True, slots=True)
class CropTrainSettings:
    """Settings every crop network's training shares; each trainer's config adds its own and checks them in
    :meth:`check`.

    Attributes:
        data: datasets to read (repeatable ``--data``).
        out: output folder.
        epochs: passes over the crops.
        seed: seed for crops, order, augmentation and initialisation.
        batch: crops per step.
        lr: peak learning rate (AdamW, cosine decay).
        threads: torch CPU threads.
        widths: channels of the network's three stages.
        copies: jittered crops per labelled object and image.
    """

    command: ClassVar[str] = "train"
    """The training command, named in error messages."""

    data: tuple[str, ...]
    out: str
    epochs: int = 6
    seed: int = 0
    batch: int = 256
    lr: float = 3e-3
    threads: int = 1
    widths: tuple[int, int, int] = (16, 32, 64)
    copies: int = 1

    def __post_init__(self) -> None:
        if not self.data:
            raise ValueError(f"{self.command} needs at least one --data folder")
        if min(self.epochs, self.batch, self.threads, self.copies) < 1 or not self.lr > 0:
            raise ValueError("epochs, batch, threads and copies must be >= 1 and lr > 0")
        if len(self.widths) != 3 or min(self.widths) < 1:
            raise ValueError(f"widths must be three positive channel counts, got {self.widths}")
        self.check()

    def check(self) -> None:
        """The checks of a trainer's own settings (ValueError); none here."""


def labelled_sources(roots: Sequence[str], split: str) -> list[tuple[LabelledImage, dict[int, int]]]:
    """The `split` images of YOLO datasets with each one's class map; datasets without a test split are skipped
    for "test", a missing train split is an error (ValueError)."""
    out = []
    for root in roots:
        cmap = dataset_class_map(root)
        try:
            out += [(it, cmap) for it in load_split(root, split)]
        except ValueError:
            if split == "train":
                raise
    return out


def fit_crops(
    model: nn.Module,
    crops: np.ndarray,
    targets: torch.Tensor,
    batch_loss: BatchLoss,
    *,
    epochs: int,
    batch: int,
    lr: float,
    seed: int,
    desc: str,
    progress: bool = True,
) -> None:
    """Train `model` in place on uint8 crops (N, S, S, 3) and their targets (N, ...).

    Each epoch visits the crops in a fresh order from ``np.random.default_rng(seed)``; augmentation draws from a
    ``torch.Generator`` seeded with `seed`; the learning rate falls from `lr` to 0 on a cosine.
    """
    from tqdm import tqdm

    opt = torch.optim.AdamW(model.parameters(), lr=lr, weight_decay=1e-4)
    gen = torch.Generator().manual_seed(seed)
    order_rng = np.random.default_rng(seed)
    steps_per_epoch = max(1, len(crops) // batch)
    total = steps_per_epoch * epochs
    x_all = torch.from_numpy(crops).permute(0, 3, 1, 2)
    bar = tqdm(total=total, desc=desc, disable=not progress)
    step = 0
    for _epoch in range(epochs):
        model.train()
        order = torch.from_numpy(order_rng.permutation(len(crops)))
        for s in range(steps_per_epoch):
            idx = order[s * batch : (s + 1) * batch]
            for g in opt.param_groups:
                g["lr"] = lr * 0.5 * (1 + math.cos(math.pi * step / total))
            loss = batch_loss(model, x_all[idx].float(), targets[idx], gen)
            opt.zero_grad()
            loss.backward()
            opt.step()
            step += 1
            bar.update(1)
            bar.set_postfix(loss=f"{loss.item():.3f}")
    bar.close()


class RawOutputs(nn.Module):
    """What a refiner's ONNX file computes: uint8 crops (N, S, S, 3) -> the network's outputs (N, k)."""

    def __init__(self, net: nn.Module) -> None:
        super().__init__()
        self.net = net

    def forward(self, crops: torch.Tensor) -> torch.Tensor:
        return self.net(crops.permute(0, 3, 1, 2).float())


def flip_rotate(x: torch.Tensor, targets: torch.Tensor, gen: torch.Generator) -> tuple[torch.Tensor, torch.Tensor]:
    """A random mirror and quarter turn of a batch of crops (N, 3, S, S), applied to their targets too: (N, 2)
    centres as fractions of the crop side from its middle, optionally followed by a width and height (N, 4),
    which a quarter turn swaps."""
    t = targets.clone()
    if bool(torch.rand(1, generator=gen) < 0.5):
        x = x.flip(3)
        t[:, 0] = -t[:, 0]
    for _ in range(int(torch.randint(0, 4, (1,), generator=gen))):
        # rot90 over (rows, columns): the pixel at (row r, column c) moves to (S - 1 - c, r)
        x = torch.rot90(x, 1, dims=(2, 3))
        turned = [t[:, 1], -t[:, 0]]
        if t.shape[1] == 4:
            turned += [t[:, 3], t[:, 2]]
        t = torch.stack(turned, dim=1)
    return x, t


def predict_crops(model: nn.Module, crops: np.ndarray, chunk: int = 1024) -> np.ndarray:
    """The network's outputs (N, k) for uint8 crops (N, S, S, 3), in eval mode, `chunk` crops at a time."""
    model.eval()
    outs = []
    with torch.no_grad():
        for i in range(0, len(crops), chunk):
            outs.append(model(torch.from_numpy(crops[i : i + chunk]).permute(0, 3, 1, 2).float()).numpy())
    return np.concatenate(outs) if outs else np.zeros((0, 0), np.float32)

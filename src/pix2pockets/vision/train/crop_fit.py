"""The training loop the crop networks share (ball classifier, diamond refiner): AdamW with a cosine learning
rate, shuffled batches, a progress bar; and the labelled datasets they read."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
import torch
from torch import nn

from pix2pockets.vision.yolo_data import LabelledImage, dataset_class_map, load_split

BatchLoss = Callable[[nn.Module, torch.Tensor, torch.Tensor, torch.Generator], torch.Tensor]
"""(model, crops (B, 3, S, S) float 0-255, targets (B, ...), generator) -> loss; augments the batch itself."""


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

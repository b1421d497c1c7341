"""Train the table model (playing surface, its corners, its side pockets) on renders and export it to ONNX.

The network is the detector's (:class:`~pix2pockets.vision.train.detector_model.CenterNet`: MobileNetV2 trunk and
a neck to stride 4) with a head of its own: three channels, the surface chance and two keypoint heatmaps
(:mod:`pix2pockets.vision.table.keypoints`). It starts from the shipped detector's trunk and neck, which already
know pool tables in renders and real photos, and learns from the exact, amodal targets of
:mod:`pix2pockets.vision.train.table_data`: binary cross-entropy on the surface, the detector's focal loss on the
keypoints. Seeded, writes ``last.pt`` each epoch, ``metrics.json`` (held-out surface IoU, corner and side-pocket
recall) and ``table.onnx``.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F  # noqa: N812

from pix2pockets.torch_device import resolve_device
from pix2pockets.vision.table.keypoints import (
    CORNER_CHANNEL,
    DEFAULT_TABLE_MODEL,
    INPUT_LONG_SIDE,
    N_TABLE_CHANNELS,
    OUTPUT_NAME,
    SIDE_CHANNEL,
    SURFACE_CHANNEL,
    peaks,
)
from pix2pockets.vision.train.detector_loss import focal_loss
from pix2pockets.vision.train.detector_model import CenterNet, sep_conv
from pix2pockets.vision.train.onnx_export import write_onnx
from pix2pockets.vision.train.table_data import TableAugment, augment_sample, load_item, render_items

CHECKPOINT = "last.pt"
HELD_OUT_KEY = 1 << 20
"""Seed-sequence key of the held-out renders (apart from the epochs' keys)."""
SURFACE_WEIGHT = 1.0
KEYPOINT_WEIGHT = 1.0
RECALL_CELLS = 2.0
"""A held-out keypoint counts as found when a peak lies within this many output cells (8 input px)."""


@dataclass(frozen=True, slots=True)
class TableTrainConfig:
    """Settings of ``pix2pockets train-table``.

    Attributes:
        data: ``pix2pockets synth`` datasets (their train splits train, their valid splits measure).
        out: output folder.
        init: a fp32 ONNX file that starts the network, or None: a table model (e.g. the shipped one) starts all
            of it (fine-tuning), a detector its trunk and neck.
        epochs, batch, lr, seed: the usual; ``lr`` is the peak of a cosine schedule with a short warm-up.
        workers: data-loading processes (0: in the training process).
        device: ``cpu``, ``cuda`` or ``auto``.
        augment: augmentation settings.
    """

    data: tuple[str, ...]
    out: str
    init: str | None = None
    epochs: int = 12
    batch: int = 32
    lr: float = 2e-3
    seed: int = 0
    workers: int = 0
    device: str = "auto"
    augment: TableAugment = field(default_factory=TableAugment)

    def check(self) -> None:
        if not self.data:
            raise ValueError("give at least one --data dataset")
        if self.epochs < 1 or self.batch < 1 or not self.lr > 0:
            raise ValueError("epochs and batch must be >= 1 and lr > 0")


class TableNet(nn.Module):
    """The detector's trunk and neck with a three-channel table head; input RGB in [0, 1] (N, 3, H, W)."""

    def __init__(self, body: CenterNet | None = None, width: int = 64) -> None:
        super().__init__()
        self.body = body or CenterNet(width=width, pretrained=False)
        head = nn.Sequential(sep_conv(width, width), nn.Conv2d(width, N_TABLE_CHANNELS, 1))
        nn.init.normal_(head[-1].weight, std=0.001)
        nn.init.zeros_(head[-1].bias)
        with torch.no_grad():
            head[-1].bias[CORNER_CHANNEL] = head[-1].bias[SIDE_CHANNEL] = -math.log(99.0)
        self.body.head = head
        self.frozen_norms = False
        """Keep the batch norms in eval mode while training (:func:`set_train_mode`)."""

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """Logits (N, 3, H/4, W/4)."""
        return self.body(x)


class ExportTable(nn.Module):
    """What the ONNX file computes: the three channels as chances."""

    def __init__(self, net: TableNet) -> None:
        super().__init__()
        self.net = net

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return torch.sigmoid(self.net(x))


def export_table(net: TableNet, path: Path) -> Path:
    """Write the model as ONNX (float input (n, 3, h, w) in [0, 1], output ``table``) with dynamic sizes."""
    axes = {"image": {0: "n", 2: "h", 3: "w"}, OUTPUT_NAME: {0: "n", 2: "h4", 3: "w4"}}
    example = torch.zeros(1, 3, INPUT_LONG_SIDE * 9 // 16 // 32 * 32 + 32, INPUT_LONG_SIDE)
    return write_onnx(ExportTable(net.cpu()), example, path, "image", OUTPUT_NAME, axes)


def table_loss(logits: torch.Tensor, target: torch.Tensor) -> tuple[torch.Tensor, dict[str, float]]:
    """Surface BCE + keypoint focal loss; also returns the parts."""
    surface = F.binary_cross_entropy_with_logits(logits[:, SURFACE_CHANNEL], target[:, SURFACE_CHANNEL])
    keys = slice(CORNER_CHANNEL, SIDE_CHANNEL + 1)
    ones = torch.ones(logits.shape[0], 2, device=logits.device)
    keypoints = focal_loss(logits[:, keys], target[:, keys], ones)
    total = SURFACE_WEIGHT * surface + KEYPOINT_WEIGHT * keypoints
    return total, {"surface": float(surface.detach()), "keypoints": float(keypoints.detach())}


class _Renders(torch.utils.data.Dataset):
    def __init__(self, items: list[tuple[Path, Path]], cfg: TableTrainConfig, epoch_key: int, train: bool) -> None:
        self.items, self.cfg, self.key, self.train = items, cfg, epoch_key, train

    def __len__(self) -> int:
        return len(self.items)

    def __getitem__(self, i: int):
        image, truth = load_item(*self.items[i])
        rng = np.random.default_rng((self.cfg.seed, self.key, i))
        aug = self.cfg.augment
        if not self.train:  # held out: no zoom, turn or colour change, only the letterbox
            aug = TableAugment(aug.input_size, zoom_share=0.0, rotate_deg=0.0, hue_share=0.0, blur_share=0.0,
                               noise_share=0.0, jpeg_share=0.0, grey_share=0.0)  # fmt: skip
        x, y = augment_sample(image, truth, aug, rng)
        return torch.from_numpy(x), torch.from_numpy(y)


def is_table_export(path: str | Path) -> bool:
    """Whether an ONNX file is a table model (its output is :data:`OUTPUT_NAME`) rather than a detector."""
    from pix2pockets.vision.train.onnx_file import load_onnx_model

    return any(out.name == OUTPUT_NAME for out in load_onnx_model(Path(path)).graph.output)


def init_network(path: str | None, width: int = 64) -> TableNet:
    """The network to train: a table model's weights whole, a detector's trunk and neck under a new head, or a
    fresh network when ``path`` is None."""
    if path is None:
        return TableNet(width=width)
    from pix2pockets.vision.train.onnx_import import load_onnx_into

    calibration = torch.rand(4, 3, 128, 128, generator=torch.Generator().manual_seed(0))
    if is_table_export(path):
        net = load_onnx_into(TableNet(width=width), path, calibration)
        net.frozen_norms = True  # fine-tuning: see set_train_mode
        return net
    return TableNet(load_onnx_into(CenterNet(width=width, pretrained=False), path, calibration))


def set_train_mode(net: TableNet) -> None:
    """Training mode, with the batch norms frozen (running statistics kept, affine weights still learnt) when the
    network was loaded from a table model: its norms hold the statistics of the data it learnt from, and a
    fine-tuning batch's own statistics would move every layer's output at the first step."""
    net.train()
    if net.frozen_norms:
        for m in net.modules():
            if isinstance(m, nn.BatchNorm2d):
                m.eval()


def held_out_report(net: TableNet, loader, device: torch.device) -> dict:
    """Surface IoU (cells above 0.5) and keypoint recall within :data:`RECALL_CELLS` on held-out renders."""
    net.eval()
    inter = union = 0.0
    found = {CORNER_CHANNEL: [0, 0], SIDE_CHANNEL: [0, 0]}
    with torch.no_grad():
        for x, y in loader:
            p = torch.sigmoid(net(x.to(device))).float().cpu().numpy()
            y = y.numpy()
            pred, true = p[:, SURFACE_CHANNEL] >= 0.5, y[:, SURFACE_CHANNEL] >= 0.5
            inter += float((pred & true).sum())
            union += float((pred | true).sum())
            for c in found:
                for k in range(len(x)):
                    truth = np.argwhere(y[k, c] >= 0.999)[:, ::-1]
                    got = peaks(p[k, c])[:, :2]
                    found[c][1] += len(truth)
                    if len(truth) and len(got):
                        d = np.linalg.norm(truth[:, None] - got[None], axis=2).min(axis=1)
                        found[c][0] += int((d <= RECALL_CELLS).sum())
    set_train_mode(net)
    return {
        "surface_iou": round(inter / max(union, 1.0), 4),
        "corner_recall": round(found[CORNER_CHANNEL][0] / max(found[CORNER_CHANNEL][1], 1), 4),
        "side_pocket_recall": round(found[SIDE_CHANNEL][0] / max(found[SIDE_CHANNEL][1], 1), 4),
        "corners": found[CORNER_CHANNEL][1],
        "side_pockets": found[SIDE_CHANNEL][1],
    }


def train_table(cfg: TableTrainConfig, progress: bool = True) -> Path:
    """Train, report, export; returns the ONNX path."""
    cfg.check()
    out = Path(cfg.out)
    out.mkdir(parents=True, exist_ok=True)
    torch.manual_seed(cfg.seed)
    device = torch.device(resolve_device(cfg.device))
    train_items = render_items(list(cfg.data), "train")
    valid_items = render_items(list(cfg.data), "valid")
    net = init_network(cfg.init).to(device)
    set_train_mode(net)
    opt = torch.optim.AdamW([p for p in net.parameters() if p.requires_grad], lr=cfg.lr, weight_decay=1e-4)
    steps = cfg.epochs * math.ceil(len(train_items) / cfg.batch)
    warm = max(1, steps // 30)
    sched = torch.optim.lr_scheduler.LambdaLR(
        opt, lambda s: min(1.0, (s + 1) / warm) * 0.5 * (1 + math.cos(math.pi * min(s, steps) / steps))
    )
    loader_args = {"batch_size": cfg.batch, "num_workers": cfg.workers, "persistent_workers": False}
    valid = torch.utils.data.DataLoader(_Renders(valid_items, cfg, HELD_OUT_KEY, False), shuffle=False, **loader_args)
    history = []
    t0 = time.perf_counter()
    for epoch in range(cfg.epochs):
        data = _Renders(train_items, cfg, epoch, True)
        order = torch.Generator().manual_seed(cfg.seed * 1000 + epoch)
        loader = torch.utils.data.DataLoader(data, shuffle=True, generator=order, drop_last=True, **loader_args)
        losses = []
        for x, y in loader:
            with torch.autocast(device.type, dtype=torch.bfloat16, enabled=device.type == "cuda"):
                logits = net(x.to(device, non_blocking=True))
            loss, _ = table_loss(logits.float(), y.to(device, non_blocking=True))
            opt.zero_grad(set_to_none=True)
            loss.backward()
            opt.step()
            sched.step()
            losses.append(float(loss.detach()))
        report = {"epoch": epoch + 1, "loss": round(float(np.mean(losses)), 4), "minutes": 0.0}
        report.update(held_out_report(net, valid, device))
        report["minutes"] = round((time.perf_counter() - t0) / 60, 2)
        history.append(report)
        if progress:
            print(json.dumps(report), flush=True)
        torch.save({"model": net.state_dict(), "epoch": epoch + 1}, out / CHECKPOINT)
    config = asdict(cfg)
    (out / "metrics.json").write_text(json.dumps({"config": config, "history": history}, indent=2) + "\n")
    return export_table(net.eval(), out / DEFAULT_TABLE_MODEL)

"""Training loop of the heatmap detector: seeded, checkpointed, resumable, exports ONNX.

Run it through ``pix2pockets train-detector``. Checkpoints (``last.pt``) hold the model, optimiser and the
position in the epoch; each sample's augmentation is drawn from ``np.random.default_rng((seed, epoch,
index))``, so a resumed run sees the same samples as an uninterrupted one.
"""

from __future__ import annotations

import dataclasses
import inspect
import json
import math
import os
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import cv2
import numpy as np
import torch
from tqdm import tqdm

from pix2pockets.torch_device import resolve_device
from pix2pockets.vision.metrics.yolo_data import LabelledImage, dataset_class_map, load_split, load_splits
from pix2pockets.vision.train.detector_loss import detector_loss
from pix2pockets.vision.train.detector_model import CenterNet, ExportWrapper
from pix2pockets.vision.train.detector_targets import AugmentConfig, Sample, make_sample
from pix2pockets.vision.train.onnx_export import write_onnx

CHECKPOINT = "last.pt"
ONNX_NAME = "detector.onnx"


@dataclass(frozen=True, slots=True)
class TrainConfig:
    """Training settings (all recorded in the checkpoint and the ONNX metadata file).

    Attributes:
        data: YOLO datasets with the five classes (their ``train`` split is used).
        balls: ball-only YOLO datasets (e.g. real photos); class ``balls_class`` is "ball", others ignored.
        balls_exclude: file-name glob patterns of ball-only images to leave out (e.g. frames of the video
            that the validation photos come from).
        balls_table_class: class id of a whole-table box in the ball-only sets; outside it the diamond
            channel learns "no diamond" (None: diamonds unsupervised in those photos).
        out: output folder (checkpoints, log, ONNX).
        epochs: passes over the five-class training images.
        seed: the one seed for initialisation, order and augmentation.
        batch: images per step.
        lr: peak AdamW learning rate (cosine decay, linear warm-up).
        threads: torch CPU threads.
        workers: data-loading processes that build the augmented batches (0: in the training process); the
            batches are the same for any number.
        device: a torch device name or ``auto`` (``cuda`` where there is one; checked by
            :func:`~pix2pockets.torch_device.resolve_device`); on a GPU the forward pass runs in bfloat16.
        limit: use only the first ``limit`` five-class training images (training-size ablation).
        balls_fraction: ball-only images per epoch, as a fraction of the five-class images (at most all of
            them once, unless ``balls_repeat``).
        balls_repeat: draw ball-only images with repeats when ``balls_fraction`` asks for more than there are
            (each copy is augmented differently).
        checkpoint_minutes: save ``last.pt`` at least this often [min].
        max_minutes: stop (checkpoint + export) after this much wall time in one call [min]; 0 = no limit.
        pretrained: start the trunk from ImageNet weights.
        init: start from the model weights of this checkpoint (a ``last.pt``).
        augment: crop size, zoom, flips, colour and stretch of the training samples.
    """

    data: tuple[str, ...]
    out: str
    balls: tuple[str, ...] = ()
    balls_class: int = 0
    balls_exclude: tuple[str, ...] = ()
    balls_table_class: int | None = None
    epochs: int = 10
    seed: int = 0
    batch: int = 8
    lr: float = 2e-3
    threads: int = 1
    workers: int = 0
    device: str = "cpu"
    limit: int | None = None
    balls_fraction: float = 0.25
    balls_repeat: bool = False
    checkpoint_minutes: float = 5.0
    max_minutes: float = 0.0
    pretrained: bool = True
    init: str | None = None
    augment: AugmentConfig = field(default_factory=AugmentConfig)

    def __post_init__(self) -> None:
        if not self.data and not self.balls:
            raise ValueError("train-detector needs at least one --data (or --balls) folder")
        if self.epochs < 1 or self.batch < 1 or self.threads < 1:
            raise ValueError("epochs, batch and threads must be >= 1")
        if self.workers < 0:
            raise ValueError("workers must be >= 0")
        if self.limit is not None and self.limit < 1:
            raise ValueError("limit must be >= 1")
        if not (self.lr > 0 and 0 <= self.balls_fraction <= 4):
            raise ValueError("lr must be > 0 and balls_fraction in [0, 4]")


def _load_sources(cfg: TrainConfig) -> tuple[list[tuple[LabelledImage, dict[int, int]]], list[LabelledImage]]:
    main = []
    for root in cfg.data:
        cmap = dataset_class_map(root)
        main += [(it, cmap) for it in load_split(root, "train")]
    if cfg.limit is not None:
        main = main[: cfg.limit]
    return main, load_splits(cfg.balls, "train", cfg.balls_exclude)


def _lr_at(step: int, total: int, peak: float) -> float:
    warm = min(200, max(1, total // 20))
    if step < warm:
        return peak * (step + 1) / warm
    return peak * 0.5 * (1 + math.cos(math.pi * min(1.0, (step - warm) / max(1, total - warm))))


def _read_rgb(path: Path) -> np.ndarray:
    img = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if img is None:
        raise ValueError(f"cannot read image {path}")
    return cv2.cvtColor(img, cv2.COLOR_BGR2RGB)


def _collate(samples: list) -> dict[str, torch.Tensor]:
    keys = [f.name for f in dataclasses.fields(samples[0])]
    return {k: torch.from_numpy(np.stack([getattr(s, k) for s in samples])) for k in keys}


def _save(path: Path, state: dict) -> None:
    tmp = path.with_suffix(".tmp")
    torch.save(state, tmp)
    os.replace(tmp, path)


def export_onnx(model: CenterNet, path: Path, example_hw: tuple[int, int] = (384, 640)) -> Path:
    """Write the model (sigmoid + peak isolation included) as ONNX with dynamic height and width."""
    axes = {"image": {0: "n", 2: "h", 3: "w"}, "out": {0: "n", 2: "h4", 3: "w4"}}
    return write_onnx(ExportWrapper(model), torch.zeros(1, 3, *example_hw), path, "image", "out", axes)


def export_checkpoint(checkpoint: str | Path, onnx_path: str | Path) -> Path:
    """Export the model of a ``last.pt`` checkpoint to ONNX (e.g. while training still runs)."""
    state = torch.load(checkpoint, map_location="cpu", weights_only=False)
    model = CenterNet(pretrained=False)
    model.load_state_dict(state["model"])
    return export_onnx(model.eval(), Path(onnx_path))


def reexport_onnx(source: str | Path, onnx_path: str | Path, seed: int = 0) -> Path:
    """Write the weights of a fp32 detector ONNX file again with the current export graph (:class:`ExportWrapper`).

    For a change in what the graph computes around the network (e.g. the ball candidate rule) without retraining;
    the network's function is unchanged (the imported weights reproduce the file exactly in eval mode).
    """
    from pix2pockets.vision.train.onnx_import import load_onnx_into

    model = CenterNet(pretrained=False)
    calibration = torch.rand(2, 3, 64, 64, generator=torch.Generator().manual_seed(seed))
    load_onnx_into(model, source, calibration)
    return export_onnx(model.eval(), Path(onnx_path))


INIT_CALIBRATION_IMAGES = 16
INIT_CALIBRATION_STREAM = 1 << 30
"""Seed-sequence key of the calibration crops (apart from the epochs' keys)."""


def _load_init(
    model: CenterNet,
    cfg: TrainConfig,
    main: list[tuple[LabelledImage, dict[int, int]]],
    balls: list[LabelledImage],
) -> None:
    """Start from ``cfg.init``: a ``last.pt`` checkpoint, or a fp32 detector ONNX file (e.g. the shipped one)."""
    init = Path(cfg.init)
    if not init.is_file():
        raise ValueError(f"--init: no file {init}")
    if init.suffix != ".onnx":
        try:
            model.load_state_dict(torch.load(init, map_location="cpu", weights_only=False)["model"])
        except Exception as err:  # unpickling and state-dict errors come in many types
            raise ValueError(f"--init: {init} is not a detector checkpoint (last.pt): {err}") from err
        return
    from pix2pockets.vision.train.onnx_import import load_onnx_into

    # batch-norm statistics are measured on training crops drawn like the first steps' (own seed stream)
    items = list(main) + [(it, None) for it in balls]
    picks = np.random.default_rng((cfg.seed, INIT_CALIBRATION_STREAM)).permutation(len(items))
    crops = [
        _sample(cfg, *items[int(j)], np.random.default_rng((cfg.seed, INIT_CALIBRATION_STREAM, int(j)))).image
        for j in picks[:INIT_CALIBRATION_IMAGES]
    ]
    load_onnx_into(model, init, torch.from_numpy(np.stack(crops)))


def _sample(
    cfg: TrainConfig, item: LabelledImage, class_map: dict[int, int] | None, rng: np.random.Generator
) -> Sample:
    """One augmented training sample; ``class_map`` None marks a ball-only photo."""
    ball_only = class_map is None
    return make_sample(
        _read_rgb(item.image_path),
        item,
        {cfg.balls_class: 0} if ball_only else class_map,
        ball_only,
        cfg.augment,
        rng,
        cfg.balls_table_class,
    )


class _EpochBatches(torch.utils.data.Dataset):
    """The collated batches of one epoch, batch ``b`` built from ``order[b * batch : (b + 1) * batch]``."""

    def __init__(self, cfg: TrainConfig, items: list, order: np.ndarray, epoch: int) -> None:
        self.cfg, self.items, self.order, self.epoch = cfg, items, order, epoch

    def __len__(self) -> int:
        return max(1, len(self.order) // self.cfg.batch)

    def __getitem__(self, b: int) -> dict[str, torch.Tensor]:
        idx = self.order[b * self.cfg.batch : (b + 1) * self.cfg.batch]
        rngs = (np.random.default_rng((self.cfg.seed, self.epoch, int(j))) for j in idx)
        return _collate([_sample(self.cfg, *self.items[j], rng) for j, rng in zip(idx, rngs, strict=True)])


def _new_model(cfg: TrainConfig, resume: bool) -> CenterNet:
    """The network to train. ImageNet trunk weights are read only when nothing else sets them: with ``--init``
    or a resume every weight is overwritten, so the weights package is not needed; the trunk's first layers are
    frozen all the same (the same random draws, so the result does not depend on that package)."""
    if not (cfg.pretrained and (cfg.init or resume)):
        return CenterNet(pretrained=cfg.pretrained)
    model = CenterNet(pretrained=False)
    model.n_frozen = inspect.signature(CenterNet).parameters["frozen_layers"].default
    for p in model.backbone.features[: model.n_frozen].parameters():
        p.requires_grad_(False)
    return model


def train(cfg: TrainConfig, resume: bool = False, progress: bool = True) -> Path:
    """Train (or resume) and export; returns the ONNX path.

    Raises:
        ValueError: for missing data, or ``resume`` without a checkpoint of the same settings.
    """
    device = torch.device(resolve_device(cfg.device))
    out = Path(cfg.out)
    out.mkdir(parents=True, exist_ok=True)
    torch.set_num_threads(cfg.threads)
    torch.manual_seed(cfg.seed)
    main, balls = _load_sources(cfg)
    model = _new_model(cfg, resume)
    opt = torch.optim.AdamW([p for p in model.parameters() if p.requires_grad], lr=cfg.lr, weight_decay=1e-4)
    if cfg.init and not resume:
        _load_init(model, cfg, main, balls)
    n_balls = (round(cfg.balls_fraction * len(main)) if main else len(balls)) if balls else 0
    if not cfg.balls_repeat:
        n_balls = min(n_balls, len(balls))
    per_epoch = len(main) + n_balls
    steps_per_epoch = max(1, per_epoch // cfg.batch)
    total = steps_per_epoch * cfg.epochs
    epoch, batch_i, step, trained_s = 0, 0, 0, 0.0
    ckpt = out / CHECKPOINT
    if resume:
        if not ckpt.exists():
            raise ValueError(f"--resume: no checkpoint {ckpt}")
        state = torch.load(ckpt, map_location="cpu", weights_only=False)
        old = dict(state["config"])
        new = _comparable(cfg)
        free = ("epochs", "max_minutes", "checkpoint_minutes", "threads", "workers", "device")
        changed = [k for k in new if k not in free and old.get(k) != new[k]]
        if changed:
            raise ValueError(f"--resume: settings differ from the checkpoint in {changed}")
        model.load_state_dict(state["model"])
        opt.load_state_dict(state["optimizer"])
        epoch, batch_i, step, trained_s = state["epoch"], state["batch"], state["step"], state["trained_s"]
    model.to(device)
    log = (out / "train_log.jsonl").open("a")
    started = last_ckpt = time.monotonic()

    def checkpoint() -> None:
        _save(
            ckpt,
            {
                "model": model.state_dict(),
                "optimizer": opt.state_dict(),
                "epoch": epoch,
                "batch": batch_i,
                "step": step,
                "trained_s": trained_s + time.monotonic() - started,
                "config": _comparable(cfg),
            },
        )

    stop = False
    bar = tqdm(total=total, initial=step, disable=not progress, desc="train-detector", unit="step")
    model.train()
    while epoch < cfg.epochs and not stop:
        order_rng = np.random.default_rng((cfg.seed, epoch))
        items: list[tuple[LabelledImage, dict[int, int] | None]] = list(main)
        if n_balls:
            picks = order_rng.choice(len(balls), n_balls, replace=n_balls > len(balls))
            items += [(balls[i], None) for i in picks]
        order = order_rng.permutation(len(items))
        batches = torch.utils.data.DataLoader(
            _EpochBatches(cfg, items, order, epoch),
            batch_size=None,
            sampler=range(batch_i, steps_per_epoch),
            num_workers=cfg.workers,
            pin_memory=device.type == "cuda",
        )
        for batch in batches:
            batch = {k: v.to(device, non_blocking=True) for k, v in batch.items()}
            for g in opt.param_groups:
                g["lr"] = _lr_at(step, total, cfg.lr)
            with torch.autocast(device.type, dtype=torch.bfloat16, enabled=device.type == "cuda"):
                heads = model(batch["image"])
            loss, parts = detector_loss(heads.float(), batch)
            opt.zero_grad(set_to_none=True)
            loss.backward()
            torch.nn.utils.clip_grad_norm_(model.parameters(), 10.0)
            opt.step()
            step += 1
            batch_i += 1
            bar.update(1)
            bar.set_postfix(loss=f"{loss.item():.3f}", epoch=epoch)
            if step % 10 == 0:
                log.write(
                    json.dumps(
                        {
                            "step": step,
                            "epoch": epoch,
                            "loss": round(loss.item(), 4),
                            **{k: round(v, 4) for k, v in parts.items()},
                            "lr": opt.param_groups[0]["lr"],
                            "t": round(trained_s + time.monotonic() - started, 1),
                        }
                    )
                    + "\n"
                )
                log.flush()
            now = time.monotonic()
            if now - last_ckpt > cfg.checkpoint_minutes * 60:
                checkpoint()
                last_ckpt = now
            if cfg.max_minutes and now - started > cfg.max_minutes * 60:
                stop = True
                break
        if not stop:
            epoch, batch_i = epoch + 1, 0
    bar.close()
    checkpoint()
    model.to("cpu").eval()
    path = export_onnx(model, out / ONNX_NAME)
    meta = {
        "config": _comparable(cfg),
        "epoch": epoch,
        "step": step,
        "total_steps": total,
        "finished": epoch >= cfg.epochs,
    }
    (out / "detector.json").write_text(json.dumps(meta, indent=2))
    log.close()
    return path


def _comparable(cfg: TrainConfig) -> dict:
    d = asdict(cfg)
    d["data"], d["balls"], d["balls_exclude"] = list(cfg.data), list(cfg.balls), list(cfg.balls_exclude)
    d["augment"] = {k: list(v) if isinstance(v, tuple) else v for k, v in d["augment"].items()}
    return d

"""Train the second-stage ball classifier (cue, black, solid, stripe, no ball) on crops and export it to ONNX.

A small VGG-style network on 32 px crops: three stages of two 3x3 convolutions (16, 32, 64 channels), then
a head: ``"grid"`` (default) pools the 8x8 feature map to 4x4 and reads it with one linear layer, so the
class can depend on *where* colour sits in the crop (a white disc that fills the ball's outline is the cue
ball; a white cap inside a coloured ring is a stripe seen from its pole); ``"mean"`` averages the feature
map over the crop first. About 80 k parameters, about 6 MFLOPs per crop.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import ClassVar

import numpy as np
import torch
from torch import nn

from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.metrics.yolo_data import LabelledImage, ball_set_of, load_splits
from pix2pockets.vision.stages.ball_classifier import OUTPUT_NAME
from pix2pockets.vision.stages.ball_colours import SOLID_ID, STRIPE_ID
from pix2pockets.vision.stages.crops import CROP_SIZE
from pix2pockets.vision.train.crop_data import CROP_LABELS, NO_BALL, CropConfig, collect_crops, degrade_crops
from pix2pockets.vision.train.crop_fit import CropTrainSettings, fit_crops, labelled_sources, predict_crops
from pix2pockets.vision.train.icon_crops import ball_icon_crops
from pix2pockets.vision.train.onnx_export import write_onnx

ONNX_NAME = "ball-classifier.onnx"


def _block(cin: int, cout: int) -> nn.Sequential:
    return nn.Sequential(
        nn.Conv2d(cin, cout, 3, padding=1, bias=False),
        nn.BatchNorm2d(cout),
        nn.ReLU(inplace=True),
        nn.Conv2d(cout, cout, 3, padding=1, bias=False),
        nn.BatchNorm2d(cout),
        nn.ReLU(inplace=True),
    )


HEADS = ("grid", "mean")
"""Classifier heads: a linear layer on the 4x4-pooled feature map, or on its mean over the crop."""


class CropNet(nn.Module):
    """Outputs (N, n_outputs) for crops given as uint8-valued floats (N, 3, S, S) in RGB, S = ``crop_size``;
    by default the logits of the classifier's five labels."""

    def __init__(
        self,
        widths: tuple[int, int, int] = (16, 32, 64),
        head: str = "grid",
        crop_size: int = CROP_SIZE,
        n_outputs: int = len(CROP_LABELS),
    ) -> None:
        super().__init__()
        if head not in HEADS:
            raise ValueError(f"head must be one of {HEADS}, got {head!r}")
        a, b, c = widths
        self.head = head
        self.features = nn.Sequential(_block(3, a), nn.MaxPool2d(2), _block(a, b), nn.MaxPool2d(2), _block(b, c))
        if head == "grid":
            cells = (crop_size // 8) ** 2  # two 2x poolings in the features, one more here
            linear = nn.Linear(c * cells, n_outputs)
            self.fc = nn.Sequential(nn.MaxPool2d(2), nn.Flatten(), nn.Dropout(0.2), linear)
        else:
            self.fc = nn.Linear(c, n_outputs)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        x = self.features(x / 127.5 - 1.0)
        return self.fc(x) if self.head == "grid" else self.fc(x.mean(dim=(2, 3)))


def load_crop_net(path: str | Path, net: CropNet, calibration: np.ndarray) -> CropNet:
    """``net`` with the weights of the classifier ONNX it was exported to (fp32; same widths, head and crop size).

    The convolutions and their batch norms come back through
    :func:`~pix2pockets.vision.train.onnx_import.load_onnx_into` (norm statistics measured on ``calibration``, uint8
    crops (N, S, S, 3)), the linear head by its initializer names (``net.<module>.weight``, ``.bias``).

    Raises:
        ValueError: when the file does not fit the network.
    """
    from onnx import numpy_helper

    from pix2pockets.vision.train.onnx_file import load_onnx_model
    from pix2pockets.vision.train.onnx_import import load_onnx_into

    x = torch.from_numpy(np.ascontiguousarray(calibration)).permute(0, 3, 1, 2).float()
    load_onnx_into(net, path, x)
    tensors = {t.name: numpy_helper.to_array(t) for t in load_onnx_model(Path(path)).graph.initializer}
    with torch.no_grad():
        for name, layer in net.named_modules():
            if not isinstance(layer, nn.Linear):
                continue
            weight, bias = tensors.get(f"net.{name}.weight"), tensors.get(f"net.{name}.bias")
            if weight is None or bias is None or weight.shape != tuple(layer.weight.shape):
                raise ValueError(f"{path}: no linear layer {name} of shape {tuple(layer.weight.shape)}")
            layer.weight.copy_(torch.from_numpy(np.array(weight)))
            layer.bias.copy_(torch.from_numpy(np.array(bias)))
    return net


class _Exported(nn.Module):
    """What the ONNX file computes: uint8 crops (N, S, S, 3) -> class probabilities (N, 5)."""

    def __init__(self, net: CropNet) -> None:
        super().__init__()
        self.net = net

    def forward(self, crops: torch.Tensor) -> torch.Tensor:
        return torch.softmax(self.net(crops.permute(0, 3, 1, 2).float()), dim=1)


@dataclass(frozen=True, slots=True)
class CropTrainConfig(CropTrainSettings):
    """Settings of ``pix2pockets train-ball-classifier``.

    Attributes (besides the shared :class:`~pix2pockets.vision.train.crop_fit.CropTrainSettings`):
        negatives: ball-only datasets (e.g. real photos): "no ball" crops only, away from their balls.
        negatives_exclude: file-name globs left out of `negatives`.
        class_power: loss weight of a class is frequency ** -class_power (0: unweighted).
        head: ``"grid"`` or ``"mean"`` (see the module docstring).
        copies: jittered crops per labelled ball and image.
        centre_jitter: largest crop centre shift, in ball diameters.
        scale_jitter: crop diameter scale range.
        low_res: share of the training crops re-sampled through 7-20 px (far or blurred balls).
        crop_size: side of a crop [px], a multiple of 8 (inference reads it from the ONNX input).
        icon_negatives: flat ball icons (broadcast graphics, :mod:`~pix2pockets.vision.train.icon_crops`) added
            as "no ball" crops, per labelled-ball crop (0: none).
        hard_negatives: copies of each of the bundled detector's false balls on the training images (pockets, cue
            tips, chalk: :mod:`~pix2pockets.vision.train.hard_negatives`) added as "no ball" crops (0: none).
        init: an fp32 classifier ONNX to start from (:func:`load_crop_net`), or None for random weights; a fine-tune
            from the bundled classifier shares its start, so the two can be averaged
            (:func:`~pix2pockets.vision.train.weight_average.average_onnx_weights`).
    """

    command: ClassVar[str] = "train-ball-classifier"

    negatives: tuple[str, ...] = ()
    negatives_exclude: tuple[str, ...] = ()
    class_power: float = 0.5
    head: str = "grid"
    centre_jitter: float = CropConfig().centre_jitter
    scale_jitter: tuple[float, float] = CropConfig().scale_jitter
    low_res: float = CropConfig().low_res
    crop_size: int = CROP_SIZE
    icon_negatives: float = 0.0
    hard_negatives: int = 0
    init: str | None = None

    def check(self) -> None:
        if self.init is not None and not Path(self.init).is_file():
            raise ValueError(f"--init: no classifier file {self.init}")
        if not 0 <= self.class_power <= 1:
            raise ValueError(f"class_power must be in [0, 1], got {self.class_power}")
        if self.head not in HEADS:
            raise ValueError(f"head must be one of {HEADS}, got {self.head!r}")
        if self.crop_size < 16 or self.crop_size % 8:
            raise ValueError(f"crop_size must be a multiple of 8 and >= 16, got {self.crop_size}")
        if not 0 <= self.low_res <= 1:
            raise ValueError(f"low_res must be in [0, 1], got {self.low_res}")
        if not 0 <= self.icon_negatives <= 1:
            raise ValueError(f"icon_negatives must be in [0, 1], got {self.icon_negatives}")
        if self.hard_negatives < 0:
            raise ValueError(f"hard_negatives must be >= 0, got {self.hard_negatives}")
        if not 0 <= self.centre_jitter < 0.5 or not 0 < self.scale_jitter[0] <= self.scale_jitter[1]:
            raise ValueError(
                f"centre_jitter must be in [0, 0.5) and scale_jitter a range lo <= hi above 0, got "
                f"{self.centre_jitter} and {self.scale_jitter}"
            )


def plain_object_balls(item: LabelledImage, cmap: dict[int, int]) -> LabelledImage:
    """A blackball render's labels with its yellows named solid, like its reds.

    ``pix2pockets synth --blackball`` labels reds with the solid and yellows with the stripe class id (the detector
    learns the set's two groups so); but a yellow has no stripe, and the classifier tells stripes by their white
    band: taught so, it would call a plain yellow ball, such as an American 1, a stripe. The pipeline names a
    blackball set's balls red or yellow by their colour. Other images are returned as they are.
    """
    if ball_set_of(item.image_path) != "blackball":
        return item
    dataset_id = {ours: theirs for theirs, ours in cmap.items()}
    stripe, solid = dataset_id.get(STRIPE_ID), dataset_id.get(SOLID_ID)
    if stripe is None or solid is None:
        return item
    return replace(item, class_id=np.where(item.class_id == stripe, solid, item.class_id))


def _sources(cfg: CropTrainConfig, split: str) -> list:
    out = [(plain_object_balls(it, cmap), cmap) for it, cmap in labelled_sources(cfg.data, split)]
    if split == "train":
        out += [(it, None) for it in load_splits(cfg.negatives, "train", cfg.negatives_exclude)]
    return out


def augment(x: torch.Tensor, gen: torch.Generator) -> torch.Tensor:
    """Random flips, quarter turns, brightness, contrast, colour balance and noise on (N, 3, S, S) in 0-255."""
    if bool(torch.rand(1, generator=gen) < 0.5):
        x = x.flip(3)
    x = torch.rot90(x, int(torch.randint(0, 4, (1,), generator=gen)), dims=(2, 3))
    return photometric(x, gen)


def photometric(x: torch.Tensor, gen: torch.Generator) -> torch.Tensor:
    """Random brightness, contrast, colour balance and noise per crop on (N, 3, S, S) in 0-255."""
    n = x.shape[0]

    def u(lo: float, hi: float, *shape: int) -> torch.Tensor:
        return lo + (hi - lo) * torch.rand(n, *shape, generator=gen)

    mean = x.mean(dim=(1, 2, 3), keepdim=True)
    x = (x - mean) * u(0.7, 1.3, 1, 1, 1) + mean * u(0.6, 1.4, 1, 1, 1)
    x = x * u(0.9, 1.1, 3, 1, 1)
    x = x + torch.randn(x.shape, generator=gen) * u(0, 6, 1, 1, 1)
    return x.clamp(0, 255)


def _confusion(model: CropNet, crops: np.ndarray, labels: np.ndarray) -> np.ndarray:
    k = len(CROP_LABELS)
    conf = np.zeros((k, k), dtype=int)
    if len(crops):
        np.add.at(conf, (labels, predict_crops(model, crops).argmax(1)), 1)
    return conf


def export_crop_classifier(model: CropNet, path: Path, size: int) -> Path:
    """Write the classifier (uint8 NHWC crops in, softmax probabilities out) as ONNX with a dynamic batch."""
    example = torch.zeros(2, size, size, 3, dtype=torch.uint8)
    axes = {"crops": {0: "n"}, OUTPUT_NAME: {0: "n"}}
    return write_onnx(_Exported(model), example, path, "crops", OUTPUT_NAME, axes)


def train_crop_classifier(cfg: CropTrainConfig, progress: bool = True) -> Path:
    """Collect crops, train, report the held-out confusion matrix in ``metrics.json``, export; returns the ONNX."""

    torch.set_num_threads(cfg.threads)
    torch.manual_seed(cfg.seed)
    out = Path(cfg.out)
    out.mkdir(parents=True, exist_ok=True)
    train = _sources(cfg, "train")
    crop_cfg = CropConfig(
        copies=cfg.copies,
        centre_jitter=cfg.centre_jitter,
        scale_jitter=cfg.scale_jitter,
        low_res=cfg.low_res,
        crop_size=cfg.crop_size,
    )
    crops, labels = collect_crops(train, read_image_rgb, cfg.seed, crop_cfg, progress)
    if cfg.icon_negatives > 0:
        rng = np.random.default_rng((cfg.seed, 1))
        icons = ball_icon_crops(round(cfg.icon_negatives * int((labels < NO_BALL).sum())), rng, cfg.crop_size)
        crops = np.concatenate([crops, degrade_crops(icons, rng, cfg.low_res)])
        labels = np.concatenate([labels, np.full(len(icons), NO_BALL)])
    if cfg.hard_negatives > 0:
        from pix2pockets.pipeline.photo import default_detector
        from pix2pockets.vision.train.hard_negatives import hard_negative_crops

        rng = np.random.default_rng((cfg.seed, 2))
        hard = hard_negative_crops(labelled_sources(cfg.data, "train"), default_detector(), cfg.crop_size)
        hard = np.concatenate([degrade_crops(hard, rng, cfg.low_res) for _ in range(cfg.hard_negatives)])
        crops = np.concatenate([crops, hard])
        labels = np.concatenate([labels, np.full(len(hard), NO_BALL)])
    test = _sources(cfg, "test")
    test_cfg = CropConfig(copies=1, crop_size=cfg.crop_size)
    test_crops, test_labels = (
        collect_crops(test, read_image_rgb, cfg.seed + 1, test_cfg, progress) if test else (None, None)
    )
    counts = np.bincount(labels, minlength=len(CROP_LABELS)).astype(float)
    weight = np.where(counts > 0, np.maximum(counts, 1) ** -cfg.class_power, 0.0)
    weight = torch.tensor(weight / (weight * counts).sum() * counts.sum(), dtype=torch.float32)

    model = CropNet(cfg.widths, cfg.head, cfg.crop_size)
    if cfg.init:
        calibration = crops[np.random.default_rng((cfg.seed, 3)).permutation(len(crops))[:64]]
        load_crop_net(cfg.init, model, calibration)

    def batch_loss(net: nn.Module, x: torch.Tensor, y: torch.Tensor, gen: torch.Generator) -> torch.Tensor:
        return nn.functional.cross_entropy(net(augment(x, gen)), y, weight=weight)

    fit_crops(
        model,
        crops,
        torch.from_numpy(labels),
        batch_loss,
        epochs=cfg.epochs,
        batch=cfg.batch,
        lr=cfg.lr,
        seed=cfg.seed,
        desc="train ball classifier",
        progress=progress,
    )

    metrics = {"config": asdict(cfg), "train_counts": counts.astype(int).tolist(), "labels": list(CROP_LABELS)}
    if test_crops is not None and len(test_crops):
        conf = _confusion(model, test_crops, test_labels)
        metrics["test_confusion"] = conf.tolist()
        recall = np.round(np.diag(conf) / np.maximum(conf.sum(1), 1), 4)
        metrics["test_recall"] = dict(zip(CROP_LABELS, recall.tolist(), strict=True))
    (out / "metrics.json").write_text(json.dumps(metrics, indent=2) + "\n")
    torch.save({"model": model.state_dict(), "config": asdict(cfg)}, out / "last.pt")
    return export_crop_classifier(model, out / ONNX_NAME, cfg.crop_size)

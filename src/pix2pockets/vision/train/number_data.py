"""Training crops for the ball-number reader: every labelled ball of a render, with its number (0-15).

The renderer's sidecar ``meta/<image>.json`` holds each ball's number next to its box (``synth.labels``); the
YOLO labels hold only the class. Crops are cut as for the ball classifier (:mod:`.crop_data`): centred on the
box with a small shift and scale jitter, some re-sampled through a lower resolution.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.stages.crops import ball_diameters, crop_balls
from pix2pockets.vision.train.crop_data import CropConfig, collect_from_images, degrade_crops


def meta_path(image_path: Path) -> Path:
    """The renderer's sidecar of an image: ``split/images/x.jpg`` -> ``split/meta/x.json``."""
    image_path = Path(image_path)
    return image_path.parent.parent / "meta" / f"{image_path.stem}.json"


def numbered_balls(meta: dict, min_visible: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Boxes (n, 4) xyxy [px] and numbers (n,) of the labelled balls in a render's sidecar, those showing at
    least `min_visible` of their outline."""
    balls = [
        b for b in meta.get("balls", []) if b.get("labelled") and float(b.get("visible_fraction", 1.0)) >= min_visible
    ]
    boxes = np.array([b["box_px"] for b in balls], dtype=float).reshape(-1, 4)
    numbers = np.array([int(b["number"]) for b in balls], dtype=int)
    return boxes, numbers


def number_crops(
    image: np.ndarray, boxes: np.ndarray, numbers: np.ndarray, rng: np.random.Generator, cfg: CropConfig
) -> tuple[np.ndarray, np.ndarray]:
    """Jittered crops (m, S, S, 3) uint8 of the balls in `boxes` and their numbers (m,), ``cfg.copies`` each."""
    if len(boxes) == 0:
        return np.empty((0, cfg.crop_size, cfg.crop_size, 3), np.uint8), np.empty(0, int)
    centres = 0.5 * (boxes[:, :2] + boxes[:, 2:])
    diameters = ball_diameters(boxes)
    crops, labels = [], []
    for _ in range(cfg.copies):
        shift = rng.uniform(-cfg.centre_jitter, cfg.centre_jitter, size=centres.shape) * diameters[:, None]
        scale = rng.uniform(*cfg.scale_jitter, size=len(diameters))
        crops.append(crop_balls(image, centres + shift, diameters * scale, cfg.crop_size))
        labels.append(numbers)
    return degrade_crops(np.concatenate(crops), rng, cfg.low_res), np.concatenate(labels)


def collect_number_crops(
    items: Sequence[LabelledImage],
    read_rgb,
    seed: int,
    cfg: CropConfig | None = None,
    min_visible: float = 0.0,
    progress: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Crops and numbers from renders with sidecars; image `j` draws from ``np.random.default_rng((seed, j))``.

    Raises:
        ValueError: if an image has no sidecar (not a ``pix2pockets synth`` render) or there are no images.
    """

    cfg = cfg or CropConfig()

    def per_image(image, item, _cmap, rng):
        path = meta_path(item.image_path)
        if not path.is_file():
            raise ValueError(f"{item.image_path} has no renderer sidecar {path}: ball numbers need synth renders")
        meta = json.loads(path.read_text())
        if "balls" not in meta:
            raise ValueError(f"{path} is not a 'pix2pockets synth' sidecar (it lists no balls with numbers)")
        boxes, numbers = numbered_balls(meta, min_visible)
        return number_crops(image, boxes, numbers, rng, cfg)

    crops, numbers = collect_from_images([(it, None) for it in items], read_rgb, seed, per_image, "crops", progress)
    return crops, numbers.astype(int)

"""Training crops for the ball classifier: labelled balls, plus "no ball" crops (numpy and OpenCV only).

Each labelled ball gives jittered crops (centre shift, scale, lower resolution). "No ball" crops come from
three places: diamonds (small bright marks a detector confuses with far balls), points just off a ball (a
second peak on a large ball), and random points on the rest of the image, ball-sized.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from pix2pockets.vision.classes import BALL_IDS, DIAMOND_ID
from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.stages.crops import CROP_SIZE, ball_diameters, crop_balls

NO_BALL = len(BALL_IDS)
"""Classifier label of "no ball" (after the four ball classes)."""
CROP_LABELS: tuple[str, ...] = ("cue", "black", "solid", "stripe", "none")


@dataclass(frozen=True, slots=True)
class CropConfig:
    """How crops are drawn from one labelled image.

    Attributes:
        copies: jittered crops per labelled ball.
        centre_jitter: largest centre shift, in ball diameters.
        scale_jitter: diameter scale range.
        low_res: probability that a crop is re-sampled through a lower resolution (far or blurred balls).
        random_negatives: random "no ball" crops per labelled ball.
        off_centre_negatives: crops centred 0.75-1.1 diameters from a ball, per labelled ball.
        diamond_negatives: most diamond crops per image.
        crop_size: side of a crop [px].
    """

    copies: int = 1
    centre_jitter: float = 0.06
    scale_jitter: tuple[float, float] = (0.92, 1.09)
    low_res: float = 0.4
    random_negatives: float = 0.6
    off_centre_negatives: float = 0.25
    diamond_negatives: int = 6
    crop_size: int = CROP_SIZE


def degrade_crops(crops: np.ndarray, rng: np.random.Generator, p: float) -> np.ndarray:
    """Re-sample a fraction `p` of the crops through 7-20 px, as a far or out-of-focus ball looks."""
    out = crops.copy()
    for i in np.flatnonzero(rng.random(len(crops)) < p):
        r = int(rng.integers(7, 21))
        small = cv2.resize(crops[i], (r, r), interpolation=cv2.INTER_AREA)
        out[i] = cv2.resize(small, (crops.shape[2], crops.shape[1]), interpolation=cv2.INTER_LINEAR)
    return out


def _far_from(points: np.ndarray, centres: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """Mask of `points` (m, 2) farther than `radius` (n,) from every centre (n, 2)."""
    if len(centres) == 0:
        return np.ones(len(points), dtype=bool)
    d = np.linalg.norm(points[:, None, :] - centres[None, :, :], axis=2)
    return np.all(d > radius[None, :], axis=1)


def image_crops(
    image: np.ndarray,
    item: LabelledImage,
    class_map: dict[int, int] | None,
    rng: np.random.Generator,
    cfg: CropConfig = CropConfig(),
) -> tuple[np.ndarray, np.ndarray]:
    """Crops (m, S, S, 3) uint8 and labels (m,) from one labelled image.

    Args:
        image: the RGB image of `item`.
        item: its labels.
        class_map: dataset class id -> detector class id; None for a ball-only set, whose balls have unknown
            classes (they give no positive crops, and "no ball" crops keep clear of them).
        rng: randomness for jitter and negative placement.
        cfg: how many crops of each kind.
    """
    cls = np.array([class_map.get(int(c), -1) for c in item.class_id] if class_map else [-2] * len(item.class_id))
    boxes = item.boxes.reshape(-1, 4)
    centres = 0.5 * (boxes[:, :2] + boxes[:, 2:])
    is_ball = np.isin(cls, BALL_IDS) | (cls == -2)
    known = np.isin(cls, BALL_IDS)
    ball_c, ball_d = centres[is_ball], ball_diameters(boxes[is_ball])
    typical_d = float(np.median(ball_d)) if len(ball_d) else 12.0
    crops, labels = [], []

    if known.any():
        kc, kd, kl = centres[known], ball_diameters(boxes[known]), cls[known]
        for _ in range(cfg.copies):
            shift = rng.uniform(-cfg.centre_jitter, cfg.centre_jitter, size=kc.shape) * kd[:, None]
            scale = rng.uniform(*cfg.scale_jitter, size=len(kd))
            crops.append(crop_balls(image, kc + shift, kd * scale, cfg.crop_size))
            labels.append(kl)

    negatives = []
    diamonds = centres[cls == DIAMOND_ID]
    if len(diamonds) > cfg.diamond_negatives:
        diamonds = diamonds[rng.choice(len(diamonds), cfg.diamond_negatives, replace=False)]
    if len(diamonds):
        d = typical_d * rng.uniform(0.7, 1.3, size=len(diamonds))
        negatives.append((diamonds + rng.normal(0, 0.05, diamonds.shape) * d[:, None], d))
    n_off = rng.binomial(len(ball_c), cfg.off_centre_negatives) if len(ball_c) else 0
    if n_off:
        pick = rng.integers(0, len(ball_c), n_off)
        angle = rng.uniform(0, 2 * np.pi, n_off)
        dist = rng.uniform(0.75, 1.1, n_off) * ball_d[pick]
        pts = ball_c[pick] + dist[:, None] * np.stack([np.cos(angle), np.sin(angle)], axis=1)
        negatives.append((pts, ball_d[pick] * rng.uniform(0.85, 1.15, n_off)))
    n_rand = round(max(1, len(ball_c)) * cfg.random_negatives)
    w, h = item.size
    pts = rng.uniform([0, 0], [w, h], size=(n_rand, 2))
    negatives.append((pts, typical_d * rng.uniform(0.6, 1.5, n_rand)))
    for pts, d in negatives:
        keep = _far_from(pts, ball_c, 0.6 * ball_d)
        if keep.any():
            crops.append(crop_balls(image, pts[keep], d[keep], cfg.crop_size))
            labels.append(np.full(int(keep.sum()), NO_BALL))
    if not crops:
        return np.empty((0, cfg.crop_size, cfg.crop_size, 3), np.uint8), np.empty(0, int)
    return degrade_crops(np.concatenate(crops), rng, cfg.low_res), np.concatenate(labels).astype(int)


PerImageCrops = Callable[[np.ndarray, LabelledImage, dict[int, int] | None, np.random.Generator], tuple]
"""(image RGB, its labels, class map, randomness) -> (crops (m, S, S, 3) uint8, targets (m, ...))."""


def collect_from_images(
    sources: Sequence[tuple[LabelledImage, dict[int, int] | None]],
    read_rgb,
    seed: int,
    per_image: PerImageCrops,
    desc: str,
    progress: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Crops and targets of `per_image` over many images, concatenated; image `j` draws from
    ``np.random.default_rng((seed, j))``.

    Raises:
        ValueError: if there are no images.
    """
    from tqdm import tqdm

    crops, targets = [], []
    for j, (item, cmap) in enumerate(tqdm(sources, desc=desc, disable=not progress)):
        c, t = per_image(read_rgb(item.image_path), item, cmap, np.random.default_rng((seed, j)))
        crops.append(c)
        targets.append(t)
    if not crops:
        raise ValueError("no images to take crops from")
    return np.concatenate(crops), np.concatenate(targets)


def collect_box_crops(
    sources: Sequence[tuple[LabelledImage, dict[int, int] | None]],
    read_rgb,
    seed: int,
    per_image: PerImageCrops,
    what: str,
    progress: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Crops and float32 box targets of a refiner's `per_image` over many images (:func:`collect_from_images`).

    Raises:
        ValueError: if no image has a labelled `what` ("balls (classes cue, black, solid, stripe)").
    """
    crops, targets = collect_from_images(sources, read_rgb, seed, per_image, f"{what.split()[0]} crops", progress)
    if not len(targets):
        raise ValueError(f"no labelled {what} in these datasets")
    return crops, targets.astype(np.float32)


def collect_crops(
    sources: Sequence[tuple[LabelledImage, dict[int, int] | None]],
    read_rgb,
    seed: int,
    cfg: CropConfig = CropConfig(),
    progress: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Crops and labels from many images; image `j` draws from ``np.random.default_rng((seed, j))``."""

    def per_image(image, item, cmap, rng):
        return image_crops(image, item, cmap, rng, cfg)

    crops, labels = collect_from_images(sources, read_rgb, seed, per_image, "crops", progress)
    return crops, labels.astype(int)

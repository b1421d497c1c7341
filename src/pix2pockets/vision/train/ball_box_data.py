"""Training crops for the ball box refiner: labelled balls seen off-centre and at the wrong size, as the detector
places its boxes (numpy and OpenCV only).

Each labelled ball gives crops cut around a box whose centre is shifted and whose size is scaled as the
detector's would be; the target is where the labelled box really lies in the crop.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from pix2pockets.vision.classes import BALL_IDS
from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.stages.ball_refiner import BALL_REFINE_CROP_SIZE, box_targets, crop_for_refiner
from pix2pockets.vision.train.crop_data import collect_box_crops, degrade_crops


@dataclass(frozen=True, slots=True)
class BallBoxCropConfig:
    """How refiner crops are drawn from one labelled image.

    Attributes:
        copies: jittered crops per labelled ball.
        centre_jitter: standard deviation of the centre shift per axis, in ball diameters (the detector's is
            about 0.07 on the test renders, with tails to 0.3), clipped at three times that.
        size_jitter: range of the size scale per box side (log-uniform; the detector's 1st-99th percentiles
            are 0.6-1.55).
        low_res: probability that a crop is re-sampled through a lower resolution.
        stretch: probability that a crop is cut with a window of another aspect (log-uniform in
            ``stretch_range``), so the ball in it is squashed as in a photo stretched by an export whose stretch
            was not recognised; the target box is squashed with it, so the refiner learns to box what it sees.
        stretch_range: range of those window aspects (width over height).
    """

    copies: int = 3
    centre_jitter: float = 0.1
    size_jitter: tuple[float, float] = (0.65, 1.5)
    low_res: float = 0.3
    stretch: float = 0.3
    stretch_range: tuple[float, float] = (0.5, 2.0)


def jittered_boxes(boxes: np.ndarray, rng: np.random.Generator, cfg: BallBoxCropConfig) -> np.ndarray:
    """Boxes (n, 4) [px] around labelled ball boxes (n, 4) with the centre shifted and each side scaled."""
    centre = 0.5 * (boxes[:, :2] + boxes[:, 2:])
    size = boxes[:, 2:] - boxes[:, :2]
    diameter = size.mean(axis=1, keepdims=True)
    limit = 3 * cfg.centre_jitter
    shift = np.clip(rng.normal(0.0, cfg.centre_jitter, size=centre.shape), -limit, limit)
    lo, hi = np.log(cfg.size_jitter)
    size = size * np.exp(rng.uniform(lo, hi, size=size.shape))
    centre = centre + shift * diameter
    return np.hstack([centre - 0.5 * size, centre + 0.5 * size])


def image_ball_box_crops(
    image: np.ndarray, item: LabelledImage, class_map: dict[int, int], rng: np.random.Generator, cfg: BallBoxCropConfig
) -> tuple[np.ndarray, np.ndarray]:
    """Crops (m, S, S, 3) uint8 and box targets (m, 4) from one labelled image (none without balls).

    Args:
        image: the RGB image of `item`.
        item: its labels.
        class_map: dataset class id -> detector class id (every ball class counts).
        rng: randomness for shifts, scales and re-sampling.
        cfg: copies and jitter.
    """
    cls = np.array([class_map.get(int(c), -1) for c in item.class_id], dtype=int)
    balls = item.boxes.reshape(-1, 4)[np.isin(cls, BALL_IDS)]
    if len(balls) == 0 or cfg.copies == 0:
        size = BALL_REFINE_CROP_SIZE
        return np.empty((0, size, size, 3), np.uint8), np.empty((0, 4))
    crops, targets = [], []
    lo, hi = np.log(cfg.stretch_range)
    for _ in range(cfg.copies):
        boxes = jittered_boxes(balls, rng, cfg)
        stretched = rng.random(len(balls)) < cfg.stretch
        aspects = np.where(stretched, np.exp(rng.uniform(lo, hi, len(balls))), 1.0)
        for aspect in np.unique(aspects):
            pick = aspects == aspect
            c, windows = crop_for_refiner(image, boxes[pick], float(aspect))
            crops.append(c)
            targets.append(box_targets(balls[pick], windows))
    return degrade_crops(np.concatenate(crops), rng, cfg.low_res), np.concatenate(targets)


def collect_ball_box_crops(
    sources: Sequence[tuple[LabelledImage, dict[int, int]]],
    read_rgb,
    seed: int,
    cfg: BallBoxCropConfig = BallBoxCropConfig(),
    progress: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Crops and targets (float32) from many images; image `j` draws from ``np.random.default_rng((seed, j))``.

    Raises:
        ValueError: if no image has a labelled ball.
    """

    def per_image(image, item, cmap, rng):
        return image_ball_box_crops(image, item, cmap, rng, cfg)

    return collect_box_crops(sources, read_rgb, seed, per_image, "balls (classes cue, black, solid, stripe)", progress)

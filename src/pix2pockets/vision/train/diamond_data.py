"""Training crops for the diamond refiner: labelled diamonds seen off-centre, as the detector places its crops
(numpy and OpenCV only).

Each labelled diamond gives crops whose centre is shifted and whose side is scaled as the detector's box would
be; the target is where the diamond's labelled box really lies in the crop.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from pix2pockets.vision.classes import DIAMOND_ID
from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.stages.diamond_refiner import DIAMOND_CROP_SIZE, box_targets, crop_diamonds, diamond_crop_sides
from pix2pockets.vision.train.crop_data import collect_box_crops, degrade_crops


@dataclass(frozen=True, slots=True)
class DiamondCropConfig:
    """How refiner crops are drawn from one labelled image.

    Attributes:
        copies: shifted crops per labelled diamond.
        centre_jitter: largest centre shift per axis, in diamond box sides (the detector's error is mostly
            below half a side, a 4 px box being typical).
        side_jitter: crop side scale range (the detector's box size is off by up to a third).
        long_side_read: range of the share of a slanted diamond's long side (beyond its short side) that the
            detector's box is taken to read when the crop side is drawn: the detector reads a 10 px wide sight
            about 7 px wide (0.5 of the excess). Sizing training crops from the label's own box instead lets the
            refiner read a box's size off the crop's scale, and under-read slanted sights where the detector's
            box is short (``docs/benchmarks-detector.md``).
        low_res: probability that a crop is re-sampled through a lower resolution.
    """

    copies: int = 1
    centre_jitter: float = 0.6
    side_jitter: tuple[float, float] = (0.85, 1.3)
    long_side_read: tuple[float, float] = (0.1, 1.1)
    low_res: float = 0.3


def image_diamond_crops(
    image: np.ndarray, item: LabelledImage, class_map: dict[int, int], rng: np.random.Generator, cfg: DiamondCropConfig
) -> tuple[np.ndarray, np.ndarray]:
    """Crops (m, S, S, 3) uint8 and box targets (m, 4) from one labelled image (none without diamonds).

    Args:
        image: the RGB image of `item`.
        item: its labels.
        class_map: dataset class id -> detector class id.
        rng: randomness for shifts, scales and re-sampling.
        cfg: copies and jitter.
    """
    cls = np.array([class_map.get(int(c), -1) for c in item.class_id], dtype=int)
    diamonds = item.boxes.reshape(-1, 4)[cls == DIAMOND_ID]
    if len(diamonds) == 0 or cfg.copies == 0:
        return np.empty((0, DIAMOND_CROP_SIZE, DIAMOND_CROP_SIZE, 3), np.uint8), np.empty((0, 4))
    centres = 0.5 * (diamonds[:, :2] + diamonds[:, 2:])
    box_side = 0.5 * ((diamonds[:, 2] - diamonds[:, 0]) + (diamonds[:, 3] - diamonds[:, 1]))
    crops, targets = [], []
    for _ in range(cfg.copies):
        shift = rng.uniform(-cfg.centre_jitter, cfg.centre_jitter, size=centres.shape) * box_side[:, None]
        sides = diamond_crop_sides(detector_like_boxes(diamonds, rng, cfg.long_side_read))
        sides = sides * rng.uniform(*cfg.side_jitter, size=len(diamonds))
        c, corners, windows = crop_diamonds(image, centres + shift, sides)
        crops.append(c)
        targets.append(box_targets(diamonds, corners, windows))
    return degrade_crops(np.concatenate(crops), rng, cfg.low_res), np.concatenate(targets)


def detector_like_boxes(boxes: np.ndarray, rng: np.random.Generator, long_side_read: tuple[float, float]) -> np.ndarray:
    """Labelled diamond boxes xyxy (n, 4) [px] with each box's excess of long over short side scaled by a share
    drawn from `long_side_read`, about the same centre: the boxes the detector would draw around them."""
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    size = boxes[:, 2:] - boxes[:, :2]
    short = size.min(axis=1, keepdims=True)
    share = rng.uniform(*long_side_read, size=(len(boxes), 1))
    half = 0.5 * (short + (size - short) * share)
    centre = 0.5 * (boxes[:, :2] + boxes[:, 2:])
    return np.hstack([centre - half, centre + half])


def collect_diamond_crops(
    sources: Sequence[tuple[LabelledImage, dict[int, int]]],
    read_rgb,
    seed: int,
    cfg: DiamondCropConfig = DiamondCropConfig(),
    progress: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Crops and targets (float32) from many images; image `j` draws from ``np.random.default_rng((seed, j))``.

    Raises:
        ValueError: if no image has a labelled diamond.
    """

    def per_image(image, item, cmap, rng):
        return image_diamond_crops(image, item, cmap, rng, cfg)

    return collect_box_crops(sources, read_rgb, seed, per_image, "diamonds (class 'dot')", progress)

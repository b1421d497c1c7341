"""Training samples for the heatmap detector: augmentation (numpy/OpenCV) and dense targets.

Each sample is a random scaled crop of a letterboxed image with colour jitter and horizontal flips; targets
are Gaussian centre heatmaps at stride 4 plus size, offset and contact-point regressions at object centres.
Randomness comes only from the ``np.random.Generator`` passed in, so a (seed, epoch, index) triple fixes a
sample.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from pix2pockets.vision.classes import BALL_IDS
from pix2pockets.vision.detect.heads import BALL_ANY, N_CLASSES, N_HEAT, STRIDE
from pix2pockets.vision.detect.letterbox import PAD_VALUE
from pix2pockets.vision.metrics.table_box import TABLE_MARGIN, inside_table_boxes
from pix2pockets.vision.metrics.yolo_data import LabelledImage

MAX_OBJECTS = 96


@dataclass(frozen=True, slots=True)
class AugmentConfig:
    """Augmentation settings.

    Attributes:
        crop: square crop side fed to the network [px] (a multiple of 32, at least 64).
        base_long_side: the image is first scaled so its long side is this [px] (the inference size).
        scale_range: extra random zoom range applied after that.
        flip: allow horizontal flips.
        colour: strength of brightness/contrast/hue-ish jitter (0 = off).
        stretch_range: pixel aspect ratios (x scale over y scale) drawn log-uniformly for stretched samples:
            photos exported at another aspect ratio, as a 16:9 frame squashed to 640x640 (0.5625) by a
            Roboflow export, or a portrait photo (1.78).
        stretch_fraction: share of rendered samples that are stretched (0 = none; no random draw is spent
            then, so older settings augment exactly as before). Ball-only photos are not: the real ones are
            such exports already (a stretched first run lost 7 points of real-photo ball AP50).
    """

    crop: int = 320
    base_long_side: int = 640
    scale_range: tuple[float, float] = (0.7, 1.4)
    flip: bool = True
    colour: float = 0.25
    stretch_range: tuple[float, float] = (0.5, 2.0)
    stretch_fraction: float = 0.0

    def __post_init__(self) -> None:
        if self.crop % 32 or self.crop < 64:
            raise ValueError(f"crop must be a multiple of 32 and >= 64, got {self.crop}")
        lo, hi = self.stretch_range
        if not 0 < lo <= hi:
            raise ValueError(f"stretch range must be 0 < lo <= hi, got {self.stretch_range}")
        if not 0 <= self.stretch_fraction <= 1:
            raise ValueError(f"stretch fraction must be in [0, 1], got {self.stretch_fraction}")


@dataclass(frozen=True, slots=True)
class Sample:
    """One network input and its targets (numpy; converted to tensors by the training loop).

    ``kind_mask`` (N_HEAT,) says which heatmap channels are supervised: ball-only photos leave the five
    class channels unsupervised (their diamonds and colours are unlabelled). ``off_table`` marks the cells of
    a ball-only photo outside its labelled table box, where the diamond channel is still taught "no diamond":
    walls, lamps and clothes are where a detector trained on renders alone invents diamonds.
    """

    image: np.ndarray  # (3, S, S) float32 in [0, 1]
    heat: np.ndarray  # (N_HEAT, S/4, S/4) float32
    kind_mask: np.ndarray  # (N_HEAT,) float32
    index: np.ndarray  # (MAX_OBJECTS,) int64 flat cell index
    reg_mask: np.ndarray  # (MAX_OBJECTS,) float32
    size: np.ndarray  # (MAX_OBJECTS, 2) log(w/4), log(h/4)
    offset: np.ndarray  # (MAX_OBJECTS, 2)
    contact: np.ndarray  # (MAX_OBJECTS, 2)
    contact_mask: np.ndarray  # (MAX_OBJECTS,)
    ball_class: np.ndarray  # (MAX_OBJECTS,) int64 ball class 0-3, -1 where unknown (diamonds, ball-only photos)
    off_table: np.ndarray  # (S/4, S/4) float32, 1 outside the table box of a ball-only photo


def off_table_mask(table_boxes: np.ndarray, out: int, margin: float = TABLE_MARGIN) -> np.ndarray:
    """(out, out) mask: 1 for heatmap cells whose centre is outside every widened table box (boxes in crop px)."""
    centres = (np.arange(out) + 0.5) * STRIDE
    xs, ys = np.meshgrid(centres, centres)
    inside = inside_table_boxes(np.stack([xs.ravel(), ys.ravel()], axis=1), table_boxes, margin)
    return (~inside).reshape(out, out).astype(np.float32)


def draw_gaussian(heat: np.ndarray, cx: int, cy: int, sigma: float) -> None:
    """Max-blend a Gaussian peak of height 1 centred on cell (cx, cy) into a 2-D heatmap, in place."""
    r = max(1, int(np.ceil(3 * sigma)))
    h, w = heat.shape
    x0, x1, y0, y1 = max(0, cx - r), min(w, cx + r + 1), max(0, cy - r), min(h, cy + r + 1)
    if x0 >= x1 or y0 >= y1:
        return
    ys, xs = np.mgrid[y0:y1, x0:x1]
    g = np.exp(-((xs - cx) ** 2 + (ys - cy) ** 2) / (2 * sigma**2))
    np.maximum(heat[y0:y1, x0:x1], g, out=heat[y0:y1, x0:x1])


def _colour_jitter(img: np.ndarray, rng: np.random.Generator, strength: float) -> np.ndarray:
    """Brightness, contrast, per-channel gain, blur and noise on a float image in [0, 1]."""
    if strength <= 0:
        return img
    gain = 1 + rng.uniform(-strength, strength, 3) * 0.5
    img = img * gain * (1 + rng.uniform(-strength, strength))
    mean = img.mean()
    img = (img - mean) * (1 + rng.uniform(-strength, strength)) + mean
    if rng.random() < 0.25:
        k = int(rng.choice([3, 5]))
        img = cv2.GaussianBlur(img, (k, k), 0)
    if rng.random() < 0.3:
        img = img + rng.normal(0, rng.uniform(0.005, 0.03), img.shape)
    return np.clip(img, 0, 1).astype(np.float32)


def make_sample(
    image_rgb: np.ndarray,
    item: LabelledImage,
    class_map: dict[int, int],
    ball_only: bool,
    cfg: AugmentConfig,
    rng: np.random.Generator,
    table_class: int | None = None,
) -> Sample:
    """Augment one labelled image and build its targets.

    Args:
        image_rgb: the decoded image (H, W, 3) uint8.
        item: its labels.
        class_map: dataset class id -> detector class id (0-4), or for ``ball_only`` sets -> anything (ids
            missing from the map are ignored, e.g. a "table" class).
        ball_only: labels are class-agnostic balls: only the "any ball" channel is supervised.
        cfg: augmentation settings.
        rng: the sample's random generator.
        table_class: for ``ball_only`` sets, the dataset class id of a box around the whole table; images
            that have one teach the diamond channel "no diamond" outside it.
    """
    h, w = image_rgb.shape[:2]
    s = cfg.crop
    scale = cfg.base_long_side / max(h, w) * rng.uniform(*cfg.scale_range)
    sx = sy = scale
    if cfg.stretch_fraction > 0 and not ball_only and rng.random() < cfg.stretch_fraction:
        aspect = math.exp(rng.uniform(*np.log(cfg.stretch_range)))
        sx, sy = scale * math.sqrt(aspect), scale / math.sqrt(aspect)
    sw, sh = w * sx, h * sy
    # Crop origin in scaled-image pixels; crops may extend past the image (padded).
    ox = rng.uniform(min(0.0, sw - s), max(0.0, sw - s))
    oy = rng.uniform(min(0.0, sh - s), max(0.0, sh - s))
    flip = cfg.flip and rng.random() < 0.5
    # Continuous pixel coordinates (corner convention): x' = ax * x + bx (a flip mirrors inside the crop),
    # y' = sy * y - oy. OpenCV maps pixel indices (centres), hence the half-pixel terms in M.
    ax = -sx if flip else sx
    bx = s + ox if flip else -ox
    M = np.array([[ax, 0, bx + 0.5 * ax - 0.5], [0, sy, -oy + 0.5 * sy - 0.5]], dtype=np.float64)
    interp = cv2.INTER_AREA if min(sx, sy) < 1 else cv2.INTER_LINEAR
    crop = cv2.warpAffine(
        image_rgb, M, (s, s), flags=interp, borderMode=cv2.BORDER_CONSTANT, borderValue=(PAD_VALUE,) * 3
    )
    img = _colour_jitter(crop.astype(np.float32) / 255.0, rng, cfg.colour)

    out = s // STRIDE
    heat = np.zeros((N_HEAT, out, out), np.float32)
    kind_mask = np.ones(N_HEAT, np.float32)
    if ball_only:
        kind_mask[:N_CLASSES] = 0
    index = np.zeros(MAX_OBJECTS, np.int64)
    reg_mask = np.zeros(MAX_OBJECTS, np.float32)
    size = np.zeros((MAX_OBJECTS, 2), np.float32)
    offset = np.zeros((MAX_OBJECTS, 2), np.float32)
    contact = np.zeros((MAX_OBJECTS, 2), np.float32)
    contact_mask = np.zeros(MAX_OBJECTS, np.float32)
    ball_class = np.full(MAX_OBJECTS, -1, np.int64)

    boxes = item.boxes.copy()
    if len(boxes):
        x1 = boxes[:, 0] * ax + bx
        x2 = boxes[:, 2] * ax + bx
        boxes = np.stack([np.minimum(x1, x2), boxes[:, 1] * sy - oy, np.maximum(x1, x2), boxes[:, 3] * sy - oy], 1)
    cont = np.stack([item.contact[:, 0] * ax + bx, item.contact[:, 1] * sy - oy], 1) if len(boxes) else boxes[:, :2]
    off_table = np.zeros((out, out), np.float32)
    if ball_only and table_class is not None and len(boxes):
        tables = boxes[item.class_id == table_class]
        if len(tables):
            off_table = off_table_mask(tables, out)
    n = 0
    order = np.argsort(-(boxes[:, 2] - boxes[:, 0]) * (boxes[:, 3] - boxes[:, 1])) if len(boxes) else []
    for i in order:
        k = int(item.class_id[i])
        if k not in class_map:
            continue
        det_k = class_map[k]
        bw, bh = boxes[i, 2] - boxes[i, 0], boxes[i, 3] - boxes[i, 1]
        c = np.array([(boxes[i, 0] + boxes[i, 2]) / 2, (boxes[i, 1] + boxes[i, 3]) / 2]) / STRIDE
        ci = np.floor(c).astype(int)
        if not (0 <= ci[0] < out and 0 <= ci[1] < out) or bw < 1 or bh < 1:
            continue
        sigma = max(0.5, 0.12 * np.sqrt(bw * bh) / STRIDE)
        is_ball = ball_only or det_k in BALL_IDS
        if not ball_only:
            draw_gaussian(heat[det_k], ci[0], ci[1], sigma)
        if is_ball:
            draw_gaussian(heat[BALL_ANY], ci[0], ci[1], sigma)
        if n < MAX_OBJECTS:
            index[n] = ci[1] * out + ci[0]
            reg_mask[n] = 1
            size[n] = np.log([bw / STRIDE, bh / STRIDE])
            offset[n] = c - ci
            if is_ball and np.all(np.isfinite(cont[i])):
                contact[n] = cont[i] / STRIDE - ci
                contact_mask[n] = 1
            if not ball_only and det_k in BALL_IDS:
                ball_class[n] = det_k
            n += 1
    return Sample(
        img.transpose(2, 0, 1).copy(),
        heat,
        kind_mask,
        index,
        reg_mask,
        size,
        offset,
        contact,
        contact_mask,
        ball_class,
        off_table,
    )

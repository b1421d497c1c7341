"""Training samples for the table model: a render, its playing surface as a mask, its corners and side pockets.

The targets come from the render's camera and table size (``meta/*.json`` of a ``pix2pockets synth`` dataset), so
they are exact and amodal: the surface under the balls and behind a player is still surface, and a corner cut
off by the frame edge is still a corner. At stride 4 of the network input:

- channel 0: share of the cell inside the playing surface (the cloth within the cushion noses), in [0, 1];
- channel 1: Gaussian peaks at the four playing-surface corners (cushion-nose corners on the cloth);
- channel 2: Gaussian peaks at the two side-pocket mouths (they mark the long rails).

Augmentation (numpy / OpenCV only): random zoom and crop (partly cut-off tables), small rotation, mirror, hue
rotation (any cloth colour), brightness, contrast, saturation, blur, noise and JPEG, then the letterbox.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from pix2pockets.geometry.table import TableSpec
from pix2pockets.vision.detect.letterbox import PAD_VALUE
from pix2pockets.vision.table.keypoints import (
    CORNER_CHANNEL,
    N_TABLE_CHANNELS,
    SIDE_CHANNEL,
    STRIDE,
    SURFACE_CHANNEL,
    cell_of_pixel,
)

SIDE_POCKETS = (1, 4)
"""Indices of the side pockets in ``TableSpec.pockets`` order."""
EDGE_SAMPLES = 64
"""Points per playing-surface edge drawn into the mask (edges bend nowhere; the samples clip the part behind the
camera)."""
MIN_DEPTH_M = 0.05
"""Surface points closer to the camera plane than this [m] are left out of the mask outline."""


@dataclass(frozen=True, slots=True)
class TableAugment:
    """Augmentation settings (shares are probabilities per sample)."""

    input_size: int = 384
    zoom: tuple[float, float] = (1.0, 2.2)
    zoom_share: float = 0.4
    rotate_deg: float = 12.0
    hue_share: float = 0.7
    blur_share: float = 0.3
    noise_share: float = 0.3
    jpeg_share: float = 0.4
    grey_share: float = 0.05
    stretch_share: float = 0.2
    stretch: tuple[float, float] = (0.7, 1.4)


@dataclass(frozen=True, slots=True)
class TableTruth:
    """What a render shows of its table [px]: the surface outline (clipped to points in front of the camera),
    the four corners and the two side-pocket mouths (NaN where behind the camera)."""

    outline: np.ndarray
    corners: np.ndarray
    sides: np.ndarray


def truth_of_meta(meta: dict) -> TableTruth:
    """The table's outline, corners and side pockets in the image of a ``pix2pockets synth`` label dict."""
    cam = meta["camera"]
    K, R, t = (np.asarray(cam[k], dtype=float) for k in ("K", "R", "t"))
    spec = TableSpec(length=float(meta["table"]["length_m"]), width=float(meta["table"]["width_m"]))

    def project(xy: np.ndarray) -> np.ndarray:
        world = np.column_stack([xy, np.zeros(len(xy))])
        c = world @ R.T + t
        uv = c @ K.T
        with np.errstate(divide="ignore", invalid="ignore"):
            px = uv[:, :2] / uv[:, 2:3]
        return np.where(c[:, 2:3] > MIN_DEPTH_M, px, np.nan)

    corners = spec.corners
    s = np.linspace(0.0, 1.0, EDGE_SAMPLES, endpoint=False)[:, None]
    edges = np.concatenate([corners[i] + s * (corners[(i + 1) % 4] - corners[i]) for i in range(4)])
    outline = project(edges)
    outline = outline[np.all(np.isfinite(outline), axis=1)]
    return TableTruth(outline, project(corners), project(spec.pocket_aims[list(SIDE_POCKETS)]))


def _gaussian(target: np.ndarray, cell: np.ndarray, sigma: float) -> None:
    """Max-draw a Gaussian of ``sigma`` cells with an exact 1 at the nearest cell of ``cell`` (x, y)."""
    h, w = target.shape
    cx, cy = np.round(cell).astype(int)
    r = int(3 * sigma) + 1
    if not (-r <= cx < w + r and -r <= cy < h + r):
        return
    ys, xs = np.mgrid[max(cy - r, 0) : min(cy + r + 1, h), max(cx - r, 0) : min(cx + r + 1, w)]
    if ys.size == 0:
        return
    g = np.exp(-((xs - cx) ** 2 + (ys - cy) ** 2) / (2 * sigma * sigma))
    target[ys, xs] = np.maximum(target[ys, xs], g)


def table_targets(truth: TableTruth, size: tuple[int, int], sigma: float = 1.5) -> np.ndarray:
    """Targets (N_TABLE_CHANNELS, h/4, w/4) float32 for a network input of ``size`` (width, height) [px] whose
    pixels the truth is given in."""
    w, h = size
    out = np.zeros((N_TABLE_CHANNELS, h // STRIDE, w // STRIDE), dtype=np.float32)
    if len(truth.outline) >= 3:
        fine = np.zeros((h, w), dtype=np.uint8)
        hull = cv2.convexHull(np.round(truth.outline * 4).astype(np.int32))
        cv2.fillPoly(fine, [hull], 1, shift=2)
        out[SURFACE_CHANNEL] = cv2.resize(fine.astype(np.float32), (w // STRIDE, h // STRIDE), cv2.INTER_AREA)
    for channel, points in ((CORNER_CHANNEL, truth.corners), (SIDE_CHANNEL, truth.sides)):
        for p in points:
            if np.all(np.isfinite(p)):
                _gaussian(out[channel], cell_of_pixel(p), sigma)
    return out


def _affine(truth: TableTruth, M: np.ndarray) -> TableTruth:
    def move(p: np.ndarray) -> np.ndarray:
        return p @ M[:, :2].T + M[:, 2] if len(p) else p

    return TableTruth(move(truth.outline), move(truth.corners), move(truth.sides))


def augment_sample(
    image: np.ndarray, truth: TableTruth, cfg: TableAugment, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """An augmented, letterboxed input (3, S, S) float32 in [0, 1] and its targets (C, S/4, S/4)."""
    h, w = image.shape[:2]
    S = cfg.input_size
    scale = S / max(h, w)
    zoom = rng.uniform(*cfg.zoom) if rng.random() < cfg.zoom_share else 1.0
    angle = rng.uniform(-cfg.rotate_deg, cfg.rotate_deg)
    M = cv2.getRotationMatrix2D((w / 2, h / 2), angle, scale * zoom)  # about the image centre
    M[:, 2] += np.array([S / 2 - w / 2, S / 2 - h / 2])  # the image centre to the input centre
    if zoom > 1:  # a random window of the zoomed image
        M[:, 2] += rng.uniform(-0.5, 0.5, 2) * (zoom - 1) * np.array([w, h]) * scale
    if rng.random() < cfg.stretch_share:  # non-square pixels, as in photos squashed by an export
        k = rng.uniform(*cfg.stretch)
        M = np.array([[k, 0.0, (1 - k) * S / 2], [0.0, 1.0, 0.0]]) @ np.vstack([M, [0.0, 0.0, 1.0]])
    if rng.random() < 0.5:  # mirror: corners and side pockets are symmetric classes
        M = np.array([[-1.0, 0.0, S], [0.0, 1.0, 0.0]]) @ np.vstack([M, [0.0, 0.0, 1.0]])
    out = cv2.warpAffine(image, M, (S, S), flags=cv2.INTER_LINEAR, borderValue=(PAD_VALUE,) * 3)
    out = _photometric(out, cfg, rng)
    return out.astype(np.float32).transpose(2, 0, 1) / 255.0, table_targets(_affine(truth, M), (S, S))


def _photometric(img: np.ndarray, cfg: TableAugment, rng: np.random.Generator) -> np.ndarray:
    """Colour, blur, noise and compression changes of a uint8 RGB image."""
    hsv = cv2.cvtColor(img, cv2.COLOR_RGB2HSV).astype(np.float32)
    if rng.random() < cfg.hue_share:
        hsv[..., 0] = (hsv[..., 0] + rng.uniform(0, 180)) % 180
    hsv[..., 1] *= rng.uniform(0.5, 1.4)
    hsv[..., 2] = hsv[..., 2] * rng.uniform(0.6, 1.4) + rng.uniform(-20, 20)
    img = cv2.cvtColor(np.clip(hsv, 0, [179, 255, 255]).astype(np.uint8), cv2.COLOR_HSV2RGB)
    if rng.random() < cfg.grey_share:
        img = np.repeat(cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)[..., None], 3, axis=2)
    if rng.random() < cfg.blur_share:
        img = cv2.GaussianBlur(img, (0, 0), rng.uniform(0.5, 2.0))
    if rng.random() < cfg.noise_share:
        img = np.clip(img + rng.normal(0, rng.uniform(2, 10), img.shape), 0, 255).astype(np.uint8)
    if rng.random() < cfg.jpeg_share:
        ok, buf = cv2.imencode(".jpg", img, [cv2.IMWRITE_JPEG_QUALITY, int(rng.integers(30, 90))])
        if ok:
            img = cv2.imdecode(buf, cv2.IMREAD_UNCHANGED)
    return img


def render_items(roots: list[str | Path], split: str) -> list[tuple[Path, Path]]:
    """(image, label JSON) pairs of the ``split`` of ``pix2pockets synth`` datasets, sorted.

    Raises:
        ValueError: when a dataset has no such split or no label files.
    """
    items = []
    for root in roots:
        folder = Path(root) / split
        images = sorted((folder / "images").glob("*.jpg")) + sorted((folder / "images").glob("*.png"))
        pairs = [(p, folder / "meta" / f"{p.stem}.json") for p in images]
        pairs = [(p, m) for p, m in pairs if m.is_file()]
        if not pairs:
            raise ValueError(f"{folder}: no images with meta/*.json labels (a 'pix2pockets synth' dataset)")
        items += pairs
    return items


def load_item(image_path: Path, meta_path: Path) -> tuple[np.ndarray, TableTruth]:
    """An RGB render and its table truth."""
    bgr = cv2.imread(str(image_path), cv2.IMREAD_COLOR)
    if bgr is None:
        raise ValueError(f"cannot read {image_path}")
    return cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB), truth_of_meta(json.loads(meta_path.read_text()))

"""Turn the heatmap detector's dense outputs into :class:`Detections` (numpy only)."""

from __future__ import annotations

import numpy as np

from pix2pockets.vision.classes import BALL_IDS, DIAMOND_ID, MIN_DIAMOND_BOX_PX
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.heads import (
    BALL_ANY,
    BALL_NMS_IOU,
    CONTACT_SLICE,
    N_CLASSES,
    N_OUT,
    OFFSET_SLICE,
    SIZE_SLICE,
    STRIDE,
)
from pix2pockets.vision.detect.letterbox import Letterbox
from pix2pockets.vision.detect.postprocess import paired_box_iou


def decode_peaks(
    out: np.ndarray,
    box: Letterbox,
    conf_threshold: float = 0.05,
    max_detections: int = 300,
    channels: tuple[int, ...] = tuple(range(N_CLASSES)),
    agnostic: bool = False,
    image_size: tuple[int, int] | None = None,
) -> Detections:
    """Detections from one image's output (N_OUT, h, w) whose heatmaps hold only local peaks.

    Args:
        out: the model output for one image, non-peak cells already zeroed by the exported graph. Ball cells
            are the "any ball" candidates; those of one ball are merged here (:func:`merged_ball_cells`).
        box: the letterbox used for the input, to map back to image pixels.
        conf_threshold: lowest peak score kept.
        max_detections: keep at most this many, the highest scores.
        channels: heatmap channels to read.
        agnostic: read the class-agnostic ball channel instead; all results get class id 0 ("any ball").
        image_size: (width, height) of the original image, to clip boxes [px].

    Returns:
        Raw detections (not post-processed), boxes and contact points in original image pixels.
    """
    _check(out)
    chans = (BALL_ANY,) if agnostic else tuple(channels)
    heat = out[list(chans)]  # a copy
    balls = [i for i, c in enumerate(chans) if c in BALL_IDS or agnostic]
    if balls:
        heat[balls] = np.where(merged_ball_cells(out, conf_threshold), 0.0, heat[balls])
    ci, ys, xs, scores = _select(heat, conf_threshold, max_detections)
    cls = np.zeros(len(ci), dtype=int) if agnostic else np.asarray(chans, dtype=int)[ci]
    is_ball = np.isin(cls, BALL_IDS) | agnostic
    return _assemble(out, box, ys, xs, scores, cls, is_ball, image_size)


def decode_ball_peaks(
    out: np.ndarray,
    box: Letterbox,
    conf_threshold: float = 0.05,
    max_detections: int = 300,
    image_size: tuple[int, int] | None = None,
) -> tuple[Detections, np.ndarray]:
    """Peaks of the "any ball" heatmap (class ids 0) and the four ball-class heatmap scores (n, 4) at each.

    Arguments as in :func:`decode_peaks`.
    """
    _check(out)
    heat = np.where(merged_ball_cells(out, conf_threshold), 0.0, out[BALL_ANY])
    _, ys, xs, scores = _select(heat[None], conf_threshold, max_detections)
    det = _assemble(out, box, ys, xs, scores, np.zeros(len(ys), dtype=int), np.ones(len(ys), bool), image_size)
    return det, out[list(BALL_IDS)][:, ys, xs].T


def merged_ball_cells(out: np.ndarray, conf_threshold: float = 0.05) -> np.ndarray:
    """(h, w) mask of the "any ball" candidate cells that belong to a neighbouring, higher-scoring candidate.

    The exported graph keeps every cell within :data:`~pix2pockets.vision.detect.heads.BALL_PEAK_RATIO` of
    its 3x3 maximum, so that touching balls in neighbouring cells both survive. A candidate is merged into one
    of its 8 neighbours when that one scores higher and their boxes overlap by IoU >=
    :data:`~pix2pockets.vision.detect.heads.BALL_NMS_IOU` (one ball seen from two cells); touching balls, whose
    boxes barely overlap, stay apart. With a strict-peak model the mask is empty. Only the candidate cells (some
    tens of a photo's tens of thousands) are read.
    """
    h, w = out.shape[1:]
    merged = np.zeros((h, w), dtype=bool)
    ys, xs = np.nonzero(out[BALL_ANY] >= conf_threshold)
    score = out[BALL_ANY, ys, xs]
    ys, xs, score = ys[score > 0], xs[score > 0], score[score > 0]
    if len(ys) < 2:
        return merged
    index = np.full((h + 2, w + 2), -1)  # candidate number of each cell, -1 elsewhere and on the border
    index[ys + 1, xs + 1] = np.arange(len(ys))
    size = np.exp(np.clip(out[SIZE_SLICE][:, ys, xs], -4.0, 6.0))
    centre = np.stack([xs, ys]) + out[OFFSET_SLICE][:, ys, xs]
    boxes = np.concatenate([centre - size / 2, centre + size / 2]).T  # (n, 4) in cells
    for dy, dx in ((dy, dx) for dy in (-1, 0, 1) for dx in (-1, 0, 1) if dy or dx):
        other = index[ys + 1 + dy, xs + 1 + dx]  # the neighbour in direction (dy, dx)
        cand = np.flatnonzero(other >= 0)
        other = other[cand]
        higher = score[other] > score[cand]
        cand, other = cand[higher], other[higher]
        same_ball = paired_box_iou(boxes[cand], boxes[other]) >= BALL_NMS_IOU
        merged[ys[cand[same_ball]], xs[cand[same_ball]]] = True
    return merged


def _check(out: np.ndarray) -> None:
    if out.ndim != 3 or out.shape[0] != N_OUT:
        raise ValueError(f"expected model output ({N_OUT}, h, w), got {out.shape}")


def _select(heat: np.ndarray, conf_threshold: float, max_detections: int) -> tuple[np.ndarray, ...]:
    """Channel, row, column and score of the heatmap cells >= the threshold, at most the top `max_detections`."""
    ci, ys, xs = np.nonzero(heat >= conf_threshold)
    scores = heat[ci, ys, xs]
    if len(scores) > max_detections:
        top = np.argsort(-scores, kind="stable")[:max_detections]
        ci, ys, xs, scores = ci[top], ys[top], xs[top], scores[top]
    return ci, ys, xs, scores


def _assemble(
    out: np.ndarray,
    box: Letterbox,
    ys: np.ndarray,
    xs: np.ndarray,
    scores: np.ndarray,
    cls: np.ndarray,
    is_ball: np.ndarray,
    image_size: tuple[int, int] | None,
) -> Detections:
    """Boxes and contact points of the chosen cells, mapped back to original image pixels."""
    off = out[OFFSET_SLICE, ys, xs].T
    size = np.exp(np.clip(out[SIZE_SLICE, ys, xs].T, -4.0, 6.0)) * STRIDE
    centre = (np.stack([xs, ys], axis=1) + off) * STRIDE
    boxes = np.hstack([centre - size / 2, centre + size / 2])
    contact = (np.stack([xs, ys], axis=1) + out[CONTACT_SLICE, ys, xs].T) * STRIDE
    boxes, contact = box.to_image(boxes), box.to_image(contact)
    diamonds = cls == DIAMOND_ID
    if np.any(diamonds):
        boxes[diamonds] = _diamond_boxes(box.to_image(centre[diamonds]), size[diamonds], box.scale)
    if image_size is not None:
        w, h = image_size
        boxes = np.clip(boxes, 0, [w, h, w, h])
    contact = np.where(is_ball[:, None], contact, np.nan)
    return Detections(boxes, scores, cls, contact)


DIAMOND_SHORT_READ_MAX_PX = 1.0
"""The most a diamond box is read short of the sight's size in the image [image px] (:func:`_diamond_boxes`)."""

DIAMOND_FULL_SCALE_FROM_PX = MIN_DIAMOND_BOX_PX + 1.0
"""Predicted diamond size [network px] from which a box is read at most :data:`DIAMOND_SHORT_READ_MAX_PX` short."""

DIAMOND_FLOOR_SHARE = 0.375
"""How far up the sizes it may stand for a floor-sized diamond prediction is read, beyond the first
:data:`DIAMOND_SHORT_READ_MAX_PX` (chosen on 1080p validation renders among 0.25, 0.375, 0.5, 0.75)."""


def _diamond_boxes(centre: np.ndarray, size_net: np.ndarray, scale: float) -> np.ndarray:
    """Diamond boxes (n, 4) in image pixels from centres [image px] and predicted sizes [network px].

    The training labels pad a sight's outline to :data:`MIN_DIAMOND_BOX_PX` in the pixels the network sees, so a
    predicted size at that floor means "a sight this small or smaller": at an input scale below 1 anything from
    the floor to ``MIN_DIAMOND_BOX_PX / scale`` image px. The floor maps to the same floor in image pixels and
    only the part above it scales with the image, which reads a larger sight ``MIN_DIAMOND_BOX_PX x (1 / scale -
    1)`` px short: 1 px in a 720p frame (input scale 0.8), which the diamond refiner was trained on and re-reads
    well, but 3.5 px in a 1080p frame (0.53), from which it does not recover. Beyond
    :data:`DIAMOND_SHORT_READ_MAX_PX` that shortfall is made up: in full from :data:`DIAMOND_FULL_SCALE_FROM_PX` up,
    by :data:`DIAMOND_FLOOR_SHARE` at the floor, linearly between. Frames of 720p or smaller are unchanged.
    On 1080p validation renders this lifts diamond AP50 from 82.9 to 93.3 (``docs/benchmarks-detector.md``).
    """
    size = MIN_DIAMOND_BOX_PX + np.maximum(size_net - MIN_DIAMOND_BOX_PX, 0.0) / scale
    shortfall = max(MIN_DIAMOND_BOX_PX * (1.0 / scale - 1.0) - DIAMOND_SHORT_READ_MAX_PX, 0.0)
    full = np.clip((size_net - MIN_DIAMOND_BOX_PX) / (DIAMOND_FULL_SCALE_FROM_PX - MIN_DIAMOND_BOX_PX), 0.0, 1.0)
    size = size + (full + (1.0 - full) * DIAMOND_FLOOR_SHARE) * shortfall
    return np.hstack([centre - size / 2, centre + size / 2])

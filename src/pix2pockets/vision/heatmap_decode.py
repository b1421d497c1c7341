"""Turn the heatmap detector's dense outputs into :class:`Detections` (numpy only)."""

from __future__ import annotations

import numpy as np

from pix2pockets.vision.classes import BALL_IDS
from pix2pockets.vision.detections import Detections
from pix2pockets.vision.heatmap_layout import (
    BALL_ANY,
    CONTACT_SLICE,
    N_CLASSES,
    N_OUT,
    OFFSET_SLICE,
    SIZE_SLICE,
    STRIDE,
)
from pix2pockets.vision.letterbox import Letterbox


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
        out: the model output for one image (peaks already isolated by the exported 3x3 max-pool).
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
    ci, ys, xs, scores = _select(out[list(chans)], conf_threshold, max_detections)
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
    _, ys, xs, scores = _select(out[[BALL_ANY]], conf_threshold, max_detections)
    det = _assemble(out, box, ys, xs, scores, np.zeros(len(ys), dtype=int), np.ones(len(ys), bool), image_size)
    return det, out[list(BALL_IDS)][:, ys, xs].T


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
    if image_size is not None:
        w, h = image_size
        boxes = np.clip(boxes, 0, [w, h, w, h])
    contact = np.where(is_ball[:, None], contact, np.nan)
    return Detections(boxes, scores, cls, contact)

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
    if out.ndim != 3 or out.shape[0] != N_OUT:
        raise ValueError(f"expected model output ({N_OUT}, h, w), got {out.shape}")
    chans = (BALL_ANY,) if agnostic else tuple(channels)
    heat = out[list(chans)]
    ci, ys, xs = np.nonzero(heat >= conf_threshold)
    scores = heat[ci, ys, xs]
    if len(scores) > max_detections:
        top = np.argsort(-scores, kind="stable")[:max_detections]
        ci, ys, xs, scores = ci[top], ys[top], xs[top], scores[top]
    cls = np.zeros(len(ci), dtype=int) if agnostic else np.asarray(chans, dtype=int)[ci]
    off = out[OFFSET_SLICE, ys, xs].T
    size = np.exp(np.clip(out[SIZE_SLICE, ys, xs].T, -4.0, 6.0)) * STRIDE
    centre = (np.stack([xs, ys], axis=1) + off) * STRIDE
    boxes = np.hstack([centre - size / 2, centre + size / 2])
    contact = (np.stack([xs, ys], axis=1) + out[CONTACT_SLICE, ys, xs].T) * STRIDE
    boxes, contact = box.to_image(boxes), box.to_image(contact)
    if image_size is not None:
        w, h = image_size
        boxes = np.clip(boxes, 0, [w, h, w, h])
    is_ball = np.isin(cls, BALL_IDS) | agnostic
    contact = np.where(is_ball[:, None], contact, np.nan)
    return Detections(boxes, scores, cls, contact)

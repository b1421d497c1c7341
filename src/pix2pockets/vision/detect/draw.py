"""Draw detections on an image (for looking at results; OpenCV)."""

from __future__ import annotations

import cv2
import numpy as np

from pix2pockets.vision.detect.detections import Detections

SHORT_NAMES = ("cue", "blk", "sol", "str", "dot")
CLASS_COLOURS = {0: (255, 255, 255), 1: (40, 40, 40), 2: (255, 60, 40), 3: (60, 120, 255), 4: (255, 230, 0)}


def draw_detections(
    image_rgb: np.ndarray, det: Detections, min_confidence: float = 0.25, numbers: np.ndarray | None = None
) -> np.ndarray:
    """A copy of the image with boxes (class colour), short labels and contact points (magenta diamonds).

    ``numbers`` (n,): each detection's ball number, negative where unknown; shown after the class (``sol 3``).
    """
    out = np.ascontiguousarray(image_rgb.copy())
    numbers = np.full(len(det), -1) if numbers is None else np.asarray(numbers, dtype=int).reshape(len(det))
    for box, conf, k, p, number in zip(det.boxes, det.confidence, det.class_id, det.contact, numbers, strict=True):
        if conf < min_confidence:
            continue
        x1, y1, x2, y2 = (round(float(v)) for v in box)
        colour = CLASS_COLOURS.get(int(k), (0, 255, 0))
        cv2.rectangle(out, (x1, y1), (x2, y2), (0, 0, 0), 3)
        cv2.rectangle(out, (x1, y1), (x2, y2), colour, 1)
        label = f"{SHORT_NAMES[int(k)]}{f' {number}' if number >= 0 else ''} {conf:.2f}"
        cv2.putText(out, label, (x1, max(8, y1 - 2)), cv2.FONT_HERSHEY_SIMPLEX, 0.3, colour, 1, cv2.LINE_AA)
        if np.all(np.isfinite(p)):
            cv2.circle(out, (round(float(p[0])), round(float(p[1]))), 2, (255, 0, 255), -1)
    return out

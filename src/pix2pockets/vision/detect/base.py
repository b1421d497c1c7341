"""The detector slot: image in, :class:`Detections` out."""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from pix2pockets.vision.detect.detections import Detections


@runtime_checkable
class Detector(Protocol):
    """Finds balls and diamonds in an RGB image (H, W, 3) uint8; returns raw (not post-processed) detections."""

    def detect(self, image_rgb: np.ndarray) -> Detections: ...

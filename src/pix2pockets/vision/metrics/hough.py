"""Hough-circle baseline with the paper's parameters (section 6.1, "Hough Circles"), for comparison only.

Adaptive threshold, then OpenCV's ``HOUGH_GRADIENT_ALT`` with dp=1, minDist=10, param1=300, param2=0.7,
maxRadius=30; minRadius 15 for balls and 0 for diamonds; then NMS with the radius as the score. It cannot tell
ball classes apart: every ball is reported as class ``solid`` and scores are ``radius / maxRadius``; judge it
with class-agnostic metrics.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from pix2pockets.vision.classes import CLASS_NAMES, DIAMOND_ID
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.postprocess import nms_indices

BALL_LABEL = CLASS_NAMES.index("solid")


@dataclass(frozen=True, slots=True)
class HoughParams:
    """The paper's Hough parameters (radii in pixels of the input image)."""

    dp: float = 1.0
    min_dist: float = 10.0
    param1: float = 300.0
    param2: float = 0.7
    max_radius: int = 30
    min_radius_ball: int = 15
    min_radius_diamond: int = 0
    block_size: int = 11
    nms_iou: float = 0.5


class HoughDetector:
    """A :class:`~pix2pockets.vision.detect.base.Detector` made of the paper's Hough-circle recipe.

    Args:
        params: Hough settings.
        diamonds: also search small circles and report them as diamonds.
    """

    def __init__(self, params: HoughParams | None = None, diamonds: bool = True) -> None:
        self.params = params or HoughParams()
        self.diamonds = diamonds

    def _circles(self, binary: np.ndarray, min_radius: int) -> np.ndarray:
        p = self.params
        found = cv2.HoughCircles(
            binary,
            cv2.HOUGH_GRADIENT_ALT,
            dp=p.dp,
            minDist=p.min_dist,
            param1=p.param1,
            param2=p.param2,
            minRadius=min_radius,
            maxRadius=p.max_radius,
        )
        return np.zeros((0, 3)) if found is None else found.reshape(-1, 3)

    def detect(self, image_rgb: np.ndarray) -> Detections:
        """Circles as detections: balls (class solid) and, if enabled, diamonds."""
        if image_rgb.ndim != 3 or image_rgb.shape[2] != 3:
            raise ValueError(f"expected an (H, W, 3) image, got {image_rgb.shape}")
        gray = cv2.cvtColor(image_rgb, cv2.COLOR_RGB2GRAY)
        binary = cv2.adaptiveThreshold(
            gray, 255, cv2.ADAPTIVE_THRESH_GAUSSIAN_C, cv2.THRESH_BINARY, self.params.block_size, 2
        )
        parts = [(self._circles(binary, self.params.min_radius_ball), BALL_LABEL)]
        if self.diamonds:
            small = self._circles(binary, self.params.min_radius_diamond)
            parts.append((small[small[:, 2] < self.params.min_radius_ball], DIAMOND_ID))
        circles = np.vstack([c for c, _ in parts])
        labels = np.concatenate([np.full(len(c), k) for c, k in parts]).astype(int)
        if not len(circles):
            return Detections.empty()
        x, y, r = circles.T
        boxes = np.stack([x - r, y - r, x + r, y + r], axis=1)
        score = np.clip(r / self.params.max_radius, 0, 1)
        keep = nms_indices(boxes, score, self.params.nms_iou)
        return Detections(boxes[keep], score[keep], labels[keep])

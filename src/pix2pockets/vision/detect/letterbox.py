"""Resize-and-pad pre-processing shared by detector training and inference (numpy + OpenCV)."""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

PAD_VALUE = 114


@dataclass(frozen=True, slots=True)
class Letterbox:
    """How an image was resized and padded: ``network_px = image_px * scale`` (padding right and bottom).

    Attributes:
        scale: resize factor network / image.
        size: (width, height) of the padded network input [px].
    """

    scale: float
    size: tuple[int, int]

    def to_image(self, xy: np.ndarray) -> np.ndarray:
        """Network pixel coordinates -> original image pixel coordinates."""
        return np.asarray(xy, dtype=float) / self.scale


def letterbox(image_rgb: np.ndarray, long_side: int = 640, multiple: int = 32) -> tuple[np.ndarray, Letterbox]:
    """Scale an image so its long side is ``long_side`` and pad right/bottom to a multiple of ``multiple``.

    Args:
        image_rgb: (H, W, 3) uint8.
        long_side: target long side [px].
        multiple: the padded width and height are multiples of this.

    Returns:
        The padded (h, w, 3) uint8 image and the :class:`Letterbox` mapping.

    Raises:
        ValueError: for an image that is not (H, W, 3) or a non-positive size.
    """
    if image_rgb.ndim != 3 or image_rgb.shape[2] != 3 or min(image_rgb.shape[:2]) < 1:
        raise ValueError(f"expected an (H, W, 3) image, got shape {image_rgb.shape}")
    if long_side < multiple or multiple < 1:
        raise ValueError(f"long_side ({long_side}) must be >= multiple ({multiple}) >= 1")
    h, w = image_rgb.shape[:2]
    scale = long_side / max(h, w)
    nw, nh = max(1, round(w * scale)), max(1, round(h * scale))
    interp = cv2.INTER_AREA if scale < 1 else cv2.INTER_LINEAR
    resized = cv2.resize(image_rgb, (nw, nh), interpolation=interp) if (nw, nh) != (w, h) else image_rgb
    pw, ph = -(-nw // multiple) * multiple, -(-nh // multiple) * multiple
    out = np.full((ph, pw, 3), PAD_VALUE, dtype=np.uint8)
    out[:nh, :nw] = resized
    return out, Letterbox(scale=scale, size=(pw, ph))


def network_input(image_rgb: np.ndarray, long_side: int = 640, multiple: int = 32) -> tuple[np.ndarray, Letterbox]:
    """The detector's input tensor for an RGB uint8 image: letterboxed, float32 in [0, 1], (1, 3, h, w).

    The one pre-processing shared by inference and int8 calibration, so both see the same numbers.
    """
    padded, box = letterbox(image_rgb, long_side, multiple)
    return (padded.astype(np.float32) / 255.0).transpose(2, 0, 1)[None], box

"""Reading photos safely: clear errors for non-images, truncated files and huge images."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

MAX_PIXELS = 64_000_000
"""Largest image accepted [pixels] (a 8000 x 8000 photo); bigger files are refused before decoding."""


def read_image_rgb(path: str | Path, max_pixels: int = MAX_PIXELS) -> np.ndarray:
    """Decode an image file to RGB uint8 (H, W, 3).

    Raises:
        ValueError: if the file is missing, not an image, truncated, or larger than ``max_pixels``.
    """
    from PIL import Image, UnidentifiedImageError

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"image not found: {path}")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            with Image.open(path) as im:
                w, h = im.size
                if w * h > max_pixels:
                    raise ValueError(f"image {path} is too large ({w}x{h} > {max_pixels} pixels)")
                im.load()
                rgb = im.convert("RGB")
    except UnidentifiedImageError as err:
        raise ValueError(f"not an image file: {path}") from err
    except (Image.DecompressionBombError, Image.DecompressionBombWarning) as err:
        raise ValueError(f"image {path} is too large: {err}") from err
    except OSError as err:
        raise ValueError(f"cannot read image {path} (truncated or corrupt): {err}") from err
    return np.asarray(rgb, dtype=np.uint8)

"""Reading photos safely: clear errors for non-images, truncated files and huge images; EXIF orientation applied."""

from __future__ import annotations

import io
import warnings
from pathlib import Path
from typing import BinaryIO

import numpy as np

MAX_PIXELS = 64_000_000
"""Largest image accepted [pixels] (a 8000 x 8000 photo); bigger files are refused before decoding."""


def read_image_rgb(path: str | Path, max_pixels: int = MAX_PIXELS) -> np.ndarray:
    """Decode an image file to RGB uint8 (H, W, 3).

    Raises:
        ValueError: if the file is missing, not an image, truncated, or larger than ``max_pixels``.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"image not found: {path}")
    return _decode(path, str(path), max_pixels)


def decode_image_rgb(data: bytes, name: str = "upload", max_pixels: int = MAX_PIXELS) -> np.ndarray:
    """Decode image file contents (e.g. an upload) to RGB uint8 (H, W, 3), with the checks of
    :func:`read_image_rgb`; ``name`` is used in the error messages.

    Raises:
        ValueError: if the data is empty, not an image, truncated, or larger than ``max_pixels``.
    """
    if not data:
        raise ValueError(f"{name} is empty (not an image)")
    return _decode(io.BytesIO(data), name, max_pixels)


def _decode(source: Path | BinaryIO, name: str, max_pixels: int) -> np.ndarray:
    from PIL import Image, ImageOps, UnidentifiedImageError

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            with Image.open(source) as im:
                w, h = im.size
                if w * h > max_pixels:
                    raise ValueError(f"image {name} is too large ({w}x{h} > {max_pixels} pixels)")
                im.load()
                # phones store portrait photos sideways plus an EXIF orientation tag: show what the user saw
                rgb = ImageOps.exif_transpose(im).convert("RGB")
    except UnidentifiedImageError as err:
        raise ValueError(f"not an image file: {name}") from err
    except (Image.DecompressionBombError, Image.DecompressionBombWarning) as err:
        raise ValueError(f"image {name} is too large: {err}") from err
    except OSError as err:
        raise ValueError(f"cannot read image {name} (truncated or corrupt): {err}") from err
    return np.asarray(rgb, dtype=np.uint8)

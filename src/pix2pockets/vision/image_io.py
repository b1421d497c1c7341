"""Reading photos safely: clear errors for non-images, truncated files and huge images; EXIF orientation applied;
JPEG, PNG, WebP, AVIF and the HEIC photos of phones (through ``pillow-heif``)."""

from __future__ import annotations

import functools
import io
import re
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


def probe_image(data: bytes, name: str = "upload", max_pixels: int = MAX_PIXELS) -> tuple[int, int]:
    """The (width, height) [px] of image file contents from its header alone, without decoding the pixels.

    A quick first check of an upload; :func:`decode_image_rgb` still finds truncated or corrupt files.

    Raises:
        ValueError: if the data is empty, not an image, or larger than ``max_pixels``.
    """
    if not data:
        raise ValueError(f"{name} is empty (not an image)")
    from PIL import UnidentifiedImageError

    try:
        with _open(io.BytesIO(data), name, max_pixels) as im:
            return im.size
    except UnidentifiedImageError as err:
        raise ValueError(f"not an image file: {name}") from err
    except OSError as err:
        raise ValueError(f"cannot read image {name} (truncated or corrupt): {err}") from err


def capped_size(width: float, height: float, max_side: int) -> tuple[int, int]:
    """(width, height) [px] rounded, shrunk alike where the longer side exceeds ``max_side`` (at least 1 px each)."""
    shrink = min(1.0, max_side / max(width, height))
    return max(1, round(width * shrink)), max(1, round(height * shrink))


def image_grid(images: list[np.ndarray], columns: int, tile: tuple[int, int] | None = None) -> np.ndarray:
    """The images side by side, ``columns`` to a row, each resized to ``tile`` (width, height) [px] when given
    (otherwise they must share one size); the last row is filled with black."""
    import cv2

    cells = [cv2.resize(im, tile, interpolation=cv2.INTER_AREA) if tile else im for im in images]
    if not cells:
        raise ValueError("image_grid needs at least one image")
    while len(cells) % columns:
        cells.append(np.zeros_like(cells[0]))
    return np.vstack([np.hstack(cells[i : i + columns]) for i in range(0, len(cells), columns)])


def _too_large(name: str, pixels: int | None, max_pixels: int, size: str = "") -> ValueError:
    if pixels is not None and pixels <= max_pixels:  # refused by Pillow's own, lower guard
        return ValueError(f"image {name} is too large for the image decoder ({size or pixels} pixels)")
    what = f"{size} = {pixels} pixels" if size else f"{pixels} pixels" if pixels else "too many pixels"
    return ValueError(f"image {name} is too large ({what}; the limit is {max_pixels} pixels)")


@functools.cache
def _register_heif() -> None:
    """Let Pillow open HEIC / HEIF files (the default photo format of iPhones), where ``pillow-heif`` is installed."""
    try:
        from pillow_heif import register_heif_opener
    except ImportError:  # a checkout without it reads every other format
        return
    register_heif_opener()


def _open(source: Path | BinaryIO, name: str, max_pixels: int):
    """``PIL.Image.open`` with the pixel limit checked from the header (the documented message either way)."""
    from PIL import Image

    _register_heif()

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            im = Image.open(source)
    except (Image.DecompressionBombError, Image.DecompressionBombWarning) as err:
        # Pillow refuses huge images itself ("Image size (N pixels) exceeds limit ..."): say it as we do
        found = re.search(r"\((\d+) pixels\)", str(err))
        raise _too_large(name, int(found.group(1)) if found else None, max_pixels) from None
    w, h = im.size
    if w * h > max_pixels:
        im.close()
        raise _too_large(name, w * h, max_pixels, f"{w}x{h}")
    return im


def _to_8_bit(im) -> np.ndarray:
    """RGB uint8 of a high-depth greyscale image (16-bit PNG ``I;16``, 32-bit ``I``, float ``F``).

    Pillow's ``convert("RGB")`` clips these to 0..255, which turns a 16-bit photo almost white.
    """
    values = np.asarray(im, dtype=np.float64)
    finite = values[np.isfinite(values)]
    lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    if im.mode == "I" and lo >= 0 and hi <= 255:  # 8-bit values stored wide
        scaled = values
    elif im.mode.startswith("I;16") or (im.mode == "I" and lo >= 0 and hi <= 65535):
        scaled = values / 257.0  # the full 16-bit range onto 0..255
    elif im.mode == "F" and lo >= 0 and hi <= 1:
        scaled = values * 255.0
    else:  # any other range: stretch what is there
        scaled = (values - lo) * (255.0 / max(hi - lo, 1e-12))
    grey = np.clip(np.round(np.nan_to_num(scaled)), 0, 255).astype(np.uint8)
    return np.repeat(grey[:, :, None], 3, axis=2)


def _decode(source: Path | BinaryIO, name: str, max_pixels: int) -> np.ndarray:
    from PIL import ImageOps, UnidentifiedImageError

    try:
        with _open(source, name, max_pixels) as im:
            im.load()
            # phones store portrait photos sideways plus an EXIF orientation tag: show what the user saw
            upright = ImageOps.exif_transpose(im)
            if upright.mode.startswith("I") or upright.mode == "F":
                return _to_8_bit(upright)
            rgb = upright.convert("RGB")
    except UnidentifiedImageError as err:
        raise ValueError(f"not an image file: {name}") from err
    except OSError as err:
        raise ValueError(f"cannot read image {name} (truncated or corrupt): {err}") from err
    return np.asarray(rgb, dtype=np.uint8)

"""The error a table fit raises, and the words and numbers its messages use."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

_PHOTO_PX_PER_PX: ContextVar[float] = ContextVar("photo_px_per_px", default=1.0)


class TableFitError(ValueError):
    """The table could not be found in the image; the message says why."""


def counted(n: int, noun: str) -> str:
    """``n`` and the noun in the number it needs: ``1 diamond``, ``3 diamonds``."""
    return f"{n} {noun}{'s' * (n != 1)}"


@contextmanager
def photo_pixels(photo_px_per_px: float) -> Iterator[None]:
    """Within this block, :func:`in_photo_px` reports lengths of the image being fitted in the user's photo's
    pixels: a large photo is fitted on a smaller copy, whose pixel is ``photo_px_per_px`` of the photo's."""
    token = _PHOTO_PX_PER_PX.set(float(photo_px_per_px))
    try:
        yield
    finally:
        _PHOTO_PX_PER_PX.reset(token)


def in_photo_px(length_px: float) -> str:
    """A length in the fitted image [px] as a message gives it: in the photo's own pixels, ``"12.3 px"``."""
    value = length_px * _PHOTO_PX_PER_PX.get()
    return f"{value:.1f} px" if abs(value) < 100 else f"{value:.0f} px"

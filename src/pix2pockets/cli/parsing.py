"""Small parsers for option values shared by several commands."""

from __future__ import annotations


def parse_number_pair(text: str, option: str, example: str) -> tuple[float, float]:
    """``(lo, hi)`` from ``"lo,hi"``; the range itself is checked where it is used.

    Raises:
        ValueError: naming ``option`` and showing ``example`` when ``text`` is not two numbers.
    """
    try:
        lo, hi = (float(v) for v in text.split(","))
    except ValueError as err:
        raise ValueError(f"{option} needs two comma-separated numbers like {example}, got {text!r}") from err
    return lo, hi

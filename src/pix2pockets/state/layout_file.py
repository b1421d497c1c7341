"""Layout files: JSON table states that can be loaded, saved and shared.

Format (version 1)::

    {
      "format": "pix2pockets-layout",
      "version": 1,
      "table": "9ft",                    # a preset name (optional, default "9ft")
      "balls": [
        {"class": "cue", "number": 0, "x": 0.635, "y": 0.635},
        {"class": "solid", "number": 3, "x": 1.9, "y": 0.4},
        {"class": "stripe", "x": 2.2, "y": 1.0}   # number optional
      ]
    }

``x`` and ``y`` are ball centres in the table frame [m] (origin at the head-bottom corner of the playing
surface, x toward the foot rail). ``class`` is one of cue, black, solid, stripe.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from pix2pockets.geometry.table import table_preset
from pix2pockets.state.ball import Ball, parse_ball_class
from pix2pockets.state.layout import TableLayout

FORMAT_NAME = "pix2pockets-layout"
FORMAT_VERSION = 1


def layout_to_dict(layout: TableLayout) -> dict[str, Any]:
    """A JSON-ready dict for ``layout``."""
    balls = []
    for ball, (x, y) in zip(layout.balls, layout.positions, strict=True):
        entry: dict[str, Any] = {"class": ball.ball_class.value}
        if ball.number is not None:
            entry["number"] = ball.number
        entry["x"] = round(float(x), 6)
        entry["y"] = round(float(y), 6)
        balls.append(entry)
    return {"format": FORMAT_NAME, "version": FORMAT_VERSION, "table": layout.spec.name, "balls": balls}


def layout_from_dict(data: Any) -> TableLayout:
    """Parse and validate a layout dict; raises ``ValueError`` naming what is wrong."""
    if not isinstance(data, dict):
        raise ValueError("a layout must be a JSON object with a 'balls' list")
    if data.get("format", FORMAT_NAME) != FORMAT_NAME:
        raise ValueError(f"not a layout file: format is {data.get('format')!r}, expected {FORMAT_NAME!r}")
    if data.get("version", FORMAT_VERSION) != FORMAT_VERSION:
        raise ValueError(f"unsupported layout version {data.get('version')!r}; this version reads {FORMAT_VERSION}")
    spec = table_preset(str(data.get("table", "9ft")))
    raw = data.get("balls")
    if not isinstance(raw, list):
        raise ValueError("a layout needs a 'balls' list")
    balls, positions = [], []
    for i, entry in enumerate(raw):
        if not isinstance(entry, dict):
            raise ValueError(f"balls[{i}] must be an object with class, x and y")
        try:
            cls = parse_ball_class(entry["class"])
            x, y = float(entry["x"]), float(entry["y"])
        except KeyError as missing:
            raise ValueError(f"balls[{i}] is missing {missing}") from None
        except (TypeError, ValueError) as err:
            raise ValueError(f"balls[{i}]: {err}") from None
        number = entry.get("number")
        if number is not None and (not isinstance(number, int) or isinstance(number, bool)):
            raise ValueError(f"balls[{i}].number must be an integer 0-15, got {number!r}")
        try:
            balls.append(Ball(cls, number))
        except ValueError as err:
            raise ValueError(f"balls[{i}]: {err}") from None
        positions.append((x, y))
    return TableLayout(tuple(balls), positions, spec)


def load_layout(path: str | os.PathLike[str]) -> TableLayout:
    """Read a layout file; ``ValueError`` with the file name if it is unreadable or invalid."""
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ValueError(f"layout file not found: {path}") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        raise ValueError(f"cannot read layout {path}: {err}") from None
    try:
        return layout_from_dict(data)
    except ValueError as err:
        raise ValueError(f"invalid layout {path}: {err}") from None


def save_layout(layout: TableLayout, path: str | os.PathLike[str], overwrite: bool = False) -> None:
    """Write ``layout`` as JSON; refuses to replace an existing file unless ``overwrite``."""
    path = Path(path)
    if path.exists() and not overwrite:
        raise ValueError(f"{path} exists; pass overwrite=True (or --force) to replace it")
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(layout_to_dict(layout), indent=2) + "\n", encoding="utf-8")
    os.replace(tmp, path)

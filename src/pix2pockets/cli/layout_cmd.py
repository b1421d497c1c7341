"""``pix2pockets layout``: check and show layout files."""

from __future__ import annotations

import argparse
from importlib import resources

import numpy as np

from pix2pockets.state import TableLayout, load_layout

EXAMPLE_LAYOUT = "layout_example.json"


def example_layout_path() -> str:
    """Path of the bundled example layout."""
    return str(resources.files("pix2pockets.data.examples").joinpath(EXAMPLE_LAYOUT))


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("layout", help="check or show a layout file (JSON table state)")
    parser.add_argument("action", choices=["check", "show"], help="check: validate; show: ASCII diagram")
    parser.add_argument("file", nargs="?", help="layout JSON (default: the bundled example)")
    parser.set_defaults(func=run)


def ascii_diagram(layout: TableLayout, columns: int = 60) -> str:
    """A top-down text picture of the layout, head rail on the left."""
    spec = layout.spec
    rows = max(3, round(columns * spec.width / spec.length / 2))
    grid = [[" "] * columns for _ in range(rows)]
    symbols = {"cue": "O", "black": "8", "solid": "s", "stripe": "x"}
    for ball, (x, y) in zip(layout.balls, layout.positions, strict=True):
        c = int(np.clip(x / spec.length * columns, 0, columns - 1))
        r = int(np.clip((spec.width - y) / spec.width * rows, 0, rows - 1))
        grid[r][c] = (
            symbols[ball.ball_class.value]
            if ball.number is None or ball.number in (0, 8)
            else (format(ball.number, "x"))
        )
    border = "+" + "-" * columns + "+"
    return "\n".join([border, *("|" + "".join(row) + "|" for row in grid), border])


def run(args: argparse.Namespace) -> int:
    path = args.file or example_layout_path()
    layout = load_layout(path)
    counts = {c: len(layout.indices_of(c)) for c in {b.ball_class for b in layout.balls}}
    summary = ", ".join(f"{n} {c.value}" for c, n in sorted(counts.items()))
    print(f"{path}: valid {layout.spec.name} layout with {len(layout)} balls ({summary})")
    if args.action == "show":
        print(ascii_diagram(layout))
        print("O cue, 8 black, 1-7 solids, 9-f stripes (hex); head rail on the left")
    return 0

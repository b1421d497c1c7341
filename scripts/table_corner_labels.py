"""Label by eye the cloth outline of a pool table in real photos, and draw the labels back for checking.

Each of the four cushions is labelled by two or more points on the outer edge of the cloth (the straight line where
the cloth-covered cushion top meets the rail or frame around the table: a sharp colour edge), read where the edge is
clear, away from the pockets, balls, hands and cues. The corners of that outline are where consecutive lines meet.
Pixels of the photo as stored (640x640 for the snooker-vision export), x to the right, y down. A photo counts as
showing the whole table when all four cushions can be traced and all four corners lie inside it.

Commands:
    list                      the photos to label: one copy of each source image of the train and valid splits
    grid IMAGE --out PNG      the photo at 2x with a labelled grid every 16 px (first, rough reading)
    zoom IMAGE --points "x,y x,y ..." --out PNG
                              5x zooms around rough points, ticks every 2 px (second reading)
    check IMAGE --lines "x,y x,y; x,y x,y; x,y x,y; x,y x,y" --out PNG
                              the four cushion lines and the corners they give drawn on the photo at 2x
    draw --labels JSON --out DIR [--sheet PNG]
                              every labelled photo with its corners and quadrilateral drawn, and a contact sheet

Usage:
    PYTHONPATH=src python scripts/table_corner_labels.py draw --labels benchmarks/data/real_table_corners.json \
        --out /tmp/corners
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import cv2
import numpy as np

from pix2pockets.vision.image_io import image_grid
from pix2pockets.vision.table.quad_geometry import quad_of_point_sets

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "real-snooker-vision"


def source_photos(data: Path) -> list[str]:
    """One copy (the first by name) of each source image of the train and valid splits, as paths under ``data``."""
    chosen: dict[str, str] = {}
    for split in ("train", "valid"):
        for path in sorted((data / split / "images").glob("*.jpg")):
            source = path.name.split(".rf.")[0]
            chosen.setdefault(source, f"{split}/images/{path.name}")
    return sorted(chosen.values())


def grid_image(image: np.ndarray, step: int = 16, scale: int = 2) -> np.ndarray:
    """The image enlarged ``scale`` times with grid lines every ``step`` px, labelled in original pixels."""
    big = cv2.resize(image, None, fx=scale, fy=scale, interpolation=cv2.INTER_CUBIC)
    h, w = image.shape[:2]
    for v in range(0, max(w, h) + 1, step):
        major = v % (step * 4) == 0
        colour = (0, 255, 255) if major else (160, 160, 160)
        thickness = 1
        if v <= w:
            cv2.line(big, (v * scale, 0), (v * scale, h * scale), colour, thickness)
        if v <= h:
            cv2.line(big, (0, v * scale), (w * scale, v * scale), colour, thickness)
        if major:
            for x in range(step * 2, w, step * 8):  # y values (red) above the horizontal lines
                cv2.putText(big, f"y{v}", (x * scale + 3, v * scale - 4), 0, 0.5, (0, 0, 255), 1)
            for y in range(step * 6, h, step * 8):  # x values (blue) right of the vertical lines
                cv2.putText(big, f"x{v}", (v * scale + 3, y * scale - 4), 0, 0.5, (255, 0, 0), 1)
    return big


def zoom_sheet(image: np.ndarray, points: np.ndarray, half: int = 24, scale: int = 5) -> np.ndarray:
    """Rows of four ``scale``-times zooms of ``2 * half`` px around each point, with ticks every 2 px and labels every
    8 px in original pixels; the rough point is marked by a small cross and the tile numbered from 1."""
    pad = half + 1
    padded = cv2.copyMakeBorder(image, pad, pad, pad, pad, cv2.BORDER_CONSTANT, value=(40, 40, 40))
    size = 2 * half * scale
    tiles = []
    for k, (px, py) in enumerate(np.round(points).astype(int)):
        x0, y0 = px - half, py - half
        crop = padded[y0 + pad : y0 + pad + 2 * half, x0 + pad : x0 + pad + 2 * half]
        tile = cv2.resize(crop, None, fx=scale, fy=scale, interpolation=cv2.INTER_NEAREST)
        for v in range(0, 2 * half + 1):
            for absolute, vertical in ((x0 + v, True), (y0 + v, False)):
                if absolute % 2:
                    continue
                colour = (0, 255, 255) if absolute % 8 == 0 else (110, 110, 110)
                a, b = ((v * scale, 0), (v * scale, size)) if vertical else ((0, v * scale), (size, v * scale))
                cv2.line(tile, a, b, colour, 1)
                if absolute % 8 == 0:
                    at = (v * scale + 2, 12) if vertical else (2, v * scale - 3)
                    cv2.putText(tile, str(absolute), at, 0, 0.4, (0, 0, 255) if vertical else (255, 0, 0), 1)
        c = half * scale
        cv2.drawMarker(tile, (c, c), (255, 0, 255), cv2.MARKER_CROSS, 14, 1)
        cv2.putText(tile, f"point {k + 1}", (4, size - 6), 0, 0.5, (255, 255, 255), 1)
        tiles.append(cv2.copyMakeBorder(tile, 2, 2, 2, 2, cv2.BORDER_CONSTANT, value=(255, 255, 255)))
    while len(tiles) % 4:
        tiles.append(np.zeros_like(tiles[0]))
    return np.vstack([np.hstack(tiles[i : i + 4]) for i in range(0, len(tiles), 4)])


def parse_lines(text: str) -> list[np.ndarray]:
    """Four cushion lines from ``"x,y x,y; x,y x,y; ..."`` (rails in order round the table), each (n >= 2, 2)."""
    lines = [np.array([[float(v) for v in p.split(",")] for p in part.split()]) for part in text.split(";")]
    if len(lines) != 4 or any(len(line) < 2 for line in lines):
        raise SystemExit("give four cushion lines of at least two points each, separated by ';'")
    return lines


def check_image(image: np.ndarray, lines: list[np.ndarray], scale: int = 2) -> np.ndarray:
    """The photo at ``scale`` times with the cushion lines drawn through their points to the corners (green), the
    points (magenta) and the corners (red, numbered)."""
    big = cv2.resize(image, None, fx=scale, fy=scale, interpolation=cv2.INTER_CUBIC)
    corners = quad_of_point_sets(lines)
    quad = np.round(corners * scale).astype(np.int32)
    cv2.polylines(big, [quad], True, (0, 255, 0), 1, cv2.LINE_AA)
    for line in lines:
        for x, y in line:
            cv2.circle(big, (round(x * scale), round(y * scale)), 3, (255, 0, 255), 1, cv2.LINE_AA)
    for k, (x, y) in enumerate(corners):
        cv2.circle(big, (round(x * scale), round(y * scale)), 5, (0, 0, 255), 1, cv2.LINE_AA)
        cv2.putText(big, str(k + 1), (round(x * scale) + 6, round(y * scale) - 6), 0, 0.6, (0, 0, 255), 2)
    return big


def draw_labels(image: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """The photo with the labelled playing surface (green) and its corners (red)."""
    out = image.copy()
    cv2.polylines(out, [np.round(corners).astype(np.int32)], True, (0, 255, 0), 1, cv2.LINE_AA)
    for x, y in corners:
        cv2.circle(out, (round(x), round(y)), 4, (0, 0, 255), 1, cv2.LINE_AA)
    return out


def named(image: np.ndarray, name: str, tile: int = 200) -> np.ndarray:
    """The image as a ``tile`` square, named by the first 10 characters of ``name``."""
    t = cv2.resize(image, (tile, tile), interpolation=cv2.INTER_AREA)
    cv2.putText(t, name[:10], (3, 14), 0, 0.45, (0, 255, 255), 1)
    return t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("command", choices=("list", "grid", "zoom", "check", "draw"))
    ap.add_argument("image", nargs="?", type=Path)
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the real-snooker-vision folder")
    ap.add_argument("--points", default="", help='points to zoom on: "x,y x,y ..."')
    ap.add_argument("--lines", default="", help='four cushion lines for check: "x,y x,y; x,y x,y; x,y x,y; x,y x,y"')
    ap.add_argument("--labels", type=Path, help="labels JSON for draw")
    ap.add_argument("--out", type=Path, help="output PNG (grid, zoom, check) or folder (draw)")
    ap.add_argument("--sheet", type=Path, default=None, help="contact sheet PNG for draw")
    args = ap.parse_args()

    if args.command == "list":
        print("\n".join(source_photos(args.data)))
        return
    if args.command != "draw":
        path = args.image if args.image.exists() else args.data / args.image
        image = cv2.imread(str(path))
        if image is None:
            raise SystemExit(f"cannot read {path}")
        if args.command == "grid":
            out = grid_image(image)
        elif args.command == "zoom":
            out = zoom_sheet(image, np.array([[float(v) for v in p.split(",")] for p in args.points.split()]))
        else:
            lines = parse_lines(args.lines)
            out = check_image(image, lines)
            print(" ".join(f"{x:.1f},{y:.1f}" for x, y in quad_of_point_sets(lines)))
        cv2.imwrite(str(args.out), out)
        return
    labels = json.loads(args.labels.read_text())
    args.out.mkdir(parents=True, exist_ok=True)
    drawn, names = [], []
    for entry in labels["photos"]:
        if not entry.get("whole_table"):
            continue
        image = cv2.imread(str(args.data / entry["image"]))
        corners = quad_of_point_sets(entry["lines"])
        picture = draw_labels(image, corners)
        name = Path(entry["image"]).name.split(".rf.")[0]
        cv2.imwrite(str(args.out / f"{name}.png"), picture)
        drawn.append(picture)
        names.append(name)
    if args.sheet is not None and drawn:
        cv2.imwrite(str(args.sheet), image_grid([named(d, n) for d, n in zip(drawn, names, strict=True)], 8))
    print(f"{len(drawn)} labelled photos drawn in {args.out}")


if __name__ == "__main__":
    main()

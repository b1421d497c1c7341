"""Label by eye the class of each boxed ball in real photos: crops to look at, and the labels drawn back.

The photos of ``../shared/data/real-snooker-vision`` box every ball (YOLO class 0) but name no class. ``sheet``
draws one photo with its boxes numbered and a sheet of 4x crops of every box, numbered the same; the labeller
writes the class of each (``cue``, ``black``, ``red``, ``yellow`` for a blackball set; ``solid``, ``stripe`` for a
numbered set; ``unknown`` where it cannot be told). ``draw`` puts a labels file back on the photos.

Usage:
    PYTHONPATH=src python scripts/ball_class_labels.py sheet valid/images/NAME.jpg --out /tmp/sheet.png
    PYTHONPATH=src python scripts/ball_class_labels.py draw --labels benchmarks/data/real_blackball_classes.json \
        --out DIR
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import cv2
import numpy as np

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "real-snooker-vision"
BALL_CLASS = 0  # the dataset's "Ball" class
COLOURS = {
    "cue": (255, 255, 255),
    "black": (60, 60, 60),
    "red": (0, 0, 255),
    "yellow": (0, 220, 255),
    "solid": (255, 128, 0),
    "stripe": (255, 0, 255),
    "unknown": (128, 128, 128),
}


def ball_boxes(data: Path, image: str) -> np.ndarray:
    """The dataset's ball boxes of a photo as normalised ``cx, cy, w, h`` rows (n, 4), in file order."""
    label = (data / image).parent.parent / "labels" / (Path(image).stem + ".txt")
    rows = [line.split() for line in label.read_text().splitlines() if line.strip()]
    return np.array([[float(v) for v in r[1:5]] for r in rows if int(r[0]) == BALL_CLASS]).reshape(-1, 4)


def to_pixels(box_cxcywh: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Normalised ``cx, cy, w, h`` -> ``x1, y1, x2, y2`` [px]."""
    w, h = size
    cx, cy, bw, bh = np.asarray(box_cxcywh, dtype=float).T
    return np.stack([(cx - bw / 2) * w, (cy - bh / 2) * h, (cx + bw / 2) * w, (cy + bh / 2) * h], axis=-1)


def sheet(image: np.ndarray, boxes_px: np.ndarray, tile: int = 96, columns: int = 8) -> np.ndarray:
    """The photo with numbered boxes above a sheet of numbered crops (each twice its box, scaled to ``tile``, the
    box drawn in it)."""
    shown = image.copy()
    for k, (x1, y1, x2, y2) in enumerate(boxes_px):
        cv2.rectangle(shown, (round(x1), round(y1)), (round(x2), round(y2)), (0, 255, 0), 1)
        cv2.putText(shown, str(k), (round(x1), round(y1) - 2), 0, 0.4, (0, 255, 255), 1)
    tiles = []
    h, w = image.shape[:2]
    for k, (x1, y1, x2, y2) in enumerate(boxes_px):
        cx, cy, half = (x1 + x2) / 2, (y1 + y2) / 2, max(x2 - x1, y2 - y1)
        a, b = int(max(cx - half, 0)), int(max(cy - half, 0))
        crop = image[b : int(min(cy + half, h)), a : int(min(cx + half, w))]
        if not crop.size:
            tiles.append(np.zeros((tile, tile, 3), np.uint8))
            continue
        sx, sy = tile / crop.shape[1], tile / crop.shape[0]
        t = cv2.resize(crop, (tile, tile), interpolation=cv2.INTER_CUBIC).astype(np.uint8)
        corner_a = (round((x1 - a) * sx), round((y1 - b) * sy))
        corner_b = (round((x2 - a) * sx), round((y2 - b) * sy))
        cv2.rectangle(t, corner_a, corner_b, (0, 255, 0), 1)  # the ball to name
        cv2.putText(t, str(k), (3, 14), 0, 0.5, (0, 255, 255), 1)
        tiles.append(t)
    while len(tiles) % columns or not tiles:
        tiles.append(np.zeros((tile, tile, 3), np.uint8))
    grid = np.vstack([np.hstack(tiles[i : i + columns]) for i in range(0, len(tiles), columns)])
    scale = grid.shape[1] / shown.shape[1]
    top = cv2.resize(shown, (grid.shape[1], round(shown.shape[0] * scale)), interpolation=cv2.INTER_CUBIC)
    return np.vstack([top, grid])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("command", choices=("sheet", "draw"))
    ap.add_argument("image", nargs="?")
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the real-snooker-vision folder")
    ap.add_argument("--labels", type=Path, help="labels JSON for draw")
    ap.add_argument("--out", type=Path, required=True, help="output PNG (sheet) or folder (draw)")
    args = ap.parse_args()
    if args.command == "sheet":
        image = cv2.imread(str(args.data / args.image))
        if image is None:
            raise SystemExit(f"cannot read {args.data / args.image}")
        boxes = to_pixels(ball_boxes(args.data, args.image), (image.shape[1], image.shape[0]))
        cv2.imwrite(str(args.out), sheet(image, boxes))
        print(f"{len(boxes)} balls, numbered 0-{len(boxes) - 1}")
        return
    args.out.mkdir(parents=True, exist_ok=True)
    labels = json.loads(args.labels.read_text())
    for entry in labels["images"]:
        image = cv2.imread(str(args.data / entry["image"]))
        size = (image.shape[1], image.shape[0])
        for ball in entry["balls"]:
            x1, y1, x2, y2 = to_pixels(np.array(ball["box_cxcywh"]), size)
            colour = COLOURS.get(ball["class"], (128, 128, 128))
            cv2.rectangle(image, (round(x1), round(y1)), (round(x2), round(y2)), colour, 1)
        cv2.imwrite(str(args.out / (Path(entry["image"]).stem.split(".rf.")[0] + ".png")), image)
    print(f"{len(labels['images'])} photos drawn in {args.out}")


if __name__ == "__main__":
    main()

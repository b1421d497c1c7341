"""Copy one split of a YOLO dataset with every image resized to WxH, as an export that squashes photos to one size
does (Roboflow's "stretch to 640x640"). Labels are normalised, so they carry over; diamond boxes (class 4) are
padded again to the labels' 4 px floor in the new pixels.

Usage:
    python scripts/stretch_yolo_split.py SRC DST WxH [--split test]

DST must not exist yet.
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

import cv2

from pix2pockets.vision.classes import DIAMOND_ID, MIN_DIAMOND_BOX_PX


def stretched_label_rows(text: str, size: tuple[int, int]) -> str:
    """YOLO label rows with diamond boxes widened to ``MIN_DIAMOND_BOX_PX`` in an image of ``size`` (w, h)."""
    rows = []
    for line in text.splitlines():
        if not line.strip():
            continue
        cls, cx, cy, bw, bh = line.split()
        w, h = float(bw), float(bh)
        if int(cls) == DIAMOND_ID:
            w, h = max(w, MIN_DIAMOND_BOX_PX / size[0]), max(h, MIN_DIAMOND_BOX_PX / size[1])
        rows.append(f"{cls} {cx} {cy} {w:.6f} {h:.6f}")
    return "\n".join(rows) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("src")
    parser.add_argument("dst")
    parser.add_argument("size", help="WxH, e.g. 640x640")
    parser.add_argument("--split", default="test")
    args = parser.parse_args()
    size = tuple(int(v) for v in args.size.lower().split("x"))
    src, dst = Path(args.src), Path(args.dst)
    if dst.exists():
        raise SystemExit(f"{dst} exists; choose another output folder")
    for sub in ("images", "labels"):
        (dst / args.split / sub).mkdir(parents=True)
    shutil.copy(src / "data.yaml", dst / "data.yaml")
    for image_path in sorted((src / args.split / "images").glob("*.jpg")):
        image = cv2.imread(str(image_path))
        resized = cv2.resize(image, size, interpolation=cv2.INTER_AREA)
        cv2.imwrite(str(dst / args.split / "images" / image_path.name), resized, [cv2.IMWRITE_JPEG_QUALITY, 92])
        label = src / args.split / "labels" / f"{image_path.stem}.txt"
        out = dst / args.split / "labels" / label.name
        out.write_text(stretched_label_rows(label.read_text(), size) if label.exists() else "")


if __name__ == "__main__":
    main()

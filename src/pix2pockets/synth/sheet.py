"""Contact sheet of synthetic renders beside real photos (for docs and for judging the realism gap).

Usage::

    python -m pix2pockets.synth.sheet --out docs/synth_examples.png \\
        --real ../shared/data/real-snooker-vision/train/images --seed 0
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path

import cv2
import numpy as np

from pix2pockets.synth.renderer import render
from pix2pockets.vision.image_io import image_grid

CELL = (400, 225)
DEFAULT_REAL = (
    "141d43f4756670f5_jpg.rf.d16cfe9c0767c77cd240ef1757c2ffb8.jpg",
    "08bc48fd4c2e93e5_jpg.rf.2e3200cb05d22da9d3e3813baae7cb68.jpg",
    "0c9bd43429af20ad_jpg.rf.efd45cc6bf403e4f8224413e2df6128a.jpg",
    "yt-D8S70xyTlbU-0164_jpg.rf.61e964c30b2349284af0889d19566ac1.jpg",
)
CAMERA_ORDER = ("top", "high", "low", "jib", "phone", "phone_low", "top", "high", "jib", "phone", "low", "phone")


def _caption(img: np.ndarray, text: str) -> np.ndarray:
    out = img.copy()
    cv2.rectangle(out, (0, 0), (len(text) * 9 + 8, 20), (0, 0, 0), -1)
    cv2.putText(out, text, (4, 15), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (255, 255, 255), 1, cv2.LINE_AA)
    return out


def _letterbox(img: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    w, h = size
    s = min(w / img.shape[1], h / img.shape[0])
    new_size = (max(1, int(img.shape[1] * s)), max(1, int(img.shape[0] * s)))
    small = cv2.resize(img, new_size, interpolation=cv2.INTER_AREA)
    out = np.full((h, w, 3), 40, np.uint8)
    y0, x0 = (h - small.shape[0]) // 2, (w - small.shape[1]) // 2
    out[y0 : y0 + small.shape[0], x0 : x0 + small.shape[1]] = small
    return out


def contact_sheet(seeds: Sequence[int], real_paths: Sequence[Path], size: tuple[int, int] = (960, 540)) -> np.ndarray:
    """A 4-column sheet: the renders of ``seeds`` (cameras cycling through the kinds), then real photos.

    Returns:
        RGB uint8 image.
    """
    cells = []
    for k, seed in enumerate(seeds):
        kind = CAMERA_ORDER[k % len(CAMERA_ORDER)]
        rend = render(seed, size, camera_kind=kind)
        cell = cv2.resize(rend.image, CELL, interpolation=cv2.INTER_AREA)
        cells.append(_caption(cell, f"synthetic seed {seed}, {rend.labels['camera']['kind']}"))
    for p in real_paths:
        bgr = cv2.imread(str(p))
        if bgr is None:
            raise ValueError(f"cannot read real photo {p}")
        cells.append(_caption(_letterbox(cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB), CELL), "REAL photo (snooker-vision)"))
    return image_grid(cells, 4)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="contact sheet of synthetic renders beside real photos")
    parser.add_argument("--out", required=True, help="output PNG")
    parser.add_argument("--real", required=True, help="folder of real photos (e.g. the snooker-vision train images)")
    parser.add_argument("--seed", type=int, default=0, help="first render seed (12 consecutive seeds)")
    args = parser.parse_args(argv)
    real_dir = Path(args.real)
    real = [real_dir / name for name in DEFAULT_REAL if (real_dir / name).exists()]
    sheet = contact_sheet(list(range(args.seed, args.seed + 12)), real)
    cv2.imwrite(args.out, cv2.cvtColor(sheet, cv2.COLOR_RGB2BGR))
    print(f"wrote {args.out} ({sheet.shape[1]}x{sheet.shape[0]}, {len(real)} real photos)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

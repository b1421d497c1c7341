"""Hand-made toy table images with exact YOLO labels, for detector tests (no renderer needed)."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

COLOURS = {0: (245, 245, 240), 1: (15, 15, 15), 2: (220, 40, 30), 3: (30, 60, 200)}


def toy_image(rng: np.random.Generator, size: tuple[int, int] = (320, 192), n_balls: int = 6):
    """A top-down toy table: rails with white diamonds, coloured balls. Returns image and (boxes, classes, contacts)."""
    w, h = size
    img = np.zeros((h, w, 3), np.uint8)
    img[:] = (90, 60, 30)
    m = 16
    img[m : h - m, m : w - m] = (20, 120, 60)
    boxes, cls, contacts = [], [], []
    for i in range(7):
        x = m + (w - 2 * m) * (i + 0.5) / 7
        for y in (m / 2, h - m / 2):
            cv2.circle(img, (round(x), round(y)), 2, (250, 250, 250), -1, cv2.LINE_AA)
            boxes.append([x - 2.5, y - 2.5, x + 2.5, y + 2.5])
            cls.append(4)
            contacts.append([np.nan, np.nan])
    r = 7
    centres: list[np.ndarray] = []
    for k in range(n_balls):
        c = 0 if k == 0 else 1 if k == 1 else int(rng.integers(2, 4))
        for _ in range(50):
            p = rng.uniform([m + r + 2, m + r + 2], [w - m - r - 2, h - m - r - 2])
            if all(np.linalg.norm(p - q) > 2 * r + 2 for q in centres):
                break
        centres.append(p)
        cv2.circle(img, (round(p[0]), round(p[1])), r, COLOURS[c], -1, cv2.LINE_AA)
        if c == 3:
            cv2.rectangle(
                img, (round(p[0] - r), round(p[1] - 2)), (round(p[0] + r), round(p[1] + 2)), (245, 245, 240), -1
            )
        boxes.append([p[0] - r, p[1] - r, p[0] + r, p[1] + r])
        cls.append(c)
        contacts.append([p[0], p[1] + 0.5 * r])
    return img, np.array(boxes), np.array(cls), np.array(contacts)


def write_toy_dataset(root: Path, n: int, seed: int = 0, split: str = "train") -> Path:
    """Write ``n`` toy images as a YOLO dataset split (with contact sidecars); returns ``root``."""
    rng = np.random.default_rng(seed)
    (root / split / "images").mkdir(parents=True, exist_ok=True)
    (root / split / "labels").mkdir(parents=True, exist_ok=True)
    (root / split / "meta").mkdir(parents=True, exist_ok=True)
    (root / "data.yaml").write_text("names: ['cue', 'black', 'solid', 'stripe', 'dot']\nnc: 5\n")
    import json

    for i in range(n):
        img, boxes, cls, contacts = toy_image(rng)
        h, w = img.shape[:2]
        cv2.imwrite(str(root / split / "images" / f"toy{i:04d}.png"), cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
        cx, cy = (boxes[:, 0] + boxes[:, 2]) / 2 / w, (boxes[:, 1] + boxes[:, 3]) / 2 / h
        bw, bh = (boxes[:, 2] - boxes[:, 0]) / w, (boxes[:, 3] - boxes[:, 1]) / h
        lines = [f"{c} {x:.6f} {y:.6f} {a:.6f} {b:.6f}" for c, x, y, a, b in zip(cls, cx, cy, bw, bh, strict=True)]
        (root / split / "labels" / f"toy{i:04d}.txt").write_text("\n".join(lines) + "\n")
        cps = [None if np.isnan(p[0]) else [float(p[0]), float(p[1])] for p in contacts]
        (root / split / "meta" / f"toy{i:04d}.json").write_text(json.dumps({"contacts_px": cps}))
    return root

"""Blackball sets on real pub photos: is the set recognised, and is each ball found and named right?

``benchmarks/data/real_blackball_classes.json`` names, by eye, every boxed ball (cue, black, red, yellow) of the
30 valid frames of ``../shared/data/real-snooker-vision`` (one video of one UK pub table). Each frame goes through
the bundled detector and the pipeline's post-processing for a ball set (``--set``, default ``auto``: read from the
balls' colours); each labelled ball is matched to the kept detection of highest IoU (>= 0.5), and its class named
in the set that was read (``red``/``yellow`` in a blackball set). Reported: frames read as blackball, balls found,
balls found and named right, per class.

Usage:
    PYTHONPATH=src python benchmarks/real_blackball_classes.py [--data DIR] [--labels FILE] [--set auto|blackball]
        [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
from collections import Counter
from pathlib import Path

import numpy as np

from pix2pockets.pipeline.photo import clean_detections_for_set, default_detector, playing_surface
from pix2pockets.state.ball_set import class_name
from pix2pockets.vision.classes import ball_class_of
from pix2pockets.vision.detect.postprocess import box_iou
from pix2pockets.vision.image_io import read_image_rgb

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "real-snooker-vision"
DEFAULT_LABELS = HERE / "data" / "real_blackball_classes.json"
CLASSES = ("cue", "black", "red", "yellow")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the real-snooker-vision folder")
    ap.add_argument("--labels", type=Path, default=DEFAULT_LABELS)
    ap.add_argument("--set", dest="ball_set", default="auto", choices=["auto", "blackball"])
    ap.add_argument("--json", default=None)
    args = ap.parse_args()

    detector = default_detector()
    entries = json.loads(args.labels.read_text())["images"]
    sets: Counter[str] = Counter()
    found: Counter[str] = Counter()
    right: Counter[str] = Counter()
    total: Counter[str] = Counter()
    confusion: Counter[tuple[str, str]] = Counter()
    for entry in entries:
        path = args.data / entry["image"]
        if not path.is_file():
            raise SystemExit(f"{path} not found: pass --data, the real-snooker-vision folder")
        rgb = read_image_rgb(path)
        h, w = rgb.shape[:2]
        det, chosen = clean_detections_for_set(detector.detect(rgb), rgb, args.ball_set, playing_surface(rgb, True))
        sets[chosen.value] += 1
        balls = det[det.is_ball]
        names = [class_name(ball_class_of(int(c)), chosen) for c in balls.class_id]
        for ball in entry["balls"]:
            truth = ball["class"]
            if truth not in CLASSES:
                continue
            total[truth] += 1
            cx, cy, bw, bh = ball["box_cxcywh"]
            box = np.array([[(cx - bw / 2) * w, (cy - bh / 2) * h, (cx + bw / 2) * w, (cy + bh / 2) * h]])
            if not len(balls):
                continue
            iou = box_iou(box, balls.boxes)[0]
            j = int(np.argmax(iou))
            if iou[j] < 0.5:
                continue
            found[truth] += 1
            confusion[(truth, names[j])] += 1
            right[truth] += names[j] == truth
    n = sum(total.values())
    print(f"frames read as: {dict(sets)}")
    print(f"{'class':<8} {'balls':>6} {'found':>7} {'named right':>12}")
    for c in CLASSES:
        print(f"{c:<8} {total[c]:>6} {found[c] / max(total[c], 1):>7.1%} {right[c] / max(total[c], 1):>12.1%}")
    print(f"{'all':<8} {n:>6} {sum(found.values()) / n:>7.1%} {sum(right.values()) / n:>12.1%}")
    print("confusions (truth -> named):", {f"{a}->{b}": k for (a, b), k in sorted(confusion.items()) if a != b})
    if args.json:
        report = {
            "frames": len(entries),
            "sets": dict(sets),
            "balls": n,
            "found": sum(found.values()),
            "right": sum(right.values()),
            "per_class": {c: {"balls": total[c], "found": found[c], "right": right[c]} for c in CLASSES},
            "confusions": {f"{a}->{b}": k for (a, b), k in sorted(confusion.items()) if a != b},
        }
        Path(args.json).write_text(json.dumps(report, indent=1) + "\n")


if __name__ == "__main__":
    main()

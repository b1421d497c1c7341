"""Detections too small for a ball where they lie: how many the size check (``locate.balls.too_small``) drops among
the detections on the fitted table that box a ball and among those that box none.

Three sets, each run as ``suggest`` finds its balls (``find_table``, then ``balls_in_play(..., drop_small=False)``,
so that every detection the check would judge is counted):

- ``--n`` renders of American sets from seed 5000 and of blackball sets from seed 7000 (960x540, every camera kind,
  players and props), a detection boxing a ball when it meets a labelled ball's visible box at IoU >= 0.5;
- the real photos whose balls were labelled by eye (``benchmarks/data/real_ball_classes.json``, 30 phone photos of
  numbered sets, and ``real_blackball_classes.json``, 30 pub video frames), the same match against those boxes.

Usage:
    OMP_NUM_THREADS=1 PYTHONPATH=src python benchmarks/ball_size_check.py [--n 150] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")

from pix2pockets.pipeline.photo import balls_in_play, default_detector, find_table
from pix2pockets.synth.renderer import render
from pix2pockets.vision.detect.postprocess import box_iou
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.locate.balls import MIN_BALL_SHARE, too_small
from pix2pockets.vision.table.fit import TableFitError

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "real-snooker-vision"
LABELS = (HERE / "data" / "real_ball_classes.json", HERE / "data" / "real_blackball_classes.json")


def rendered(n: int) -> Iterator[tuple[str, np.ndarray, np.ndarray, str]]:
    """(set name, image, labelled visible ball boxes (m, 4) [px], ball set) of the renders."""
    for ball_set, seed in (("american", 5000), ("blackball", 7000)):
        for k in range(n):
            out = render((seed, k), (960, 540), ball_set=ball_set)
            boxes = [b["box_px"] for b in out.labels["balls"] if b["labelled"]]
            yield f"renders, {ball_set}", out.image, np.array(boxes, dtype=float).reshape(-1, 4), ball_set


def labelled_photos(data: Path) -> Iterator[tuple[str, np.ndarray, np.ndarray, str]]:
    """(set name, image, ball boxes labelled by eye (m, 4) [px], ``auto``) of the real photos."""
    for path in LABELS:
        for entry in json.loads(path.read_text())["images"]:
            image = read_image_rgb(data / entry["image"])
            h, w = image.shape[:2]
            cxcywh = np.array([b["box_cxcywh"] for b in entry["balls"]], dtype=float).reshape(-1, 4) * [w, h, w, h]
            boxes = np.column_stack([cxcywh[:, :2] - cxcywh[:, 2:] / 2, cxcywh[:, :2] + cxcywh[:, 2:] / 2])
            yield "real photos", image, boxes, "auto"


def judged(image: np.ndarray, truth: np.ndarray, ball_set: str, detector) -> tuple[np.ndarray, np.ndarray] | None:
    """For the detections on the fitted table: whether each boxes a ball, and whether the size check drops it."""
    raw = detector.detect(image)
    try:
        det, chosen, _, fit = find_table(image, raw, ball_set=ball_set)
    except TableFitError:
        return None
    located = balls_in_play(raw, det, image, chosen, fit, drop_small=False)
    boxes = located.detections.boxes
    if len(boxes) == 0:
        return None
    is_ball = box_iou(boxes, truth).max(axis=1) >= 0.5 if len(truth) else np.zeros(len(boxes), dtype=bool)
    return is_ball, too_small(fit.camera, boxes, located.positions, fit.spec)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=150, help="renders of each ball set (default 150)")
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the real-snooker-vision folder")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()

    detector = default_detector()
    counts: dict[str, dict[str, int]] = {}
    start = time.perf_counter()
    for name, image, truth, ball_set in (*rendered(args.n), *labelled_photos(args.data)):
        out = judged(image, truth, ball_set, detector)
        if out is None:
            continue
        is_ball, dropped = out
        c = counts.setdefault(name, {"balls": 0, "balls_dropped": 0, "no_ball": 0, "no_ball_dropped": 0})
        c["balls"] += int(is_ball.sum())
        c["balls_dropped"] += int((is_ball & dropped).sum())
        c["no_ball"] += int((~is_ball).sum())
        c["no_ball_dropped"] += int((~is_ball & dropped).sum())
    print(f"{'set':<20} {'boxing a ball':>14} {'dropped':>8} {'boxing none':>12} {'dropped':>8}")
    for name, c in counts.items():
        print(f"{name:<20} {c['balls']:>14} {c['balls_dropped']:>8} {c['no_ball']:>12} {c['no_ball_dropped']:>8}")
    print(f"{time.perf_counter() - start:.0f} s")
    if args.json:
        report = {"n_renders_per_set": args.n, "min_ball_share": MIN_BALL_SHARE, "sets": counts}
        Path(args.json).write_text(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()

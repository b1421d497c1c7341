"""How often the ball-number reader names a ball right, on rendered splits (their sidecars hold the numbers).

Two readings per split:
- *label boxes*: every labelled ball's own box and class go to the reader (`assign_numbers`: a number of the
  ball's class, each number once per table); this measures the reader alone.
- *photo*: the bundled detector and the pipeline's post-processing (`clean_detections`) find the balls and their
  classes; each labelled ball is matched to the found ball of highest IoU (>= 0.5), and its number is counted
  right when the found ball carries it. Misses and wrong classes show up as wrong here. *Named*: the share of
  the found balls whose number the pipeline shows (chance >= ``SURE_NUMBER_CHANCE``), and how many of those
  are right.

Usage:
    PYTHONPATH=src python benchmarks/ball_numbers.py --data DATASET [--data ...] [--split test] [--limit N]
        [--reader PATH] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from pix2pockets.pipeline.photo import clean_detections
from pix2pockets.pipeline.result import SURE_NUMBER_CHANCE
from pix2pockets.vision.detect.onnx_detector import OnnxDetector
from pix2pockets.vision.detect.postprocess import box_iou
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.metrics.yolo_data import split_dir
from pix2pockets.vision.stages.ball_numbers import (
    N_NUMBERS,
    BallNumberReader,
    assign_numbers,
)


def score_split(root: str, split: str, reader: BallNumberReader, detector: OnnxDetector, limit: int | None) -> dict:
    """Counts of right numbers per true number, for label boxes and for the photo pipeline."""
    folder = split_dir(root, split)
    metas = sorted((folder / "meta").glob("*.json"))[:limit]
    if not metas:
        raise SystemExit(f"{folder} has no renderer sidecars (meta/*.json): numbers need 'pix2pockets synth' renders")
    total = np.zeros(N_NUMBERS, int)
    right_labels = np.zeros(N_NUMBERS, int)
    right_photo = np.zeros(N_NUMBERS, int)
    found = np.zeros(N_NUMBERS, int)
    named = named_right = 0  # found balls whose number the pipeline would show (chance >= SURE_NUMBER_CHANCE)
    seconds = 0.0
    for path in metas:
        meta = json.loads(path.read_text())
        balls = [b for b in meta["balls"] if b["labelled"]]
        if not balls:
            continue
        image = read_image_rgb(next((folder / "images").glob(path.stem + ".*")))
        boxes = np.array([b["box_px"] for b in balls], float)
        truth = np.array([b["number"] for b in balls])
        classes = np.array([b["class_id"] for b in balls])
        np.add.at(total, truth, 1)
        t = time.perf_counter()
        numbers, _ = assign_numbers(reader.read(image, boxes), classes)
        seconds += time.perf_counter() - t
        np.add.at(right_labels, truth, numbers == truth)

        det = clean_detections(detector.detect(image))
        det = det[det.is_ball]
        if len(det) == 0:
            continue
        got, chance = reader.numbers(image, det.boxes, det.class_id)
        iou = box_iou(boxes, det.boxes)
        best = iou.argmax(axis=1)
        hit = iou[np.arange(len(balls)), best] >= 0.5
        np.add.at(found, truth, hit)
        np.add.at(right_photo, truth, hit & (got[best] == truth))
        shown = hit & (chance[best] >= SURE_NUMBER_CHANCE)
        named += int(shown.sum())
        named_right += int((shown & (got[best] == truth)).sum())
    return {
        "data": str(root),
        "images": len(metas),
        "balls": int(total.sum()),
        "label_boxes_accuracy": round(float(right_labels.sum() / max(total.sum(), 1)), 4),
        "photo_found": round(float(found.sum() / max(total.sum(), 1)), 4),
        "photo_accuracy": round(float(right_photo.sum() / max(total.sum(), 1)), 4),
        "photo_accuracy_of_found": round(float(right_photo.sum() / max(found.sum(), 1)), 4),
        "photo_named_of_found": round(named / max(found.sum(), 1), 4),
        "photo_named_right": round(named_right / max(named, 1), 4),
        "reader_ms_per_ball": round(1000 * seconds / max(total.sum(), 1), 3),
        "label_boxes_by_number": {
            str(n): round(float(right_labels[n] / total[n]), 4) for n in range(N_NUMBERS) if total[n]
        },
        "photo_by_number": {str(n): round(float(right_photo[n] / total[n]), 4) for n in range(N_NUMBERS) if total[n]},
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", action="append", required=True, help="rendered dataset (repeatable)")
    ap.add_argument("--split", default="test")
    ap.add_argument("--limit", type=int, default=None, help="first N images per dataset")
    ap.add_argument("--reader", default=str(BallNumberReader.default_path()), help="ball-number reader ONNX")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()

    reader = BallNumberReader(args.reader)
    detector = OnnxDetector.from_default()
    rows = [score_split(root, args.split, reader, detector, args.limit) for root in args.data]
    print(
        f"{'data':<28} {'images':>6} {'balls':>6} {'label boxes':>11} {'found':>6} {'photo':>6} {'of found':>8} "
        f"{'named':>6} {'named right':>11}"
    )
    for r in rows:
        print(
            f"{Path(r['data']).name:<28} {r['images']:>6} {r['balls']:>6} {r['label_boxes_accuracy']:>11.3f} "
            f"{r['photo_found']:>6.3f} {r['photo_accuracy']:>6.3f} {r['photo_accuracy_of_found']:>8.3f} "
            f"{r['photo_named_of_found']:>6.3f} {r['photo_named_right']:>11.3f}"
        )
    if args.json:
        Path(args.json).write_text(json.dumps({"reader": args.reader, "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()

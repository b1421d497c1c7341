"""Ball classes on real photos: how often the detector calls a real cue, 8, solid or stripe right.

The phone photos of ``../shared/data/real-snooker-vision`` box every ball but name no class. For 30 of them that
show a numbered pool set, ``benchmarks/data/real_ball_classes.json`` gives the class of 174 boxed balls, told by
eye from crops (balls that could not be told are left out). Each labelled ball is matched to the detection of
highest IoU (>= 0.5) and its class compared, three ways:

- *raw*: the most confident raw entry (before post-processing) of the matched box;
- *paper*: after the paper's post-processing (class-agnostic NMS, caps);
- *pipeline*: after the product's (`clean_detections`: one class per ball, cue and 8 once each, per-class
  confidence floors); a ball the pipeline drops counts as missed;
- *located*: on the photos where the pipeline fits a table, the *pipeline* reading's balls that lie on it
  (`locate_balls`): the cue ball and the 8 claimed before the balls off the table are dropped;
- *on the table*: on the same photos, as `suggest` reads them: the balls off the table dropped first, then the cue
  ball and the 8 claimed among the rest (`balls_in_play`).

In the last two a ball off the fitted table counts as missed.

The detector saw these photos' ball boxes in training (the "any ball" head), never their classes.

Usage:
    PYTHONPATH=src python benchmarks/real_ball_classes.py [--data DIR] [--labels FILE] [--numbers none]
        [--classifier PATH] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from pix2pockets.cli.detector_options import add_detector_options, detector_from_args
from pix2pockets.pipeline.photo import balls_in_play, clean_detections, read_surface
from pix2pockets.state.ball_set import BallSet
from pix2pockets.vision.classes import BALL_IDS, CLASS_NAMES
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.onnx_detector import OnnxDetectorConfig
from pix2pockets.vision.detect.postprocess import box_iou, postprocess
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.locate.balls import locate_balls
from pix2pockets.vision.table.estimate import estimate_table
from pix2pockets.vision.table.fit import TableFitError

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "real-snooker-vision"
DEFAULT_LABELS = HERE / "data" / "real_ball_classes.json"
MIN_IOU = 0.5
MISSED = len(BALL_IDS)  # the confusion matrix's last column
READINGS = ("raw", "paper", "pipeline", "located", "on the table")


def labelled_boxes(entry: dict, size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Boxes xyxy (n, 4) [px] and class ids (n,) of one image's labelled balls."""
    w, h = size
    cxcywh = np.array([b["box_cxcywh"] for b in entry["balls"]], float).reshape(-1, 4) * [w, h, w, h]
    boxes = np.hstack([cxcywh[:, :2] - cxcywh[:, 2:] / 2, cxcywh[:, :2] + cxcywh[:, 2:] / 2])
    return boxes, np.array([CLASS_NAMES.index(b["class"]) for b in entry["balls"]], int)


def called_classes(boxes: np.ndarray, found: Detections) -> np.ndarray:
    """For each labelled box, the class of the found ball of highest IoU >= :data:`MIN_IOU` (among the most
    confident entries of equal boxes), else :data:`MISSED`."""
    found = found[np.where(found.is_ball)[0]]
    called = np.full(len(boxes), MISSED)
    if not len(found) or not len(boxes):
        return called
    iou = box_iou(boxes, found.boxes)
    for i, row in enumerate(iou):
        if row.max() < MIN_IOU:
            continue
        same = np.isclose(row, row.max())
        best = np.argmax(np.where(same, found.confidence, -1.0))
        called[i] = found.class_id[best]
    return called


def confusion(data: Path, labels: dict, detector) -> dict[str, np.ndarray]:
    """Confusion matrices (true class x called class or missed) per reading."""
    counts = {r: np.zeros((len(BALL_IDS), len(BALL_IDS) + 1), int) for r in READINGS}
    for entry in labels["images"]:
        path = data / entry["image"]
        if not path.is_file():
            raise SystemExit(f"{path} not found: pass --data, the real-snooker-vision folder")
        image = read_image_rgb(path)
        boxes, truth = labelled_boxes(entry, (image.shape[1], image.shape[0]))
        raw = detector.detect(image)
        det = clean_detections(raw)
        readings = {"raw": raw, "paper": postprocess(raw), "pipeline": det}
        size = (image.shape[1], image.shape[0])
        surface = read_surface(image, det, True)
        try:
            fit = estimate_table(image, det, size, pixel_aspect=det.pixel_aspect, surface=surface)
        except TableFitError:
            pass
        else:
            readings["located"] = locate_balls(fit.camera, det, fit.spec).detections
            readings["on the table"] = balls_in_play(raw, det, image, BallSet.AMERICAN, fit).detections
        for reading, found in readings.items():
            np.add.at(counts[reading], (truth, called_classes(boxes, found)), 1)
    return counts


def summary(matrix: np.ndarray) -> dict:
    """Per true class: balls, found share, right share of all and of the found; and the totals."""
    rows = {}
    for c in BALL_IDS:
        n, missed, right = int(matrix[c].sum()), int(matrix[c, MISSED]), int(matrix[c, c])
        rows[CLASS_NAMES[c]] = {
            "balls": n,
            "found": (n - missed) / n if n else float("nan"),
            "right": right / n if n else float("nan"),
            "right_of_found": right / (n - missed) if n > missed else float("nan"),
        }
    n, found = int(matrix.sum()), int(matrix[:, :MISSED].sum())
    right = int(np.trace(matrix[:, :MISSED]))
    rows["all"] = {"balls": n, "found": found / n, "right": right / n, "right_of_found": right / found}
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the real-snooker-vision folder")
    ap.add_argument("--labels", type=Path, default=DEFAULT_LABELS, help="ball classes JSON")
    add_detector_options(ap)
    ap.add_argument("--json", default=None)
    args = ap.parse_args()

    labels = json.loads(args.labels.read_text())
    detector = detector_from_args(args, OnnxDetectorConfig().conf_threshold)
    counts = confusion(args.data, labels, detector)
    print(f"{'reading':<12} {'class':<7} {'balls':>5} {'found':>6} {'right':>6} {'of found':>8}   called as")
    header = " ".join(f"{n:>6}" for n in (*CLASS_NAMES[:MISSED], "missed"))
    for reading in READINGS:
        for name, row in summary(counts[reading]).items():
            calls = ""
            if name != "all":
                calls = " ".join(f"{v:>6}" for v in counts[reading][CLASS_NAMES.index(name)])
            print(
                f"{reading:<12} {name:<7} {row['balls']:>5} {row['found']:>6.3f} {row['right']:>6.3f} "
                f"{row['right_of_found']:>8.3f}   {calls}"
            )
    print(f"{'':<51}{header}")
    if args.json:
        report = {
            "labels": str(args.labels),
            "options": {k: v for k, v in vars(args).items() if k not in ("data", "labels", "json")},
            "readings": {r: {"summary": summary(m), "confusion": m.tolist()} for r, m in counts.items()},
            "confusion_columns": [*CLASS_NAMES[:MISSED], "missed"],
        }
        Path(args.json).write_text(json.dumps(report, indent=1) + "\n")


if __name__ == "__main__":
    main()

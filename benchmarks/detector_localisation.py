"""How well the detector places the objects it finds: centre error and IoU per class, on a labelled split.

For every ground-truth box, the raw detection of the same kind (diamond, or any ball from the "any ball"
heatmap) whose centre is nearest is taken, if it scores at least ``--conf`` and lies within half a box side
(at least 3 px). Reported per kind: how many were found that way, the centre error percentiles [px] and the
share of found objects whose box reaches IoU 0.5, the AP50 criterion. For 4 px diamond boxes a centre error
of about 1 px already fails IoU 0.5, so this share is what limits diamond AP50.

Usage:
    PYTHONPATH=src python benchmarks/detector_localisation.py --data DATASET [--split test] [--model PATH]
        [--conf 0.2] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from pix2pockets.vision.classes import BALL_IDS, DIAMOND_ID
from pix2pockets.vision.detect.onnx_detector import OnnxDetector, OnnxDetectorConfig, default_model_path
from pix2pockets.vision.detect.postprocess import box_iou
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.metrics.yolo_data import dataset_class_map, load_split


def _match(gt: np.ndarray, pred: np.ndarray) -> list[tuple[float, float]]:
    """(centre error [px], IoU) of the nearest prediction for each ground-truth box it is close enough to."""
    if len(gt) == 0 or len(pred) == 0:
        return []
    gc = 0.5 * (gt[:, :2] + gt[:, 2:])
    pc = 0.5 * (pred[:, :2] + pred[:, 2:])
    dist = np.linalg.norm(gc[:, None] - pc[None], axis=2)
    iou = box_iou(gt, pred)
    reach = np.maximum(3.0, 0.5 * (gt[:, 2:] - gt[:, :2]).max(axis=1))
    j = dist.argmin(axis=1)
    rows = np.arange(len(gt))
    ok = dist[rows, j] <= reach
    return list(zip(dist[rows, j][ok].tolist(), iou[rows, j][ok].tolist(), strict=True))


def _summary(pairs: list[tuple[float, float]], n_gt: int) -> dict:
    err = np.array([p[0] for p in pairs])
    iou = np.array([p[1] for p in pairs])
    if not len(pairs):
        return {"n_gt": n_gt, "found": 0.0}
    return {
        "n_gt": n_gt,
        "found": round(len(pairs) / max(n_gt, 1), 4),
        "centre_err_px_p50": round(float(np.percentile(err, 50)), 3),
        "centre_err_px_p90": round(float(np.percentile(err, 90)), 3),
        "iou_p50": round(float(np.median(iou)), 3),
        "iou50_share_of_found": round(float((iou >= 0.5).mean()), 4),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", required=True)
    ap.add_argument("--split", default="test")
    ap.add_argument("--model", default=str(default_model_path()))
    ap.add_argument("--conf", type=float, default=0.2)
    ap.add_argument("--json", default=None)
    args = ap.parse_args()

    det = OnnxDetector(args.model, OnnxDetectorConfig(threads=1))
    cmap = dataset_class_map(args.data)
    kinds = {"diamond": [], "ball": []}
    counts = {"diamond": 0, "ball": 0}
    for item in load_split(args.data, args.split):
        image = read_image_rgb(item.image_path)
        cls = np.array([cmap.get(int(c), -1) for c in item.class_id])
        raw = det.detect(image)
        diamonds = raw.boxes[(raw.class_id == DIAMOND_ID) & (raw.confidence >= args.conf)]
        balls = det.detect_balls(image)
        ball_boxes = balls.boxes[balls.confidence >= args.conf]
        for kind, gt, pred in (
            ("diamond", item.boxes[cls == DIAMOND_ID], diamonds),
            ("ball", item.boxes[np.isin(cls, BALL_IDS)], ball_boxes),
        ):
            counts[kind] += len(gt)
            kinds[kind] += _match(gt, pred)
    report = {
        "data": args.data,
        "split": args.split,
        "model": args.model,
        "conf": args.conf,
        **{k: _summary(v, counts[k]) for k, v in kinds.items()},
    }
    print("| kind | objects | found | centre error p50 / p90 [px] | IoU p50 | IoU >= 0.5 (of found) |")
    print("|---|---|---|---|---|---|")
    for k in kinds:
        r = report[k]
        if r["found"]:
            print(
                f"| {k} | {r['n_gt']} | {100 * r['found']:.1f} % | {r['centre_err_px_p50']:.2f} / "
                f"{r['centre_err_px_p90']:.2f} | {r['iou_p50']:.2f} | {100 * r['iou50_share_of_found']:.1f} % |"
            )
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()

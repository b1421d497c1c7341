"""How much of a stripe ball's coloured band the camera sees, and how the detector's class call depends on it.

A stripe ball seen from near its pole shows a white disc with the band as a thin ring at the rim. For each
stripe in a rendered split (the ``seed`` in each JSON label rebuilds the scene, ball rotations included), the
share of the ball's visible disc that is band is computed from the geometry (uniform samples on the
projected disc). The detector (and ball classifier) is run on the image; the class of its best-scoring
detection with IoU >= 0.5 on the ball's box is counted per band-share bucket. Cue balls are counted too.

Usage:
    PYTHONPATH=src python benchmarks/stripe_visibility.py --data DATASET [--split test] [--model PATH]
        [--classifier PATH|none] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import itertools
import json
from pathlib import Path

import numpy as np

from pix2pockets.synth import scene_codes as sc
from pix2pockets.synth.renderer import scene_of
from pix2pockets.vision.classes import BALL_IDS, CLASS_NAMES
from pix2pockets.vision.detect.onnx_detector import (
    OnnxDetector,
    OnnxDetectorConfig,
    default_model_path,
)
from pix2pockets.vision.detect.postprocess import box_iou
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.metrics.yolo_data import split_dir
from pix2pockets.vision.stages.ball_classifier import BallClassifier

BUCKETS = (0.0, 0.2, 0.35, 0.5, 1.01)
DISC = np.random.default_rng(0).uniform(-1, 1, (6000, 2))
DISC = DISC[(DISC**2).sum(axis=1) < 1]


def band_share(centre: np.ndarray, rotation: np.ndarray, band: float, camera: np.ndarray) -> float:
    """Share of the visible disc of a ball at ``centre`` [m] seen from ``camera`` [m] that lies in the band
    ``|q_z| < band`` of the ball frame (``rotation``: world -> ball)."""
    d = camera - centre
    d /= np.linalg.norm(d)
    u = np.cross(d, [0.0, 0.0, 1.0])
    u = u / np.linalg.norm(u) if np.linalg.norm(u) > 1e-9 else np.array([1.0, 0.0, 0.0])
    w = np.cross(d, u)
    normals = DISC[:, :1] * u + DISC[:, 1:] * w + np.sqrt(1 - (DISC**2).sum(axis=1))[:, None] * d
    return float(np.mean(np.abs(normals @ rotation[2]) < band))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", required=True)
    ap.add_argument("--split", default="test")
    ap.add_argument("--model", default=str(default_model_path()))
    ap.add_argument("--classifier", default=None)
    ap.add_argument("--json", default=None)
    args = ap.parse_args()

    det = OnnxDetector(args.model, OnnxDetectorConfig(threads=1), BallClassifier.from_option(args.classifier))
    folder = split_dir(args.data, args.split)
    stripes: list[tuple[float, int]] = []
    cues: list[int] = []
    for meta_path in sorted((folder / "meta").glob("*.json")):
        meta = json.loads(meta_path.read_text())
        scene = scene_of(tuple(meta["seed"]))
        band = float(scene.shade[sc.S_BAND])
        camera = np.asarray(meta["camera"]["position_m"], float)
        image = read_image_rgb(next((folder / "images").glob(meta_path.stem + ".*")))
        raw = det.detect(image)
        balls = np.isin(raw.class_id, BALL_IDS)
        for i, ball in enumerate(meta["balls"]):
            if not ball["labelled"] or ball["class"] not in ("stripe", "cue"):
                continue
            iou = box_iou(np.asarray(ball["box_px"])[None], raw.boxes[balls])[0]
            hit = iou >= 0.5
            call = int(raw.class_id[balls][hit][raw.confidence[balls][hit].argmax()]) if hit.any() else -1
            if ball["class"] == "cue":
                cues.append(call)
            else:
                share = band_share(np.asarray(scene.ball_centres[i]), scene.rotations[i], band, camera)
                stripes.append((share, call))
    share = np.array([s for s, _ in stripes])
    call = np.array([c for _, c in stripes])
    rows = []
    for lo, hi in itertools.pairwise(BUCKETS):
        sel = (share >= lo) & (share < hi) & (call >= 0)
        row = {"band_share": [lo, min(hi, 1.0)], "n": int(sel.sum())}
        row.update({CLASS_NAMES[k]: round(float(np.mean(call[sel] == k)), 3) if sel.any() else None for k in BALL_IDS})
        rows.append(row)
    cue_calls = np.array(cues)
    found = cue_calls[cue_calls >= 0]
    cue_row = {"n": len(found), **{CLASS_NAMES[k]: round(float(np.mean(found == k)), 3) for k in BALL_IDS}}
    print(f"stripes labelled {len(stripes)}, found {int((call >= 0).sum())}")
    print("| visible band share | stripes found | called stripe | cue | solid | black |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        if r["n"]:
            lo, hi = r["band_share"]
            calls = " | ".join(f"{r[k]:.2f}" for k in ("stripe", "cue", "solid", "black"))
            print(f"| {lo:.2f}-{hi:.2f} | {r['n']} | {calls} |")
    print(f"cue balls found {cue_row['n']}: called cue {cue_row['cue']:.2f}, stripe {cue_row['stripe']:.2f}")
    if args.json:
        report = {
            "data": args.data,
            "model": args.model,
            "classifier": args.classifier,
            "stripes": rows,
            "cue": cue_row,
        }
        Path(args.json).write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()

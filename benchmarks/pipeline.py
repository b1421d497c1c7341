"""Photo -> suggestion time at 1280x720 (or ``--size``) on this machine, per stage, plus the cold model load.

Uses the real detector (bundled ONNX model) and the default planner when they are present in this build;
otherwise the missing part is replaced by the stand-ins of ``pix2pockets.testing`` (exact labels / a
nearest-pocket planner) and the table says so. The photo is the bundled example (1280x720) unless ``--image`` is given;
it is resized to ``--size`` (e.g. ``4032x2268``: a 16:9 frame of a 12 MP phone photo's width).

Usage:
    PYTHONPATH=src:. python benchmarks/pipeline.py --json OUT.json [--runs 5] [--image PHOTO] [--size 1280x720]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

import cv2

from pix2pockets.data.examples import example_photo_path
from pix2pockets.pipeline import photo
from pix2pockets.pipeline.draw import render_result
from pix2pockets.synth.renderer import parse_size


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--image", help="photo to time (default: the bundled example)")
    parser.add_argument("--size", default="1280x720", help="WIDTHxHEIGHT the photo is resized to [px]")
    parser.add_argument("--json", help="write results here")
    args = parser.parse_args(argv)

    from pix2pockets.testing import ExampleLabelsDetector, NearestPocketPlanner

    notes = []
    t = time.perf_counter()
    try:
        detector = photo.default_detector()
        cold = time.perf_counter() - t
        det_name = "onnx"
    except ValueError as err:
        detector, cold, det_name = ExampleLabelsDetector(), None, "exact-labels stand-in"
        notes.append(f"detector missing ({err}); the example photo's exact labels used")
    try:
        planner = photo.default_planner()
        plan_name = type(planner).__name__
    except (ValueError, ImportError) as err:
        planner, plan_name = NearestPocketPlanner(), "nearest-pocket stand-in"
        notes.append(f"planner missing ({err}); stand-in used")

    path = args.image if args.image and det_name == "onnx" else example_photo_path()
    rgb = photo.load_image(path)
    try:
        size = parse_size(args.size)
    except ValueError as err:
        parser.error(str(err))
    if rgb.shape[:2] != size[::-1]:
        larger = size[0] * size[1] > rgb.shape[0] * rgb.shape[1]
        rgb = cv2.resize(rgb, size, interpolation=cv2.INTER_CUBIC if larger else cv2.INTER_AREA)
    source = path
    stages: dict[str, list[float]] = {}
    for _ in range(args.runs):
        t = time.perf_counter()
        res = photo.suggest(rgb, "auto", detector, planner)
        t_draw = time.perf_counter()
        render_result(rgb, res)
        res.timings["draw"] = time.perf_counter() - t_draw
        res.timings["total+draw"] = time.perf_counter() - t
        for k, v in res.timings.items():
            stages.setdefault(k, []).append(v)
    out = {
        "image": source,
        "size": [int(rgb.shape[1]), int(rgb.shape[0])],
        "detector": det_name,
        "planner": plan_name,
        "cold_model_load_s": cold,
        "runs": args.runs,
        "median_s": {k: statistics.median(v) for k, v in stages.items()},
        "notes": notes,
    }
    print(f"pipeline at {out['size'][0]}x{out['size'][1]} ({source}); detector {det_name}, planner {plan_name}")
    print(f"cold model load: {'n/a' if cold is None else f'{cold:.3f} s'}")
    print(f"{'stage':<12} {'median s':>9}")
    for k, v in out["median_s"].items():
        print(f"{k:<12} {v:9.4f}")
    for n in notes:
        print("note:", n)
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

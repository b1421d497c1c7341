"""Detector CPU latency with onnxruntime: pre-processing + network + ball refiner + ball classifier + ball-number
reader + diamond refiner + decoding + post-processing per image, on synthetic renders of common photo sizes
(640 px; 720p and 1080p frames run at the 1024 px default maximum input).

Usage:
    PYTHONPATH=src python benchmarks/detector.py [--model PATH] [--classifier PATH|none]
        [--diamond-refiner PATH|none] [--ball-refiner PATH|none] [--numbers PATH|none] [--threads 1] [--repeats 20]
        [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import time
from pathlib import Path

import numpy as np

from pix2pockets.synth.renderer import render
from pix2pockets.vision.detect.onnx_detector import (
    OnnxDetector,
    OnnxDetectorConfig,
    default_model_path,
)
from pix2pockets.vision.detect.postprocess import postprocess
from pix2pockets.vision.stages.ball_classifier import BallClassifier
from pix2pockets.vision.stages.ball_numbers import BallNumberReader
from pix2pockets.vision.stages.ball_refiner import BallRefiner
from pix2pockets.vision.stages.diamond_refiner import DiamondRefiner

SIZES = ((640, 360), (640, 480), (640, 640), (1280, 720), (1920, 1080))


def measure(detector: OnnxDetector, size: tuple[int, int], repeats: int, seed: int = 0) -> dict:
    """Median and p90 wall time [ms] of detect + postprocess on a synthetic render of ``size`` (w, h)."""
    image = np.ascontiguousarray(render((seed, 0), size).image)
    for _ in range(3):
        postprocess(detector.detect(image))
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        postprocess(detector.detect(image))
        times.append(1000 * (time.perf_counter() - t))
    times.sort()
    return {
        "image_px": list(size),
        "median_ms": round(statistics.median(times), 1),
        "p90_ms": round(times[int(0.9 * (len(times) - 1))], 1),
        "min_ms": round(times[0], 1),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", default=str(default_model_path()))
    parser.add_argument("--classifier", default=None, help="ball classifier ONNX, 'none' (default: bundled)")
    parser.add_argument("--diamond-refiner", default=None, help="diamond refiner ONNX, 'none' (default: bundled)")
    parser.add_argument("--ball-refiner", default=None, help="ball refiner ONNX, 'none' (default: bundled)")
    parser.add_argument("--numbers", default=None, help="ball-number reader ONNX, 'none' (default: bundled)")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--repeats", type=int, default=20)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    classifier = BallClassifier.from_option(args.classifier, args.threads)
    refiner = DiamondRefiner.from_option(args.diamond_refiner, args.threads)
    balls = BallRefiner.from_option(args.ball_refiner, args.threads)
    numbers = BallNumberReader.from_option(args.numbers, args.threads)
    config = OnnxDetectorConfig(threads=args.threads)
    detector = OnnxDetector(args.model, config, classifier, refiner, balls, numbers)
    rows = [measure(detector, s, args.repeats) for s in SIZES]
    clf = classifier.model_path.name if classifier else "none"
    ref = refiner.model_path.name if refiner else "none"
    ball_ref = balls.model_path.name if balls else "none"
    reader = numbers.model_path.name if numbers else "none"
    size_mb = Path(args.model).stat().st_size / 1e6
    print(
        f"model {args.model} ({size_mb:.1f} MB), classifier {clf}, diamond refiner {ref}, ball refiner {ball_ref}, "
        f"number reader {reader}, onnxruntime threads {args.threads}"
    )
    print(f"{'image px':>10} {'median ms':>10} {'p90 ms':>8} {'min ms':>8}")
    for r in rows:
        print(f"{'x'.join(map(str, r['image_px'])):>10} {r['median_ms']:>10} {r['p90_ms']:>8} {r['min_ms']:>8}")
    if args.json:
        out = {"model": args.model, "classifier": clf, "diamond_refiner": ref, "ball_refiner": ball_ref}
        out["number_reader"] = reader
        out["threads"] = args.threads
        out["machine"] = platform.machine()
        out["results"] = rows
        Path(args.json).write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()

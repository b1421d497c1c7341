"""Training-size ablation (the paper's Fig. 4a): AP50 of detectors trained on the first N training images.

Each size trains from the same seed for the same number of optimiser steps (``--steps``, so small sets are
seen many times and compute is equal), then is scored on the test split (class-wise AP50 after
post-processing, averaged over classes).

Usage:
    PYTHONPATH=src python benchmarks/detector_datasize.py --data DIR [--data DIR ...] --out DIR \
        [--eval-data DIR] [--sizes 10,20,40,80,155] [--steps 300] [--seed 0] [--json OUT.json]

``--eval-data`` (default: the first ``--data``) is the dataset whose ``--split`` scores every model.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from pix2pockets.vision.detect.onnx_detector import OnnxDetector, OnnxDetectorConfig
from pix2pockets.vision.metrics.evaluation import EvalOptions, evaluate_detector
from pix2pockets.vision.train.detector import TrainConfig, train


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, action="append", help="training dataset (repeatable)")
    parser.add_argument("--eval-data", default=None, help="dataset to score on (default: the first --data)")
    parser.add_argument("--out", required=True)
    parser.add_argument("--sizes", default="10,20,40,80,155")
    parser.add_argument("--steps", type=int, default=300, help="optimiser steps per run")
    parser.add_argument("--batch", type=int, default=8)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--split", default="test")
    parser.add_argument("--limit-eval", type=int, default=None)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    eval_data = args.eval_data or args.data[0]
    rows = []
    for n in (int(s) for s in args.sizes.split(",")):
        steps_per_epoch = max(1, n // args.batch)  # the trainer drops the last partial batch
        epochs = max(1, math.ceil(args.steps / steps_per_epoch))
        cfg = TrainConfig(
            data=tuple(args.data),
            out=str(Path(args.out) / f"n{n}"),
            epochs=epochs,
            seed=args.seed,
            batch=args.batch,
            limit=n,
        )
        onnx = train(cfg, progress=False)
        det = OnnxDetector(onnx, OnnxDetectorConfig(conf_threshold=0.01))
        rep = evaluate_detector(det, eval_data, EvalOptions(split=args.split, limit=args.limit_eval), progress=False)
        row = {
            "n_train": n,
            "epochs": epochs,
            "steps": epochs * steps_per_epoch,
            "ap50_after": rep["after"]["average"]["ap50"],
            "ap50_before": rep["before"]["average"]["ap50"],
        }
        rows.append(row)
        print(
            f"n={n:5d} epochs={epochs:4d} AP50 before {row['ap50_before']:.3f} after {row['ap50_after']:.3f}",
            flush=True,
        )
    if args.json:
        Path(args.json).write_text(
            json.dumps(
                {"data": args.data, "eval_data": eval_data, "steps": args.steps, "seed": args.seed, "rows": rows},
                indent=1,
            )
        )


if __name__ == "__main__":
    main()

"""Ball classes on the fitted table, on renders: the cue ball and the 8 claimed before or after the balls off the
table are dropped.

Renders ``--n`` scenes of each ball set (``render(seed, size, ball_set=...)``, seeds from ``--seed``), runs the bundled
detector, then ``find_table`` as ``suggest`` runs it for the set (given; a blackball set's table sized among the UK
ones), and compares each labelled ball's class with the class of the kept ball that boxes it (IoU >= 0.5; none:
missed), two ways:

- *located*: the post-processed balls that lie on the fitted table (``locate_balls``): the cue ball and the 8 are
  claimed before the balls off the table are dropped;
- *on the table*: as ``suggest`` reads them (``balls_in_play``): the raw detections off the table dropped first, then
  the cue ball and the 8 claimed among the rest.

Only renders with a table fit count; a labelled ball off the fitted table counts as missed.

Usage:
    PYTHONPATH=src python benchmarks/rendered_table_classes.py [--n 200] [--seed 7000] [--size 960x540] [--json OUT]
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")

from pix2pockets.pipeline.photo import balls_in_play, default_detector, find_table
from pix2pockets.state.ball_set import BallSet, class_name
from pix2pockets.synth.renderer import parse_size, render
from pix2pockets.vision.classes import BALL_IDS, CLASS_NAMES
from pix2pockets.vision.locate.balls import locate_balls
from pix2pockets.vision.table.fit import TableFitError
from real_ball_classes import MISSED, called_classes
from rendered_blackball import render_options, truth_of

READINGS = ("located", "on the table")


def main() -> None:
    args = render_options(__doc__, 200, "renders of each ball set")

    size = parse_size(args.size)
    detector = default_detector()
    report: dict = {"n_renders": args.n, "first_seed": args.seed, "size": list(size)}
    start = time.perf_counter()
    print(f"{'set':<10} {'reading':<13} " + " ".join(f"{'right ' + n:>13}" for n in ("cue", "8", "object")))
    for ball_set in BallSet:
        counts = {r: np.zeros((len(BALL_IDS), MISSED + 1), int) for r in READINGS}
        fitted = 0
        for k in range(args.n):
            out = render(args.seed + k, size, ball_set=ball_set.value)
            truth = truth_of(out.labels)
            raw = detector.detect(out.image)
            try:
                det, _, _, fit = find_table(out.image, raw, ball_set=ball_set)
            except TableFitError:
                continue
            fitted += 1
            readings = {
                "located": locate_balls(fit.camera, det, fit.spec).detections,
                "on the table": balls_in_play(raw, det, out.image, ball_set, fit).detections,
            }
            for reading, found in readings.items():
                np.add.at(counts[reading], (truth.class_id, called_classes(truth.boxes, found)), 1)
        report[ball_set.value] = {"fitted": fitted}
        for reading, m in counts.items():
            right = np.diag(m[:, :MISSED])
            per_class = {
                class_name(CLASS_NAMES[c], ball_set): {"balls": int(m[c].sum()), "right": int(right[c])}
                for c in BALL_IDS
            }
            report[ball_set.value][reading] = {"per_class": per_class, "confusion": m.tolist()}
            objects = right[2:].sum(), m[2:].sum()
            cells = [(right[0], m[0].sum()), (right[1], m[1].sum()), objects]
            print(f"{ball_set.value:<10} {reading:<13} " + " ".join(f"{f'{a}/{b}':>13}" for a, b in cells))
        print(f"{ball_set.value:<10} {fitted} of {args.n} renders with a table fit")
    report["seconds"] = round(time.perf_counter() - start, 1)
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=1) + "\n")


if __name__ == "__main__":
    main()

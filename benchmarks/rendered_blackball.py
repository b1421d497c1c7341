"""Blackball sets on renders: each class found (AP50), and the set read from the photo.

Renders ``--n`` scenes with a blackball set (7 reds, 7 yellows, the black, the cue ball) on UK 7- and 6-foot tables
(``render(..., ball_set="blackball")``: the renderer's pub, home and hall builds, every camera kind, players and props
as in any render), runs the bundled detector and the pipeline's post-processing for a ball set, and scores the kept
balls against the render's labels: AP50 per class (cue, black, red, yellow; reds carry the solid class id and
yellows the stripe class id, :mod:`pix2pockets.state.ball_set`), and precision / recall at the pipeline's scores.

Two readings of the set: ``--set blackball`` (the user said so) and ``auto`` (read from the balls' colours; the
share of frames read as blackball is reported, of all and of those showing at least three object balls, the fewest
the set is read from; the classes are scored as the pipeline names them).

Usage:
    PYTHONPATH=src python benchmarks/rendered_blackball.py [--n 100] [--seed 7000] [--size 960x540] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
import time
from collections import Counter

import numpy as np

from pix2pockets.pipeline.photo import clean_detections_for_set, default_detector, playing_surface
from pix2pockets.state.ball_set import class_name
from pix2pockets.synth.renderer import parse_size, render
from pix2pockets.vision.classes import BALL_IDS, CLASS_NAMES
from pix2pockets.vision.metrics.detection import GroundTruth, evaluate_classes
from pix2pockets.vision.stages.ball_colours import MIN_COLOURED_BALLS

SETS = ("blackball", "auto")
OBJECT_IDS = (CLASS_NAMES.index("solid"), CLASS_NAMES.index("stripe"))
"""Class ids of the object balls: the reds and yellows of a blackball set."""


def truth_of(labels: dict) -> GroundTruth:
    """The render's labelled balls: boxes (n, 4) [px] and class ids."""
    balls = [b for b in labels["balls"] if b["labelled"]]
    boxes = np.array([b["box_px"] for b in balls], dtype=float).reshape(-1, 4)
    return GroundTruth(boxes, np.array([b["class_id"] for b in balls], dtype=int))


def render_options(description: str, n: int, what: str = "renders", seed: int = 7000) -> argparse.Namespace:
    """The command line of a benchmark on renders: ``--n``, ``--seed``, ``--size`` and ``--json``."""
    ap = argparse.ArgumentParser(description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=n, help=f"{what} (default {n})")
    ap.add_argument("--seed", type=int, default=seed, help=f"first render seed (default {seed})")
    ap.add_argument("--size", default="960x540", help="render size WxH (default 960x540)")
    ap.add_argument("--json", default=None, help="write the results here")
    return ap.parse_args()


def main() -> None:
    args = render_options(__doc__, 100)

    size = parse_size(args.size)
    detector = default_detector()
    truths = []
    kept: dict[str, list] = {s: [] for s in SETS}
    read_as: Counter[str] = Counter()
    read_with_balls: Counter[str] = Counter()  # frames showing at least MIN_COLOURED_BALLS object balls
    start = time.perf_counter()
    for k in range(args.n):
        out = render(args.seed + k, size, ball_set="blackball")
        truths.append(truth_of(out.labels))
        raw = detector.detect(out.image)
        surface_mask = playing_surface(out.image, True)
        for ball_set in SETS:
            det, chosen = clean_detections_for_set(raw, out.image, ball_set, surface_mask)
            if ball_set == "auto":
                read_as[chosen.value] += 1
                if np.isin(truths[-1].class_id, OBJECT_IDS).sum() >= MIN_COLOURED_BALLS:
                    read_with_balls[chosen.value] += 1
                if chosen.value != "blackball":  # an American reading names no reds or yellows
                    det = det[~np.isin(det.class_id, OBJECT_IDS)]
            kept[ball_set].append(det[det.is_ball])
    seconds = time.perf_counter() - start

    with_balls = max(sum(read_with_balls.values()), 1)
    report: dict = {
        "n_renders": args.n,
        "first_seed": args.seed,
        "size": list(size),
        "read_as_blackball": round(read_as["blackball"] / args.n, 4),
        "frames_with_object_balls": sum(read_with_balls.values()),
        "read_as_blackball_with_object_balls": round(read_with_balls["blackball"] / with_balls, 4),
        "n_balls": int(sum(len(t.boxes) for t in truths)),
        "seconds": round(seconds, 1),
    }
    print(f"{args.n} blackball renders at {size[0]}x{size[1]}, {report['n_balls']} labelled balls")
    print(
        f"set read from the photo (auto): blackball in {100 * report['read_as_blackball']:.1f} % of the frames, "
        f"{100 * report['read_as_blackball_with_object_balls']:.1f} % of the {report['frames_with_object_balls']} "
        f"showing at least {MIN_COLOURED_BALLS} object balls"
    )
    header = f"{'set':10s} {'class':7s} {'balls':>6s} {'AP50':>6s} {'precision':>9s} {'recall':>7s}"
    print(header)
    print("-" * len(header))
    for ball_set in SETS:
        per = evaluate_classes(kept[ball_set], truths, BALL_IDS)
        report[ball_set] = {}
        for cid, m in per.items():
            name = class_name(CLASS_NAMES[cid], "blackball")
            report[ball_set][name] = m.as_dict()
            scores = f"{100 * m.ap50:6.1f} {100 * m.precision:9.1f} {100 * m.recall:7.1f}"
            print(f"{ball_set:10s} {name:7s} {m.n_gt:6d} {scores}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(report, fh, indent=1)


if __name__ == "__main__":
    main()

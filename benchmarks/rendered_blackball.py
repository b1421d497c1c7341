"""Blackball sets on renders: each class found (AP50), and the set read from the photo.

Renders ``--n`` scenes with a blackball set (7 reds, 7 yellows, the black, the cue ball) on UK 7- and 6-foot tables
(``render(..., ball_set="blackball")``: the renderer's pub, home and hall builds, every camera kind, players and props
as in any render), runs the bundled detector and the pipeline's post-processing for a ball set, and scores the kept
balls against the render's labels: AP50 per class (cue, black, red, yellow; reds carry the solid class id and
yellows the stripe class id, :mod:`pix2pockets.state.ball_set`), and precision / recall at the pipeline's scores.

Two readings of the set: ``--set blackball`` (the user said so) and ``auto`` (read from the balls' colours; the
share of frames read as blackball is reported, of all and of those showing at least three object balls, the fewest
the set is read from; the classes are scored as the pipeline names them).

``--misses`` lists each labelled black the ``blackball`` reading does not keep as the black (IoU >= 0.5) and each
black it keeps on no labelled black, with what the detector made of that spot: the labelled box's size and visible
share, the best-overlapping kept ball (class, IoU) and raw detection (class, score, "any ball" score, IoU), or the
labelled ball a false black lies on.

Usage:
    PYTHONPATH=src python benchmarks/rendered_blackball.py [--n 100] [--seed 7000] [--size 960x540] [--misses]
        [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
import time
from collections import Counter
from collections.abc import Callable

import numpy as np

from pix2pockets.pipeline.photo import clean_detections_for_set, default_detector, playing_surface
from pix2pockets.state.ball_set import class_name
from pix2pockets.synth.renderer import parse_size, render
from pix2pockets.vision.classes import BALL_IDS, CLASS_NAMES
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.postprocess import box_iou
from pix2pockets.vision.metrics.detection import GroundTruth, evaluate_classes
from pix2pockets.vision.stages.ball_colours import BLACK_ID, MIN_COLOURED_BALLS

SETS = ("blackball", "auto")
OBJECT_IDS = (CLASS_NAMES.index("solid"), CLASS_NAMES.index("stripe"))
"""Class ids of the object balls: the reds and yellows of a blackball set."""
MATCH_IOU = 0.5


def truth_of(labels: dict) -> GroundTruth:
    """The render's labelled balls: boxes (n, 4) [px] and class ids."""
    balls = [b for b in labels["balls"] if b["labelled"]]
    boxes = np.array([b["box_px"] for b in balls], dtype=float).reshape(-1, 4)
    return GroundTruth(boxes, np.array([b["class_id"] for b in balls], dtype=int))


def render_options(
    description: str,
    n: int,
    what: str = "renders",
    seed: int = 7000,
    more: Callable[[argparse.ArgumentParser], None] | None = None,
) -> argparse.Namespace:
    """The command line of a benchmark on renders: ``--n``, ``--seed``, ``--size``, ``--json`` and what ``more``
    adds."""
    ap = argparse.ArgumentParser(description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=n, help=f"{what} (default {n})")
    ap.add_argument("--seed", type=int, default=seed, help=f"first render seed (default {seed})")
    ap.add_argument("--size", default="960x540", help="render size WxH (default 960x540)")
    ap.add_argument("--json", default=None, help="write the results here")
    if more is not None:
        more(ap)
    return ap.parse_args()


def _best(boxes: np.ndarray, box: np.ndarray) -> tuple[int, float]:
    """Index and IoU of the box in ``boxes`` (m, 4) that overlaps ``box`` (4,) most; (-1, 0) for none."""
    if not len(boxes):
        return -1, 0.0
    iou = box_iou(box[None, :], boxes)[0]
    j = int(np.argmax(iou))
    return j, float(iou[j])


def black_misses(seed: int, labels: dict, raw: Detections, kept: Detections) -> list[dict]:
    """The labelled blacks of one render not kept as the black, and the kept blacks on no labelled black, each with
    what the detector made of its spot (see the module docstring)."""
    balls = [b for b in labels["balls"] if b["labelled"]]
    truth = truth_of(labels)
    kept_black = kept[kept.class_id == BLACK_ID]
    rows = []
    for b, box in zip(balls, truth.boxes, strict=True):
        if b["class_id"] != BLACK_ID or _best(kept_black.boxes, box)[1] >= MATCH_IOU:
            continue
        k, k_iou = _best(kept.boxes, box)
        r, r_iou = _best(raw.boxes, box)
        rows.append(
            {
                "seed": seed,
                "kind": "missed",
                "size_px": round(float(min(box[2] - box[0], box[3] - box[1])), 1),
                "visible": round(float(b.get("visible_fraction", 1.0)), 2),
                "kept": None if k < 0 else {"class": CLASS_NAMES[kept.class_id[k]], "iou": round(k_iou, 2)},
                "raw": None
                if r < 0
                else {
                    "class": CLASS_NAMES[raw.class_id[r]],
                    "score": round(float(raw.confidence[r]), 3),
                    "ball_score": round(float(raw.ball_score[r]), 3),
                    "iou": round(r_iou, 2),
                },
            }
        )
    for box, score in zip(kept_black.boxes, kept_black.confidence, strict=True):
        t, t_iou = _best(truth.boxes, box)
        if t >= 0 and truth.class_id[t] == BLACK_ID and t_iou >= MATCH_IOU:
            continue
        on = None if t < 0 or t_iou < 0.1 else {"class": CLASS_NAMES[truth.class_id[t]], "iou": round(t_iou, 2)}
        rows.append({"seed": seed, "kind": "false", "score": round(float(score), 3), "on": on})
    return rows


def main() -> None:
    args = render_options(
        __doc__, 100, more=lambda ap: ap.add_argument("--misses", action="store_true", help="list the black's misses")
    )

    size = parse_size(args.size)
    detector = default_detector()
    truths = []
    kept: dict[str, list] = {s: [] for s in SETS}
    read_as: Counter[str] = Counter()
    read_with_balls: Counter[str] = Counter()  # frames showing at least MIN_COLOURED_BALLS object balls
    misses: list[dict] = []
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
            if args.misses and ball_set == "blackball":
                misses += black_misses(args.seed + k, out.labels, raw, det[det.is_ball])
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
    if args.misses:
        print(
            f"the black's misses (--set blackball): {sum(m['kind'] == 'missed' for m in misses)} missed, "
            f"{sum(m['kind'] == 'false' for m in misses)} false"
        )
        for m in misses:
            print("  " + json.dumps(m))
        report["black_misses"] = misses
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(report, fh, indent=1)


if __name__ == "__main__":
    main()

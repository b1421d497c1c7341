"""The ball set read from renders of both sets: blackball sets read as blackball, American sets not.

Renders ``--n`` scenes of each set from ``--seed`` on (``render(..., ball_set=...)``: every build, camera kind, player
and prop the renderer draws), runs the bundled detector, the table model's playing surface and
``clean_detections_for_set(..., "auto", surface_mask)`` as ``suggest`` does, and counts the frames read as blackball,
of all and of those showing at least three object balls (the fewest the set is read from).

Usage:
    PYTHONPATH=src python benchmarks/rendered_set_reading.py [--n 200] [--seed 7000] [--size 960x540] [--json OUT.json]
"""

from __future__ import annotations

import json

import numpy as np

from pix2pockets.pipeline.photo import clean_detections_for_set, default_detector, playing_surface
from pix2pockets.synth.renderer import parse_size, render
from pix2pockets.vision.stages.ball_colours import MIN_COLOURED_BALLS
from rendered_blackball import OBJECT_IDS, render_options, truth_of


def main() -> None:
    args = render_options(__doc__, 200)
    size = parse_size(args.size)
    detector = default_detector()
    report: dict = {"n_renders": args.n, "first_seed": args.seed, "size": list(size)}
    print(f"{'set':10s} {'renders':>7s} {'read blackball':>14s} {'>= 3 object balls':>18s} {'read blackball':>14s}")
    for ball_set in ("blackball", "american"):
        read = shown = read_shown = 0
        for k in range(args.n):
            out = render(args.seed + k, size, ball_set=ball_set)
            raw = detector.detect(out.image)
            _, chosen = clean_detections_for_set(raw, out.image, "auto", playing_surface(out.image, True))
            blackball = chosen.value == "blackball"
            enough = int(np.isin(truth_of(out.labels).class_id, OBJECT_IDS).sum()) >= MIN_COLOURED_BALLS
            read += blackball
            shown += enough
            read_shown += blackball and enough
        report[ball_set] = {"read_blackball": read, "with_object_balls": shown, "read_blackball_with": read_shown}
        print(f"{ball_set:10s} {args.n:7d} {read:14d} {shown:18d} {read_shown:14d}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(report, fh, indent=1)


if __name__ == "__main__":
    main()

"""Check the ``paper`` simulator against a pymunk re-creation of the paper's environment world.

The re-creation (:mod:`pix2pockets.physics.paper.reference`) steps the paper's pymunk world itself. Both
simulators play the same strokes from the paper's start layouts; the script reports how often they
agree on the first ball hit and on the set of pocketed balls, and the distribution of final-position
differences.

    python benchmarks/paper_pymunk_check.py --shots 300 --json benchmarks/results/paper-pymunk-check.json
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

from pix2pockets.geometry.raster import PAPER_LAYOUT
from pix2pockets.physics import make_simulator
from pix2pockets.physics.paper import PAPER_PX, paper_level_speed
from pix2pockets.physics.paper.reference import pymunk_shot
from pix2pockets.planner.paper_protocol import PAPER_SEED_BASE, paper_start_layout
from pix2pockets.state import Shot


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--shots", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", help="write the summary as JSON")
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    sim = make_simulator("paper")
    sim.simulate(paper_start_layout(PAPER_SEED_BASE), Shot(angle=0.0, speed=0.5))  # load the compiled kernel
    agree_first = agree_pots = 0
    dists: list[float] = []
    t_pm = t_ours = 0.0
    for s in range(args.shots):
        layout = paper_start_layout(PAPER_SEED_BASE + s)
        cue = layout.cue_index
        level = int(rng.integers(1, 31))
        target = int(rng.integers(0, len(layout) - 1))
        d = layout.positions[target] - layout.positions[cue]
        angle = math.atan2(d[1], d[0]) + rng.normal(0.0, 0.05)
        speed = paper_level_speed(level)
        t0 = time.process_time()
        res = sim.simulate(layout, Shot(angle=angle, speed=speed))
        t_ours += time.process_time() - t0
        uv = PAPER_LAYOUT.from_table(layout.positions)
        t0 = time.process_time()
        pots, final_uv, first, _ = pymunk_shot(uv, cue, -angle, speed / PAPER_PX)  # pixels: v down
        t_pm += time.process_time() - t0
        ours_pots = dict(zip(res.pocketed, res.pocketed_into, strict=True))
        pots = {b: k for b, (k, _) in pots.items()}
        agree_first += (res.first_contact if res.first_contact is not None else -1) == first
        same = ours_pots == pots
        agree_pots += same
        if same:
            ours_uv = PAPER_LAYOUT.from_table(res.final.positions)
            theirs = final_uv[list(res.final_ids)]
            dists.extend(np.hypot(*(ours_uv - theirs).T).tolist())
    d = np.array(dists) if dists else np.zeros(1)
    summary = {
        "shots": args.shots,
        "first_contact_agree": agree_first / args.shots,
        "pocketed_agree": agree_pots / args.shots,
        "final_position_diff_px_median": float(np.median(d)),
        "final_position_diff_px_p90": float(np.percentile(d, 90)),
        "final_position_within_1px": float(np.mean(d < 1.0)),
        "pymunk_s_per_shot": t_pm / args.shots,
        "paper_s_per_shot": t_ours / args.shots,
    }
    print(json.dumps(summary, indent=2))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(summary, f, indent=2)


if __name__ == "__main__":
    main()

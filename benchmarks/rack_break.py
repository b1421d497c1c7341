"""Breaks of the standard rack in the event physics: how often a ball drops, by cue-ball speed.

The cue ball on the head spot is sent full at the apex ball of ``eight_ball_rack()`` ``--breaks`` times per speed,
its direction jittered by a Gaussian of ``--angle-sigma`` [rad] (seeded); with ``--hand-racked`` each break gets its
own triangle racked by hand (``pipeline.break_shot.hand_racked``: neighbours a fifth of a millimetre apart, as balls
made to their tolerance lie), else the perfect one. The share of breaks that pocket an
object ball, the object balls pocketed per break and the share that pocket the cue ball are printed per speed. Real
breaks pot more the harder they are hit; this tells whether the physics can give a break a chance
(``pipeline/break_shot.py``).

Usage:
    PYTHONPATH=src python benchmarks/rack_break.py [--speeds 4,6,8,10] [--breaks 60] [--angle-sigma 0.003]
        [--hand-racked] [--seed 0] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

from pix2pockets.physics.event.simulator import EventSimulator
from pix2pockets.pipeline.break_shot import hand_racked
from pix2pockets.state import Shot, eight_ball_rack


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--speeds", default="4,6,8,10", help="cue-ball speeds [m/s], comma-separated")
    ap.add_argument("--breaks", type=int, default=60, help="breaks per speed")
    ap.add_argument("--angle-sigma", type=float, default=0.003, help="aim jitter [rad]")
    ap.add_argument("--hand-racked", action="store_true", help="rack each break by hand (tenths of a mm apart)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", default=None)
    args = ap.parse_args()

    rack = eight_ball_rack(rng=np.random.default_rng(args.seed))
    cue, apex = rack.positions[rack.cue_index], rack.positions[1]
    aim = math.atan2(float(apex[1] - cue[1]), float(apex[0] - cue[0]))
    sim = EventSimulator()
    rng = np.random.default_rng(args.seed)
    rows = []
    print(f"{'speed m/s':>9} {'a ball pocketed':>15} {'balls per break':>15} {'cue ball pocketed':>17}")
    for speed in (float(v) for v in args.speeds.split(",")):
        potted = balls = scratched = 0
        for _ in range(args.breaks):
            racked = hand_racked(rack, rng) if args.hand_racked else rack
            result = sim.simulate(racked, Shot(angle=aim + rng.normal(0.0, args.angle_sigma), speed=speed))
            dropped = sum(i != rack.cue_index for i in result.pocketed)
            potted += dropped > 0
            balls += dropped
            scratched += bool(result.cue_pocketed)
        row = {"speed_mps": speed, "potted": potted / args.breaks, "balls_per_break": balls / args.breaks}
        rows.append({**row, "cue_pocketed": scratched / args.breaks})
        print(f"{speed:9.1f} {potted / args.breaks:15.1%} {balls / args.breaks:15.2f} {scratched / args.breaks:17.1%}")
    if args.json:
        with open(args.json, "w") as fh:
            options = {"breaks": args.breaks, "angle_sigma": args.angle_sigma, "hand_racked": args.hand_racked}
            json.dump({**options, "seed": args.seed, "rows": rows}, fh)


if __name__ == "__main__":
    main()

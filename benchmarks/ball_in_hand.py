"""Ball in hand: where the cue ball is put, against a coarse grid of spots.

Each of ``--racks`` layouts of our protocol (16 balls, solids, the cue ball taken off) gets its cue ball placed
anywhere on the table by :func:`pix2pockets.planner.ball_in_hand.best_placement`, once from the straight-in spots of
the likeliest pots (shipped) and once from the free spots nearest a 4 x 2 grid over the table, both with the default
search planner (no time budget). Per method: the first shot's chance measured over ``--samples`` noisy executions of
the skill's noise (:func:`pix2pockets.planner.chance.measure_chance`), the turn played from there under the same
noise (full-turn clear), and the placement time on one core.

Usage:
    OMP_NUM_THREADS=1 PYTHONPATH=src python benchmarks/ball_in_hand.py [--racks 150] [--seed 0] [--skill pro]
        [--samples 200] [--json OUT.json]
"""

from __future__ import annotations

import json
import os
import time

import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")

from _racks import rack_parser, rack_setup
from pix2pockets.planner.ball_in_hand import best_placement, grid_spots
from pix2pockets.planner.chance import measure_chance
from pix2pockets.planner.evaluation import play_turn

METHODS = ("straight-in spots", "4 x 2 grid")


def main(argv: list[str] | None = None) -> int:
    ap = rack_parser(__doc__, 150)
    ap.add_argument("--samples", type=int, default=200, help="noisy executions behind each first shot's chance")
    args = ap.parse_args(argv)

    planner, noise, sim, proto = rack_setup(args.skill)
    rows = {m: {"chance": [], "cleared": [], "seconds": []} for m in METHODS}
    for i in range(args.racks):
        full = proto.layout(16, args.seed, i)
        layout = full.without([full.cue_index])
        for method in METHODS:
            spots = None if method == METHODS[0] else grid_spots(layout)
            t = time.perf_counter()
            placed, top = best_placement(
                layout, planner, proto.state, np.random.default_rng([args.seed, i]), spots=spots
            )
            rows[method]["seconds"].append(time.perf_counter() - t)
            chance = measure_chance(
                planner, placed, proto.state, top.shot, noise, args.samples, np.random.default_rng([args.seed, i, 2])
            )
            rows[method]["chance"].append(chance.p)
            turn = play_turn(
                placed,
                proto.state,
                planner,
                sim.simulate,
                noise,
                np.random.default_rng([args.seed, i, 1]),
                judge=proto.judge,
                success=proto.success,
            )
            rows[method]["cleared"].append(bool(turn.cleared))
        if (i + 1) % 25 == 0:
            print(f"{i + 1} racks", flush=True)

    summary = {}
    print(f"{'placement':<20} {'first-shot chance':>18} {'full-turn clear':>16} {'placement s':>12}")
    for method, r in rows.items():
        summary[method] = {
            "first_shot_chance_mean": float(np.mean(r["chance"])),
            "full_turn_clear": float(np.mean(r["cleared"])),
            "placement_seconds_median": float(np.median(r["seconds"])),
        }
        s = summary[method]
        print(
            f"{method:<20} {100 * s['first_shot_chance_mean']:>17.1f}% {100 * s['full_turn_clear']:>15.1f}% "
            f"{s['placement_seconds_median']:>12.2f}"
        )
    a, b = (np.array(rows[m]["chance"]) for m in METHODS)
    wins = int(np.sum(a > b)), int(np.sum(b > a))
    print(f"first shot likelier: from the straight-in spots on {wins[0]} racks, from the grid on {wins[1]}")
    if args.json:
        doc = {"racks": args.racks, "seed": args.seed, "skill": args.skill, "samples": args.samples, "methods": summary}
        doc["first_shot_likelier"] = dict(zip(METHODS, wins, strict=True))
        with open(args.json, "w") as f:
            json.dump(doc, f, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

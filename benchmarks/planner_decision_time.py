"""Decision time of the planners on full racks (16 balls at random spots), one core.

Usage::

    OMP_NUM_THREADS=1 PYTHONPATH=src python benchmarks/planner_decision_time.py --layouts 50 --json out.json
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from pix2pockets.planner.evaluation import environment_state, sample_environment
from pix2pockets.planner.registry import make_planner


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--layouts", type=int, default=50)
    parser.add_argument("--planners", nargs="+", default=["oracle", "oracle-mirror", "search"])
    parser.add_argument("--time-budget", type=float, default=0.5, help="search time budget [s] (0.5)")
    parser.add_argument("--skill", default="pro", help="the noise the search plans for (pro, club, beginner)")
    parser.add_argument("--json", metavar="OUT.json")
    args = parser.parse_args()
    state = environment_state(16)
    layouts = [sample_environment(16, np.random.default_rng([0, i, 0])) for i in range(args.layouts)]
    rows = {}
    for name in args.planners:
        planner = make_planner(name, noise=args.skill, time_budget=args.time_budget)
        planner.suggest(layouts[0], state, np.random.default_rng(0))  # warm-up (JIT, caches)
        times, cpu = [], []
        for i, lay in enumerate(layouts):
            t0, c0 = time.perf_counter(), time.process_time()
            planner.suggest(lay, state, np.random.default_rng(i))
            times.append(time.perf_counter() - t0)
            cpu.append(time.process_time() - c0)
        t = np.array(times) * 1000
        c = np.array(cpu) * 1000
        rows[name] = {
            "mean_ms": t.mean(),
            "median_ms": np.median(t),
            "p95_ms": np.percentile(t, 95),
            "max_ms": t.max(),
            "cpu_mean_ms": c.mean(),
            "cpu_max_ms": c.max(),
        }
    print(f"full-rack decision time, {args.layouts} layouts, skill {args.skill} (ms)")
    print(f"{'planner':<16}{'mean':>9}{'median':>9}{'p95':>9}{'max':>9}{'cpu mean':>10}{'cpu max':>9}")
    for name, r in rows.items():
        print(
            f"{name:<16}{r['mean_ms']:9.1f}{r['median_ms']:9.1f}{r['p95_ms']:9.1f}{r['max_ms']:9.1f}"
            f"{r['cpu_mean_ms']:10.1f}{r['cpu_max_ms']:9.1f}"
        )
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(
                {"layouts": args.layouts, "time_budget_s": args.time_budget, "skill": args.skill, "planners": rows},
                f,
                indent=2,
            )


if __name__ == "__main__":
    main()

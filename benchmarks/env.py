"""Environment throughput: env steps per second with random actions, per variant and backend.

Usage:
    PYTHONPATH=src python benchmarks/env.py [--steps 200] [--physics pymunk event] [--json OUT.json]

Each variant (1-ball, 2-ball, all-ball x discrete/continuous) runs ``--steps`` random steps on one core
(resetting on termination; reset time included). ``--masks`` also times ``action_masks()``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np

from pix2pockets.env.pool_env import PoolEnv
from pix2pockets.physics import available_simulators

VARIANTS = [("one", "discrete"), ("two", "discrete"), ("all", "discrete"), ("all", "continuous")]


def bench_variant(balls: str, action_type: str, physics: str, steps: int, masks: bool, seed: int = 0) -> dict:
    env = PoolEnv(balls=balls, action_type=action_type, physics=physics)
    env.reset(seed=seed)
    env.action_space.seed(seed)
    episodes = 0
    mask_time = 0.0
    t0 = time.perf_counter()
    for _ in range(steps):
        if masks:
            tm = time.perf_counter()
            env.action_masks()
            mask_time += time.perf_counter() - tm
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            episodes += 1
            env.reset()
    elapsed = time.perf_counter() - t0
    out = {
        "steps": steps,
        "episodes": episodes,
        "seconds": round(elapsed, 3),
        "steps_per_s": round(steps / elapsed, 2),
    }
    if masks:
        out["mask_ms"] = round(1000 * mask_time / steps, 3)
        out["steps_per_s_without_masks"] = round(steps / (elapsed - mask_time), 2)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200, help="random steps per variant (default 200)")
    parser.add_argument("--physics", nargs="+", default=None, help="backends (default: all available)")
    parser.add_argument("--masks", action="store_true", help="also time action_masks() (discrete variants)")
    parser.add_argument("--json", type=Path, default=None, help="write the results to this JSON file")
    args = parser.parse_args(argv)
    if args.steps < 1:
        print("error: --steps must be >= 1", file=sys.stderr)
        return 2
    backends = args.physics or available_simulators()
    unknown = [b for b in backends if b not in available_simulators()]
    if unknown:
        print(f"error: unknown backend(s) {unknown}; available: {available_simulators()}", file=sys.stderr)
        return 2
    results: dict = {"backends": {}, "steps": args.steps, "machine": platform.processor() or platform.machine()}
    print(f"{'backend':8} {'variant':18} {'steps/s':>9} {'episodes':>9} {'mask ms':>8}")
    for physics in backends:
        results["backends"][physics] = {}
        # warm-up (JIT compilation / caches) outside the timing
        PoolEnv(balls="two", physics=physics).reset(seed=0)
        warm = PoolEnv(balls="two", physics=physics)
        warm.reset(seed=0)
        warm.step(np.array([100, 5]))
        for balls, action_type in VARIANTS:
            masks = args.masks and action_type == "discrete"
            r = bench_variant(balls, action_type, physics, args.steps, masks)
            name = f"{balls}-{action_type}"
            results["backends"][physics][name] = r
            mask_ms = r.get("mask_ms", float("nan"))
            print(f"{physics:8} {name:18} {r['steps_per_s']:9.1f} {r['episodes']:9d} {mask_ms:8.2f}")
    if args.json:
        tmp = args.json.with_name(args.json.name + ".tmp")
        tmp.write_text(json.dumps(results, indent=2) + "\n")
        os.replace(tmp, args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

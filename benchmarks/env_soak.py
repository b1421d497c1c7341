"""Soak test: many random steps over every environment variant, checking invariants after each step.

Usage:
    PYTHONPATH=src python benchmarks/env_soak.py --steps 1000000 [--physics event] [--json OUT.json]

Checks after every step: no exception, observation finite and inside the observation space, reward
finite and in [-1, 1], no two balls overlapping (beyond 1 micrometre), every ball centre on the playing
surface (a ball radius inside the cushion noses). Variants rotate every ``--chunk`` steps; execution noise
is on for half of them. Prints the count of steps and failures; exits non-zero on any failure.
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import sys
import time
import traceback
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np

from pix2pockets.env.pool_env import PoolEnv
from pix2pockets.state import TableLayout

TOL = 1e-6  # [m]


def check_layout(layout: TableLayout) -> str | None:
    """A description of what is wrong with ``layout``, or ``None``."""
    pos = layout.positions
    spec = layout.spec
    r = spec.ball_radius
    if not np.all(np.isfinite(pos)):
        return "non-finite ball position"
    if not np.all(spec.contains(pos, margin=r - TOL)):
        return "ball off the playing surface"
    if len(pos) > 1:
        d = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
        d[np.diag_indices(len(pos))] = np.inf
        if d.min() < 2 * r - TOL:
            return f"overlap {1000 * (2 * r - d.min()):.3f} mm"
    return None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=10_000, help="total random steps (default 10000)")
    parser.add_argument("--physics", default=None, help="backend (default: the environment default)")
    parser.add_argument("--chunk", type=int, default=1000, help="steps per variant before rotating")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", type=Path, default=None, help="write a summary JSON here")
    parser.add_argument("--progress", type=int, default=50_000, help="print progress every N steps")
    args = parser.parse_args(argv)
    if args.steps < 1 or args.chunk < 1:
        print("error: --steps and --chunk must be >= 1", file=sys.stderr)
        return 2
    variants = list(
        itertools.product(["one", "two", "all"], ["discrete", "continuous"], ["turn", "shot"], [False, True])
    )
    envs: dict = {}
    counts = {"steps": 0, "episodes": 0, "failures": 0, "pocketed": 0}
    failures: list[str] = []
    rng = np.random.default_rng(args.seed)
    t0 = time.perf_counter()
    step = 0
    k = 0
    while step < args.steps:
        balls, action_type, mode, noisy = variants[k % len(variants)]
        k += 1
        key = (balls, action_type, mode, noisy)
        if key not in envs:
            kw = {"aim_noise_deg": 0.5, "speed_noise": 0.1} if noisy else {}
            if args.physics:
                kw["physics"] = args.physics
            env = PoolEnv(balls=balls, action_type=action_type, mode=mode, sim_errors="raise", **kw)
            env.reset(seed=int(rng.integers(2**31)))
            env.action_space.seed(int(rng.integers(2**31)))
            envs[key] = env
        env = envs[key]
        for _ in range(min(args.chunk, args.steps - step)):
            step += 1
            action = env.action_space.sample()
            before = env.unwrapped.layout
            try:
                obs, reward, terminated, truncated, info = env.step(action)
                problem = None
                if not np.all(np.isfinite(obs)) or not env.observation_space.contains(obs):
                    problem = "observation outside the space"
                elif not np.isfinite(reward) or abs(reward) > 1.0 + 1e-9:
                    problem = f"reward {reward}"
                else:
                    problem = check_layout(env.unwrapped.layout)
                counts["pocketed"] += info["pocketed"]
                if problem:
                    raise RuntimeError(problem)
                if terminated or truncated:
                    counts["episodes"] += 1
                    env.reset()
            except Exception as err:  # a soak test counts every failure and keeps going
                counts["failures"] += 1
                if len(failures) < 20:
                    repro = {"numbers": [b.number for b in before.balls], "positions": before.positions.tolist()}
                    repro["action"] = np.asarray(action).tolist()
                    trace = traceback.format_exc(limit=3)
                    failures.append(f"{key}: {err!r}\nrepro (exact floats): {json.dumps(repro)}\n{trace}")
                env.reset()
            counts["steps"] = step
            if step % args.progress == 0:
                rate = step / (time.perf_counter() - t0)
                print(f"{step} steps, {counts['failures']} failures, {rate:.0f} steps/s", flush=True)
                _write(args.json, _summary(counts, envs, t0, step, args.steps), failures)
    summary = _summary(counts, envs, t0, step, args.steps)
    print(json.dumps(summary))
    for f in failures:
        print(f, file=sys.stderr)
    _write(args.json, summary, failures)
    return 1 if counts["failures"] else 0


def _summary(counts: dict, envs: dict, t0: float, step: int, target: int) -> dict:
    elapsed = time.perf_counter() - t0
    summary = {**counts, "target_steps": target, "complete": step >= target}
    summary.update(seconds=round(elapsed, 1), steps_per_s=round(step / elapsed, 1))
    summary["physics"] = next(iter(envs.values())).simulator.name
    summary["variants"] = len(envs)
    return summary


def _write(path: Path | None, summary: dict, failures: list[str]) -> None:
    """Write the summary atomically (also as progress, so an interrupted run leaves its count)."""
    if path is None:
        return
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps({**summary, "first_failures": failures}, indent=2) + "\n")
    os.replace(tmp, path)


if __name__ == "__main__":
    raise SystemExit(main())

"""Physics throughput: shots per second on one core, per backend and scenario, plus JIT warm-up.

Usage:
    PYTHONPATH=src python benchmarks/physics.py [--shots 2000] [--max-seconds 20] [--backends event pymunk]
                                                [--no-cold] [--json OUT.json]

Scenarios (seeded, the same shots for every backend):
    scattered16: 16 balls at random spots, a medium-speed (2-3 m/s) shot at a random object ball with a
                 little random tip offset;
    two_ball:    the cue ball and one object ball at random spots, the same kind of shot;
    break:       the 8-ball rack, cue ball on the head spot, a full-speed (9-11 m/s) break at the apex.

``shots_per_s`` times ``simulate`` (a full ``ShotResult`` with every event) per CPU second of this
single-threaded process (``time.process_time``: one core's worth of work, robust on a shared, loaded
machine); ``wall_shots_per_s`` is the same per wall-clock second. For backends with the lean batch API
(``simulate_arrays``, the planner's hot path) ``batch_shots_per_s`` times that too. Warm-up:
``first_call_s`` is the first shot in this process (numba cache load, or compile if no cache), and unless
``--no-cold`` the event backend's cold start is measured in fresh processes with an empty numba cache
(``cold_compile_s``: import + first shot including the full JIT compile) and then with that cache warm
(``cached_start_s``: import + first shot).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np

from pix2pockets.physics import available_simulators, make_simulator
from pix2pockets.state import Shot, TableLayout, eight_ball_rack, random_layout

SCENARIOS = ("scattered16", "two_ball", "break")


def make_cases(scenario: str, count: int, seed: int = 0) -> list[tuple[TableLayout, Shot]]:
    """``count`` seeded (layout, shot) pairs for a scenario."""
    rng = np.random.default_rng(seed)
    cases = []
    for _ in range(count):
        if scenario == "break":
            layout = eight_ball_rack(rng=rng)
            cue, apex = layout.positions[0], layout.positions[1]
            angle = math.atan2(apex[1] - cue[1], apex[0] - cue[0]) + rng.normal(0.0, math.radians(0.3))
            cases.append((layout, Shot(angle=angle, speed=rng.uniform(9.0, 11.0))))
            continue
        numbers = list(range(16)) if scenario == "scattered16" else [0, int(rng.integers(1, 16))]
        layout = random_layout(rng, numbers)
        target = int(rng.integers(1, len(layout)))
        d = layout.positions[target] - layout.positions[0]
        angle = math.atan2(d[1], d[0]) + rng.normal(0.0, 0.01)
        tip = rng.uniform(-0.2, 0.2, 2)
        cases.append((layout, Shot(angle=angle, speed=rng.uniform(2.0, 3.0), side=tip[0], height=tip[1])))
    return cases


def bench(backend: str, scenario: str, cases, max_seconds: float) -> dict:
    """Shots per second for one backend on one scenario."""
    sim = make_simulator(backend)
    t0 = time.perf_counter()
    sim.simulate(*cases[0])
    first_call = time.perf_counter() - t0
    done = 0
    events = 0
    t0, c0 = time.perf_counter(), time.process_time()
    for layout, shot in cases:
        events += len(sim.simulate(layout, shot).events)
        done += 1
        if time.perf_counter() - t0 > max_seconds:
            break
    elapsed, cpu = time.perf_counter() - t0, time.process_time() - c0
    out = {
        "shots": done,
        "cpu_seconds": round(cpu, 3),
        "shots_per_s": round(done / cpu, 1),
        "wall_shots_per_s": round(done / elapsed, 1),
        "events_per_shot": round(events / done, 1),
        "first_call_s": round(first_call, 3),
    }
    if hasattr(sim, "simulate_arrays"):
        sim.simulate_arrays(cases[0][0], [cases[0][1]])  # load/compile the batch kernel
        # the planner's pattern: many strokes from one layout; here blocks of 10 strokes per layout
        block = 10
        t0, c0 = time.perf_counter(), time.process_time()
        n_batch = 0
        for k in range(0, len(cases), block):
            chunk = cases[k : k + block]
            strokes = [s for _, s in chunk]
            for layout, _ in chunk:
                sim.simulate_arrays(layout, strokes)
                n_batch += len(strokes)
            if time.perf_counter() - t0 > max_seconds:
                break
        out["batch_shots_per_s"] = round(n_batch / (time.process_time() - c0), 1)
        out["batch_wall_shots_per_s"] = round(n_batch / (time.perf_counter() - t0), 1)
    return out


_COLD_SNIPPET = """
import time
t0 = time.perf_counter()
c0 = time.process_time()
from pix2pockets.physics import make_simulator
from pix2pockets.state import Shot, eight_ball_rack
sim = make_simulator("event")
sim.simulate(eight_ball_rack(), Shot(angle=0.0, speed=5.0))
sim.simulate_arrays(eight_ball_rack(), [Shot(angle=0.0, speed=5.0)])
print(time.perf_counter() - t0, time.process_time() - c0)
"""


def cold_start() -> dict:
    """Import + first shot of the event backend in fresh processes: empty numba cache, then warm."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=str(Path(__file__).resolve().parents[1] / "src"))
        times = []
        for _ in range(2):
            t0 = time.perf_counter()
            proc = subprocess.run([sys.executable, "-c", _COLD_SNIPPET], env=env, capture_output=True, text=True)
            wall = time.perf_counter() - t0
            if proc.returncode != 0:
                raise RuntimeError(f"cold-start probe failed: {proc.stderr.strip().splitlines()[-1:]}")
            elapsed, cpu = (float(x) for x in proc.stdout.split())
            times.append((elapsed, cpu, wall))
    return {
        "cold_compile_s": round(times[0][0], 2),
        "cold_compile_cpu_s": round(times[0][1], 2),
        "cached_start_s": round(times[1][0], 2),
        "cached_start_cpu_s": round(times[1][1], 2),
        "cached_process_wall_s": round(times[1][2], 2),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shots", type=int, default=2000, help="shots per scenario (default 2000)")
    parser.add_argument("--max-seconds", type=float, default=20.0, help="time cap per backend and scenario")
    parser.add_argument("--backends", nargs="+", default=None, help="default: all registered backends")
    parser.add_argument("--scenarios", nargs="+", default=list(SCENARIOS), choices=SCENARIOS)
    parser.add_argument("--no-cold", action="store_true", help="skip the cold-start (empty JIT cache) probe")
    parser.add_argument("--json", type=Path, default=None, help="write results to this JSON file")
    args = parser.parse_args(argv)
    backends = args.backends or available_simulators()
    unknown = sorted(set(backends) - set(available_simulators()))
    if unknown:
        print(f"error: unknown backend(s) {unknown}; available: {available_simulators()}", file=sys.stderr)
        return 2
    if args.shots < 1 or args.max_seconds <= 0:
        print("error: --shots must be >= 1 and --max-seconds > 0", file=sys.stderr)
        return 2

    results: dict = {"backends": {b: {} for b in backends}}
    for scenario in args.scenarios:
        cases = make_cases(scenario, args.shots)
        for backend in backends:
            results["backends"][backend][scenario] = bench(backend, scenario, cases, args.max_seconds)
    if "event" in backends and not args.no_cold:
        results["warmup"] = {"event": cold_start()}
    if "event" in backends and "pymunk" in backends:
        ratios = {}
        for scenario in args.scenarios:
            ev, pm = results["backends"]["event"][scenario], results["backends"]["pymunk"][scenario]
            ratios[scenario] = {"simulate": round(ev["shots_per_s"] / pm["shots_per_s"], 1)}
            if "batch_shots_per_s" in ev:
                ratios[scenario]["batch"] = round(ev["batch_shots_per_s"] / pm["shots_per_s"], 1)
        results["event_over_pymunk"] = ratios
    results["machine"] = {
        "python": platform.python_version(),
        "processor": platform.processor() or platform.machine(),
        "cpus": os.cpu_count(),
        "load_avg_1min": round(os.getloadavg()[0], 2) if hasattr(os, "getloadavg") else None,
    }

    header = f"{'backend':8s} {'scenario':12s} {'shots/s':>9s} {'batch/s':>9s} {'events':>7s} {'first call s':>12s}"
    print(header)
    print("-" * len(header))
    for backend in backends:
        for scenario in args.scenarios:
            r = results["backends"][backend][scenario]
            batch = f"{r['batch_shots_per_s']:9.0f}" if "batch_shots_per_s" in r else f"{'-':>9s}"
            print(
                f"{backend:8s} {scenario:12s} {r['shots_per_s']:9.1f} {batch} {r['events_per_shot']:7.1f} "
                f"{r['first_call_s']:12.3f}"
            )
    if "event_over_pymunk" in results:
        for scenario, ratio in results["event_over_pymunk"].items():
            print(f"event / pymunk on {scenario}: {ratio}")
    if "warmup" in results:
        print(f"event warm-up (fresh processes): {results['warmup']['event']}")
    if args.json:
        tmp = args.json.with_name(args.json.name + ".tmp")
        tmp.write_text(json.dumps(results, indent=2) + "\n")
        os.replace(tmp, args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

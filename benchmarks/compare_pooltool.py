"""Compare the event backend with pooltool on the same random shots (optional; pooltool is not a dependency).

Usage:
    PYTHONPATH=src python benchmarks/compare_pooltool.py [--shots 300] [--ball-friction] [--json OUT.json]
                                                         --pooltool-python venv-pooltool/bin/python

pooltool 0.6.0 lives in its own venv (see docs/benchmarks-physics.md for the install). Both engines get
the same layouts and the same initial cue-ball velocity and spin (our strike model; pooltool's cue strike
is bypassed), the same ball constants (friction, restitution, spin friction) and the simplest matching
collision models in pooltool: frictionless inelastic ball-ball (``FrictionalInelastic`` with zero
friction, ``e_b`` = 0.95; with ``--ball-friction`` its Alciatore friction fit, which ours follows then) and
``impulse_frictional_inelastic`` cushions. The tables differ in pocket
shape: pooltool models jaws as circular arcs and its own pocket circles; we use straight jaw faces and
capture circles, with the same mouth widths.

Reported: how often the pocketed sets agree, how far final centres of balls on the table in both differ,
and the CPU time per shot of each engine.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from pix2pockets.physics.event import EventSimulator, PhysicsParams
from pix2pockets.physics.event._motion import strike
from pix2pockets.physics.event.params import SPIN_FRICTION_PER_METRE
from pix2pockets.state import Shot, random_layout


def make_cases(count: int, seed: int) -> list[tuple]:
    rng = np.random.default_rng(seed)
    cases = []
    for k in range(count):
        numbers = list(range(16)) if k % 2 == 0 else [0, int(rng.integers(1, 16))]
        layout = random_layout(rng, numbers)
        target = int(rng.integers(1, len(layout)))
        d = layout.positions[target] - layout.positions[0]
        angle = math.atan2(d[1], d[0]) + rng.normal(0.0, 0.01)
        tip = rng.uniform(-0.2, 0.2, 2)
        cases.append((layout, Shot(angle=angle, speed=rng.uniform(1.0, 3.0), side=tip[0], height=tip[1])))
    return cases


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shots", type=int, default=300)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--pooltool-python", required=True, help="python of a venv with pooltool installed")
    parser.add_argument(
        "--ball-friction",
        action="store_true",
        help="friction between the balls in both engines (ours: PhysicsParams(ball_friction=True); pooltool: "
        "FrictionalInelastic with its AlciatoreBallBallFriction defaults, the same fit)",
    )
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    if not Path(args.pooltool_python).exists():
        print(f"error: no pooltool interpreter at {args.pooltool_python}", file=sys.stderr)
        return 2

    params = PhysicsParams(ball_friction=args.ball_friction)
    sim = EventSimulator(params)
    cases = make_cases(args.shots, args.seed)
    spec = cases[0][0].spec
    prm = params.packed(spec.ball_radius, spec.cushion_height)
    payload = {
        "length": spec.length,
        "width": spec.width,
        "R": spec.ball_radius,
        "corner_mouth": spec.corner_mouth,
        "side_mouth": spec.side_mouth,
        "ball_friction": args.ball_friction,
        "params": {
            "m": spec.ball_mass,
            "mu_slide": params.mu_slide,
            "mu_roll": params.mu_roll,
            "spin_per_metre": SPIN_FRICTION_PER_METRE,
            "e_ball": params.e_ball,
            "e_cushion": params.e_cushion,
            "mu_cushion": params.mu_cushion,
            "g": params.g,
        },
        "cases": [],
    }
    ours = []
    sim.simulate(*cases[0])  # load the JIT cache before timing
    cpu_ours = []
    for layout, shot in cases:
        vel, w = np.zeros((1, 2)), np.zeros((1, 3))
        strike(0, shot.angle, shot.speed, shot.side, shot.height, shot.elevation, vel, w, prm)
        payload["cases"].append({"xy": layout.positions.tolist(), "cue": [*vel[0].tolist(), *w[0].tolist()]})
        c0 = time.process_time()
        res = sim.simulate(layout, shot)
        cpu_ours.append(time.process_time() - c0)
        final = np.array(layout.positions, dtype=float)
        final[list(res.final_ids)] = res.final.positions
        ours.append((set(res.pocketed), final))

    with tempfile.TemporaryDirectory() as tmp:
        src, dst = Path(tmp) / "in.json", Path(tmp) / "out.json"
        src.write_text(json.dumps(payload))
        env = dict(os.environ, HOME=tmp, OMP_NUM_THREADS="1")  # pooltool writes ~/.config/pooltool
        t0 = time.perf_counter()
        worker = Path(__file__).with_name("_pooltool_worker.py")
        proc = subprocess.run([args.pooltool_python, str(worker), str(src), str(dst)], env=env, capture_output=True)
        wall = time.perf_counter() - t0
        if proc.returncode != 0:
            print(f"error: pooltool worker failed: {proc.stderr.decode()[-2000:]}", file=sys.stderr)
            return 1
        theirs = json.loads(dst.read_text())

    agree, errors, diffs, moved_diffs, per_shot_max = 0, 0, [], [], []
    cpu_theirs = [other["cpu_s"] for other in theirs][1:]  # the first shot includes loading its JIT cache
    for (layout, _), (our_pocketed, our_final), other in zip(cases, ours, theirs, strict=True):
        if other["error"]:
            errors += 1
            continue
        their_pocketed = set(other["pocketed"])
        agree += our_pocketed == their_pocketed
        both = [k for k in range(len(our_final)) if k not in our_pocketed and k not in their_pocketed]
        their_final = np.array(other["final"])
        d = np.linalg.norm(our_final[both] - their_final[both], axis=1)
        diffs.extend(d.tolist())
        start = layout.positions[both]
        moved = (np.linalg.norm(our_final[both] - start, axis=1) > 1e-9) | (
            np.linalg.norm(their_final[both] - start, axis=1) > 1e-9
        )
        moved_diffs.extend(d[moved].tolist())
        per_shot_max.append(float(d.max()) if len(d) else 0.0)
    n_ok = len(ours) - errors
    diffs = np.array(diffs)
    moved_diffs = np.array(moved_diffs)
    per_shot_max = np.array(per_shot_max)
    result = {
        "shots": len(ours),
        "ball_friction": args.ball_friction,
        "pooltool_errors": errors,
        "pocketed_set_agreement": round(agree / max(n_ok, 1), 3),
        "final_position_diff_m": {  # every ball on the table in both, moved or not
            "median": round(float(np.median(diffs)), 4),
            "p90": round(float(np.percentile(diffs, 90)), 4),
            "max": round(float(diffs.max()), 4),
        },
        "moved_ball_final_diff_m": {
            "balls": len(moved_diffs),
            "median": round(float(np.median(moved_diffs)), 4),
            "p75": round(float(np.percentile(moved_diffs, 75)), 4),
            "p90": round(float(np.percentile(moved_diffs, 90)), 4),
        },
        "shots_all_within_1cm": round(float(np.mean(per_shot_max < 0.01)), 3),
        "shots_all_within_5cm": round(float(np.mean(per_shot_max < 0.05)), 3),
        "cpu_ms_per_shot_mean": {
            "event": round(1000 * float(np.mean(cpu_ours)), 3),
            "pooltool": round(1000 * float(np.mean(cpu_theirs)), 2),
        },
        "cpu_ms_per_shot_median": {
            "event": round(1000 * float(np.median(cpu_ours)), 3),
            "pooltool": round(1000 * float(np.median(cpu_theirs)), 2),
        },
        "pooltool_worker_wall_s": round(wall, 1),
    }
    print(json.dumps(result, indent=2))
    if args.json:
        tmp = args.json.with_name(args.json.name + ".tmp")
        tmp.write_text(json.dumps(result, indent=2) + "\n")
        os.replace(tmp, args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Targeted soak of wedged configurations for the event backend (balls pinned against rails and jaws).

Usage:
    PYTHONPATH=src python benchmarks/wedge_soak.py --layouts 2000 [--shots 40] [--seed 0] [--json OUT.json]

Layouts: a ball frozen to a cushion with another ball frozen to it (the cue ball or an object ball),
balls in the jaws of a pocket, three-ball clusters against a rail, a ball in a corner. Each layout is
struck ``--shots`` times at random speeds (log-uniform 0.01-11.5 m/s), angles (mostly into the wedge),
tip offsets and elevations. Checks every outcome: status OK, no overlap beyond 1 micrometre, every
resting ball on the playing surface, every pocketed ball
dropped at its pocket (not pushed through a rail). Prints counts and the worst cases (with exact repro).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np

from pix2pockets.geometry import TableSpec
from pix2pockets.physics.event import EventSimulator
from pix2pockets.state import Ball, TableLayout

SPEC = TableSpec()
R = SPEC.ball_radius
TOL = 1e-6  # [m]


def _on_rail(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A centre frozen to a random cushion (away from the pockets) and the cushion's inward normal."""
    L, W = SPEC.length, SPEC.width
    side = int(rng.integers(4))
    if side == 0:
        return np.array([R, rng.uniform(0.15, W - 0.15)]), np.array([1.0, 0.0])
    if side == 1:
        return np.array([L - R, rng.uniform(0.15, W - 0.15)]), np.array([-1.0, 0.0])
    x = rng.uniform(0.15, L - 0.15)
    if abs(x - L / 2) < 0.12:
        x += 0.25
    if side == 2:
        return np.array([x, R]), np.array([0.0, 1.0])
    return np.array([x, W - R]), np.array([0.0, -1.0])


def _touching(p: np.ndarray, angle: float) -> np.ndarray:
    return p + 2 * R * np.array([math.cos(angle), math.sin(angle)])


def _valid(pts: list[np.ndarray]) -> bool:
    arr = np.array(pts)
    if not np.all(SPEC.contains(arr, margin=R - 1e-12)):
        return False
    d = np.linalg.norm(arr[:, None] - arr[None], axis=-1) + np.eye(len(arr)) * 9
    return bool(d.min() >= 2 * R - 1e-12)


def make_layout(rng: np.random.Generator, kind: int) -> tuple[list[np.ndarray], int]:
    """Ball centres (cue ball first) and the index of the ball to aim at."""
    base, nrm = _on_rail(rng)
    t = np.array([-nrm[1], nrm[0]])
    phi0 = math.atan2(nrm[1], nrm[0])
    if kind == 0:  # cue ball frozen to a ball frozen to the rail (directly pinned)
        a = phi0 + rng.uniform(-1.4, 1.4) * (rng.random() < 0.7)
        return [_touching(base, a), base], 1
    if kind == 1:  # object ball on the rail, another frozen to it, cue ball at a distance
        a = phi0 + rng.uniform(-1.5, 1.5)
        b = _touching(base, a)
        d = rng.uniform(3 * R, 0.8)
        ang = math.atan2(*(b - base)[::-1]) + rng.normal(0, 0.4)
        cue = b + d * np.array([math.cos(ang), math.sin(ang)])
        return [cue, b, base], 1
    if kind == 2:  # two balls frozen along the rail, touching each other, plus one wedged on top
        b = base + 2 * R * t
        c = _touching(base, phi0 + math.pi / 3 * rng.choice([-1, 1]) * rng.uniform(0.9, 1.0))
        cue = c + rng.uniform(3 * R, 0.6) * np.array(
            [math.cos(phi0 + rng.normal(0, 0.6)), math.sin(phi0 + rng.normal(0, 0.6))]
        )
        return [cue, b, base, c], 3
    if kind == 3:  # ball in the jaws / at a pocket mouth
        pk = SPEC.pockets[int(rng.integers(6))]
        c = np.asarray(pk.centre, dtype=float)
        mid = SPEC.size / 2
        inward = (mid - c) / np.linalg.norm(mid - c)
        p = c + inward * rng.uniform(0.02, 0.12) + rng.normal(0, 0.02, 2)
        p = np.clip(p, R, SPEC.size - R)
        q = _touching(p, math.atan2(inward[1], inward[0]) + rng.normal(0, 0.5))
        cue = q + inward * rng.uniform(3 * R, 0.5) + rng.normal(0, 0.05, 2)
        return [cue, q, p], 1
    # kind 4: a ball in a corner of two rails region or a chain of three frozen to the rail, cue frozen
    a = phi0 + rng.uniform(-0.3, 0.3)
    b = _touching(base, a)
    c = _touching(b, a + rng.uniform(-0.5, 0.5))
    return [c, b, base], 1


def run(layouts: int, shots: int, seed: int) -> dict:
    sim = EventSimulator()
    rng = np.random.default_rng(seed)
    counts = {"shots": 0, "budget": 0, "overlap": 0, "off_table": 0, "not_finite": 0, "through_cushion": 0}
    max_nev = 0
    worst: list[dict] = []
    done = 0
    while done < layouts:
        kind = done % 5
        pts, aim = make_layout(rng, kind)
        if not _valid(pts):
            continue
        done += 1
        layout = TableLayout(tuple(Ball.numbered(k) for k in range(len(pts))), np.array(pts), SPEC)
        m = shots
        arr = np.zeros((m, 5))
        d = layout.positions[aim] - layout.positions[0]
        at = math.atan2(d[1], d[0])
        arr[:, 0] = np.where(rng.random(m) < 0.8, at + rng.normal(0, 0.3, m), rng.uniform(-np.pi, np.pi, m))
        arr[:, 1] = np.exp(rng.uniform(np.log(0.01), np.log(11.5), m))
        radius, phase = np.sqrt(rng.random(m)) * 0.5, rng.uniform(0, 2 * np.pi, m)
        arr[:, 2], arr[:, 3] = radius * np.cos(phase), radius * np.sin(phase)
        arr[:, 4] = np.where(rng.random(m) < 0.2, rng.uniform(0, 1.2, m), 0.0)
        out = sim.simulate_arrays(layout, arr)
        counts["shots"] += m
        max_nev = max(max_nev, int(out.n_events.max()) if hasattr(out, "n_events") else 0)
        for s in range(m):
            problem = None
            if out.status[s] == 1:
                problem = "budget"
            elif out.status[s] != 0:
                problem = "not_finite"
            else:
                on = out.pocket[s] < 0
                fp = out.final_positions[s][on]
                far = [
                    np.linalg.norm(out.final_positions[s][b] - SPEC.pockets[out.pocket[s][b]].centre)
                    > SPEC.pockets[out.pocket[s][b]].capture_radius + 2 * R
                    for b in np.nonzero(~on)[0]
                ]
                if any(far):
                    problem = "through_cushion"
                elif len(fp) and not np.all(SPEC.contains(fp, margin=R - TOL)):
                    problem = "off_table"
                elif len(fp) > 1:
                    dd = np.linalg.norm(fp[:, None] - fp[None], axis=-1) + np.eye(len(fp)) * 9
                    if dd.min() < 2 * R - TOL:
                        problem = "overlap"
            if problem:
                counts[problem] += 1
                if len(worst) < 20:
                    worst.append(
                        {
                            "problem": problem,
                            "kind": kind,
                            "positions": layout.positions.tolist(),
                            "shot": arr[s].tolist(),
                        }
                    )
    return {"counts": counts, "max_events": max_nev, "failures": worst}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--layouts", type=int, default=500)
    parser.add_argument("--shots", type=int, default=40)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    if args.layouts < 1 or args.shots < 1:
        print("error: --layouts and --shots must be >= 1", file=sys.stderr)
        return 2
    t0 = time.process_time()
    res = run(args.layouts, args.shots, args.seed)
    res["cpu_s"] = round(time.process_time() - t0, 2)
    print(json.dumps({k: v for k, v in res.items() if k != "failures"}))
    for f in res["failures"][:5]:
        print(json.dumps(f))
    if args.json:
        args.json.write_text(json.dumps(res, indent=2) + "\n")
    bad = sum(v for k, v in res["counts"].items() if k != "shots")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

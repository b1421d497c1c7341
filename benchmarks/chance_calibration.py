"""Calibration of the reported success chances: predicted vs observed success, in bins (reliability diagram).

Plays seeded all-ball turns (the ``evaluate planner`` layouts) with the search planner for one skill level;
``--seed`` with several seeds pools their decisions (``--shots`` each).
At every decision it records the planner's own estimate (``Suggestion.success_probability``), the measured
chance of the chosen stroke (:func:`pix2pockets.planner.chance.measure_chance`, fresh draws of the same
noise) and whether the one executed stroke (another fresh draw) succeeded. Bins of 10 points of predicted
chance; a bin's gap is |mean predicted - observed|.

Usage::

    OMP_NUM_THREADS=1 PYTHONPATH=src python benchmarks/chance_calibration.py --skill pro --shots 2000 \\
        --json calib-pro.json --plot calib-pro.png
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from pix2pockets.physics import make_simulator
from pix2pockets.planner.base import legal_targets
from pix2pockets.planner.chance import measure_chance
from pix2pockets.planner.evaluation import ours_protocol, wilson_interval
from pix2pockets.planner.noise import noise_model
from pix2pockets.planner.registry import make_planner
from pix2pockets.rules import GameState, Outcome

EDGES = np.linspace(0.0, 1.0, 11)


def collect(skill: str, shots: int, seeds: list[int], samples: int, time_budget: float | None) -> dict:
    """Per seed, play turns until ``shots`` decisions are recorded; the decisions of all seeds pooled
    (planner p, measured p, success)."""
    noise = noise_model(skill)
    planner = make_planner("search", noise=skill, time_budget=time_budget)
    sim = make_simulator("event")
    protocol = ours_protocol()
    rows: list[tuple[float, float, int]] = []
    turns = 0
    t0 = time.perf_counter()
    for seed in seeds:
        wanted, turn = len(rows) + shots, 0
        while len(rows) < wanted:
            layout, state = protocol.layout(16, seed, turn), protocol.state
            rng = np.random.default_rng([seed, turn, 1])
            plan_rng, noise_rng, chance_rng = (np.random.default_rng(s) for s in rng.bit_generator.seed_seq.spawn(3))
            turn += 1
            while len(rows) < wanted and legal_targets(layout, state):
                best = planner.suggest(layout, state, plan_rng)[0]
                measured = measure_chance(planner, layout, state, best.shot, noise, samples, chance_rng)
                estimate = best.success_probability or 0.0  # a fallback or safety stroke carries no estimate
                try:
                    result = sim.simulate(layout, noise.perturb(best.shot, noise_rng))
                except RuntimeError:
                    rows.append((estimate, measured.p, 0))
                    break
                judged = protocol.judge(result, state)
                ok = judged.shot_succeeded
                rows.append((estimate, measured.p, int(ok)))
                if judged.outcome is not Outcome.CONTINUE or result.final.cue_index is None:
                    break
                layout, state = result.final, GameState(judged.group)
        turns += turn
    arr = np.array(rows)
    return {
        "skill": skill,
        "seeds": seeds,
        "turns": turns,
        "shots": len(rows),
        "chance_samples": samples,
        "time_budget_s": time_budget,
        "wall_s": time.perf_counter() - t0,
        "planner_estimate": bins(arr[:, 0], arr[:, 2]),
        "measured_chance": bins(arr[:, 1], arr[:, 2]),
    }


def bins(predicted: np.ndarray, observed: np.ndarray) -> list[dict]:
    """Reliability table: per bin of predicted chance, count, mean predicted, observed rate and its interval."""
    out = []
    idx = np.clip(np.digitize(predicted, EDGES[1:-1]), 0, len(EDGES) - 2)
    for b in range(len(EDGES) - 1):
        m = idx == b
        n = int(m.sum())
        if not n:
            continue
        k = int(observed[m].sum())
        lo, hi = wilson_interval(k, n)
        out.append(
            {
                "bin": [float(EDGES[b]), float(EDGES[b + 1])],
                "n": n,
                "predicted": float(predicted[m].mean()),
                "observed": k / n,
                "observed_ci95": [lo, hi],
                "gap": abs(float(predicted[m].mean()) - k / n),
            }
        )
    return out


def plot(results: list[dict], path: str) -> None:
    """Reliability diagram: observed vs predicted per bin, one line per skill and predictor."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 5))
    ax.plot([0, 1], [0, 1], color="grey", lw=1, ls="--", label="perfect")
    for res in results:
        for key, style in (("measured_chance", "-o"), ("planner_estimate", ":x")):
            rows = [r for r in res[key] if r["n"] >= 20]
            ax.plot(
                [r["predicted"] for r in rows],
                [r["observed"] for r in rows],
                style,
                label=f"{res['skill']}: {key.replace('_', ' ')}",
            )
    ax.set_xlabel("predicted chance (bin mean)")
    ax.set_ylabel("observed success")
    ax.set_title("Chances vs outcomes (bins of >= 20 shots)", fontsize=10)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--skill", nargs="+", default=["pro"], help="skill levels (default pro)")
    ap.add_argument("--shots", type=int, default=2000, help="decisions per skill and seed (2000)")
    ap.add_argument("--seed", type=int, nargs="+", default=[0], help="layout seeds, their decisions pooled (0)")
    ap.add_argument("--samples", type=int, default=200, help="sampled strokes behind each measured chance (200)")
    ap.add_argument("--time-budget", type=float, default=None, help="planner budget [s] (default none)")
    ap.add_argument("--json", help="write the tables here")
    ap.add_argument("--plot", help="write the reliability diagram here (.png)")
    args = ap.parse_args()
    results = []
    for skill in args.skill:
        res = collect(skill, args.shots, args.seed, args.samples, args.time_budget)
        results.append(res)
        print(f"{skill}: {res['shots']} shots over {res['turns']} turns (seeds {res['seeds']}), {res['wall_s']:.0f} s")
        for key in ("measured_chance", "planner_estimate"):
            print(f"  {key}")
            for r in res[key]:
                print(
                    f"    {r['bin'][0]:.1f}-{r['bin'][1]:.1f}  n={r['n']:5d}  predicted {r['predicted']:.3f}  "
                    f"observed {r['observed']:.3f}  gap {100 * r['gap']:.1f} pts"
                )
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1) + "\n")
    if args.plot:
        plot(results, args.plot)


if __name__ == "__main__":
    main()

"""Where full-turn clears fail: each shot of the search planner's turns under a skill's noise, by own balls left.

``--racks`` layouts of our protocol (16 balls, solids) are played as in ``pix2pockets evaluate planner`` (the default
search planner without a time budget, the skill's noise on every stroke). Every shot is recorded with the legal
balls left before it (the last of them is the 8), the planner's chance for the stroke it chose and whether it
succeeded. Reported per balls left: shots, failures, the failures the chances predict, the mean chance, and how many
shots were chosen below 80 %; the last own ball and the 8 are told apart. For the last own ball chosen below 80 %,
how hard that ball is from anywhere: its best direct pot chance from a free spot of the table (cue ball in hand,
spots 5 cm apart, 1 degree of aim).

Usage:
    OMP_NUM_THREADS=1 PYTHONPATH=src python benchmarks/turn_failures.py [--racks 200] [--seed 0] [--skill pro]
        [--json OUT.json]
"""

from __future__ import annotations

import json
import math
import os
from collections import defaultdict

import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")

from _racks import rack_parser, rack_setup
from pix2pockets.planner.ball_in_hand import free_spots
from pix2pockets.planner.base import legal_targets
from pix2pockets.planner.evaluation import continues_or_wins
from pix2pockets.planner.position import direct_pot_probabilities
from pix2pockets.rules import GameState, Outcome

LOW_CHANCE = 0.8
"""Shots chosen below this chance are counted apart."""
ANYWHERE_SIGMA = math.radians(1.0)
"""Aim spread [rad] of the from-anywhere chance."""


def best_spot_chance(layout, target: int) -> float:
    """The best direct pot chance of ball ``target`` from any free spot, the cue ball taken off the table."""
    base = layout.without([layout.cue_index])
    t = target - int(layout.cue_index < target)
    spots = free_spots(base, step=0.05)
    positions = np.vstack([base.positions, spots[:1]])
    best = 0.0
    for xy in spots:
        positions[-1] = xy
        best = max(best, float(direct_pot_probabilities(positions, len(base), [t], base.spec, ANYWHERE_SIGMA).max()))
    return best


def play(layout, state, planner, simulate, noise, judge, success, rng: np.random.Generator) -> list[dict]:
    """One turn's shots: the legal balls left before each, the chosen stroke's chance, whether it succeeded."""
    plan_rng, noise_rng = (np.random.default_rng(s) for s in rng.bit_generator.seed_seq.spawn(2))
    shots: list[dict] = []
    while len(shots) < 30 and legal_targets(layout, state):
        legal = legal_targets(layout, state)
        best = planner.suggest(layout, state, plan_rng)[0]
        result = simulate(layout, noise.perturb(best.shot, noise_rng))
        turn = judge(result, state)
        ok = bool(success(turn))
        eight = legal == [layout.black_index]
        chance = float(best.success_probability or 0.0)
        shot = {"left": len(legal), "eight": eight, "chance": chance, "ok": ok}
        if len(legal) == 1 and not eight and chance < LOW_CHANCE:
            shot["anywhere"] = best_spot_chance(layout, legal[0])
        shots.append(shot)
        if turn.outcome is not Outcome.CONTINUE or not ok:
            break
        layout, state = result.final, GameState(turn.group)
    return shots


def main(argv: list[str] | None = None) -> int:
    ap = rack_parser(__doc__, 200)
    args = ap.parse_args(argv)

    planner, noise, sim, proto = rack_setup(args.skill)
    success = proto.success or continues_or_wins
    turns = []
    for i in range(args.racks):
        rng = np.random.default_rng([args.seed, i, 1])
        turns.append(
            play(proto.layout(16, args.seed, i), proto.state, planner, sim.simulate, noise, proto.judge, success, rng)
        )
        if (i + 1) % 50 == 0:
            print(f"{i + 1} racks", flush=True)

    groups: dict[str, list[dict]] = defaultdict(list)
    for shots in turns:
        for s in shots:
            key = "the 8" if s["eight"] else ("last own ball" if s["left"] == 1 else f"{s['left']} own balls")
            groups[key].append(s)
    order = sorted((k for k in groups if k[0].isdigit()), key=lambda k: -int(k.split()[0]))
    order += [k for k in ("last own ball", "the 8") if k in groups]
    cleared = sum(1 for shots in turns if shots and shots[-1]["ok"] and shots[-1]["eight"])
    print(f"{args.racks} racks, {args.skill} noise: full-turn clear {100 * cleared / args.racks:.1f} %")
    print(f"{'before the shot':<16} {'shots':>6} {'failed':>7} {'expected':>9} {'mean chance':>12} {'below 80 %':>11}")
    rows = {}
    for key in order:
        ss = groups[key]
        chance = np.array([s["chance"] for s in ss])
        ok = np.array([s["ok"] for s in ss])
        rows[key] = {
            "shots": len(ss),
            "failed": int((~ok).sum()),
            "expected_failures": float((1 - chance).sum()),
            "mean_chance": float(chance.mean()),
            "below_low_chance": int((chance < LOW_CHANCE).sum()),
            "failed_below_low_chance": int((~ok & (chance < LOW_CHANCE)).sum()),
        }
        r = rows[key]
        print(
            f"{key:<16} {r['shots']:>6} {r['failed']:>7} {r['expected_failures']:>9.1f} {r['mean_chance']:>12.3f} "
            f"{r['below_low_chance']:>11}"
        )
    anywhere = [s["anywhere"] for ss in groups.values() for s in ss if "anywhere" in s]
    if anywhere:
        q = np.percentile(anywhere, [25, 50, 75])
        print(
            f"last own ball chosen below {LOW_CHANCE:.0%}: {len(anywhere)}; its best chance from any spot "
            f"(1 degree of aim), quartiles {q[0]:.2f} / {q[1]:.2f} / {q[2]:.2f}"
        )
    if args.json:
        doc = {"racks": args.racks, "seed": args.seed, "skill": args.skill, "cleared": cleared, "by_left": rows}
        doc["last_ball_low_chance_from_anywhere"] = anywhere
        with open(args.json, "w") as f:
            json.dump(doc, f, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Whole games between two planners: who wins, in how many shots, with how many fouls.

Game ``i`` starts from layout ``i`` of the ``evaluate planner`` protocol (16 balls at random spots, an open table) on
the set's table (``--set american``: 9-foot, 8-ball rules; ``blackball``: UK 7-foot, WEPF rules, two visits after a
foul), every stroke executed with the ``--skill`` noise; the players take turns to start (A starts the even games).
Ball in hand after a foul (8-ball: anywhere; WEPF: behind the baulk line, only when the cue ball dropped) goes to the
free spot the player's planner likes best (:func:`pix2pockets.planner.ball_in_hand.best_placement`).

Usage:
    OMP_NUM_THREADS=1 PYTHONPATH=src python benchmarks/games.py [--a search] [--b oracle] [--set blackball]
        [--skill club] [--games 40] [--seed 0] [--stroke-budget 3000] [--time-budget S] [--json OUT.json]

The search planner's decisions are capped at ``--stroke-budget`` simulated strokes (about 0.3 s on one quiet core), so
the same games are played on any machine; ``--time-budget`` caps them in seconds instead (or as well).
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from pix2pockets.geometry import table_preset
from pix2pockets.physics import make_simulator
from pix2pockets.planner.evaluation import ours_protocol, wilson_interval
from pix2pockets.planner.game import play_game
from pix2pockets.planner.noise import noise_model
from pix2pockets.planner.registry import make_planner

TABLES = {"american": "9ft", "blackball": "uk7"}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--a", default="search", help="player A's planner (default search)")
    ap.add_argument("--b", default="oracle", help="player B's planner (default oracle)")
    ap.add_argument("--set", dest="ball_set", default="blackball", choices=sorted(TABLES))
    ap.add_argument("--skill", default="club", help="stroke noise of both players (default club)")
    ap.add_argument("--games", type=int, default=40)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--stroke-budget", type=int, default=3000, help="search planner's strokes simulated per decision at most"
    )
    ap.add_argument("--time-budget", type=float, default=None, help="search planner's time per decision at most [s]")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()

    noise = noise_model(args.skill)
    budget = {"time_budget": args.time_budget, "stroke_budget": args.stroke_budget}
    a = make_planner(args.a, noise=args.skill, **budget)
    b = make_planner(args.b, noise=args.skill, **budget)
    protocol = ours_protocol(table_preset(TABLES[args.ball_set]))
    sim = make_simulator("event")
    wins = {"A": 0, "B": 0, "unfinished": 0}
    shots, fouls_a, fouls_b = [], 0, 0
    start = time.perf_counter()
    for i in range(args.games):
        a_first = i % 2 == 0
        players = (a, b) if a_first else (b, a)
        layout = protocol.layout(16, args.seed, i)
        record = play_game(layout, players, sim, args.ball_set, noise, np.random.default_rng([args.seed, i, 7]))
        shots.append(record.shots)
        a_index = 0 if a_first else 1
        fouls_a += record.fouls[a_index]
        fouls_b += record.fouls[1 - a_index]
        if record.winner is None:
            wins["unfinished"] += 1
        else:
            wins["A" if record.winner == a_index else "B"] += 1
    lo, hi = wilson_interval(wins["A"], args.games)
    report = {
        "a": args.a,
        "b": args.b,
        "ball_set": args.ball_set,
        "table": TABLES[args.ball_set],
        "skill": args.skill,
        "games": args.games,
        "seed": args.seed,
        "time_budget_s": args.time_budget,
        "stroke_budget": args.stroke_budget,
        "wins": wins,
        "a_win_share": wins["A"] / args.games,
        "a_win_share_ci95": [lo, hi],
        "shots_per_game_mean": float(np.mean(shots)),
        "fouls_per_game": {"A": fouls_a / args.games, "B": fouls_b / args.games},
        "seconds": round(time.perf_counter() - start, 1),
    }
    table = TABLES[args.ball_set]
    print(f"{args.games} {args.ball_set} games on {table}, {args.skill} noise, A = {args.a}, B = {args.b}")
    print(f"A wins {wins['A']} ({100 * report['a_win_share']:.1f} %, 95 % CI {100 * lo:.1f}-{100 * hi:.1f}), "
          f"B wins {wins['B']}, unfinished {wins['unfinished']}")  # fmt: skip
    print(f"shots per game {report['shots_per_game_mean']:.1f}; fouls per game A {fouls_a / args.games:.2f}, "
          f"B {fouls_b / args.games:.2f}; {report['seconds']} s")  # fmt: skip
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(report, fh, indent=1)


if __name__ == "__main__":
    main()

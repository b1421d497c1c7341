"""``pix2pockets evaluate planner``: the paper's Table 3 protocol for any planner.

Example::

    pix2pockets evaluate planner --planner search --balls 16 --layouts 1000 --seed 0 --noise fastfiz \\
        --json search-fastfiz.json
    pix2pockets evaluate planner --physics paper --planner oracle --layouts 1000 --json paper-oracle.json
"""

from __future__ import annotations

import argparse
from pathlib import Path

from pix2pockets.files import check_output, write_json
from pix2pockets.planner.evaluation import BALL_SETS, evaluate_planner, ours_protocol, paper_protocol
from pix2pockets.planner.noise import noise_model
from pix2pockets.planner.registry import PLANNER_NAMES, make_planner


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``planner`` target to the ``evaluate`` group."""
    parser = sub.add_parser(
        "planner",
        help="per-shot success and full-turn clear of a planner over seeded random layouts",
        description="Paper Table 3 protocol: per-shot success (legal pot of an own ball; fouls fail) and "
        "full-turn clear (the group then the 8 without a miss or foul) over N seeded layouts, with 95% "
        "Wilson intervals.",
    )
    parser.add_argument("--planner", default="search", choices=PLANNER_NAMES, help="planner (default search)")
    parser.add_argument(
        "--balls",
        type=int,
        default=16,
        choices=sorted(BALL_SETS),
        help="environment as in the paper: 1 = the cue ball alone (pot it), 2 = cue + 8 (pot the 8), "
        "16 = all balls, clear solids then the 8 (16)",
    )
    parser.add_argument("--layouts", type=int, default=100, help="number of layouts / turns (100)")
    parser.add_argument(
        "--seed",
        type=int,
        default=None,
        help="seed of the layouts and noise (default 0; 12345 with the paper protocol, whose layout i is "
        "drawn after np.random.seed(seed + i))",
    )
    parser.add_argument(
        "--noise", default="none", help="execution noise: none, fastfiz, fastfiz5x, aim:<deg>, gauss:<deg>:<m/s>"
    )
    parser.add_argument(
        "--planning-noise",
        default="auto",
        help="noise the search planner plans for (auto: the execution noise, fastfiz when that is none)",
    )
    parser.add_argument(
        "--physics", default="event", help="simulator backend: event, paper (the paper's environment) or pymunk (event)"
    )
    parser.add_argument(
        "--protocol",
        choices=("auto", "ours", "paper"),
        default="auto",
        help="layouts, shooter and judgement: ours (solids, 8-ball rules) or paper (its start layouts on its "
        "table, the stripes, its judgement; success = an own ball dropped); auto: paper with --physics paper",
    )
    parser.add_argument(
        "--paper-defects",
        default="",
        help="paper protocol: comma-separated defects of its environment to switch back on: spawn-in-pocket "
        "(balls may start inside a pocket circle), early-eight-wins (the 8 before the group's last ball wins)",
    )
    parser.add_argument(
        "--time-budget", type=float, default=None, help="search decision limit [s] (default: none, reproducible)"
    )
    parser.add_argument("--oracle-speed", type=float, default=None, help="the Oracle's max-power speed [m/s]")
    parser.add_argument("--json", metavar="OUT.json", help="write the results as JSON")
    parser.add_argument("--force", action="store_true", help="overwrite an existing --json file")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


register_target = register

PAPER_DEFECTS = ("spawn-in-pocket", "early-eight-wins")
"""Defects of the paper's environment that ``--paper-defects`` can switch back on."""
PAPER_PLANNING_NOISE = "gauss:0.125:0.01"
"""The search planner's planning noise on the paper physics when execution is noiseless: FastFiz's aim
noise and 1% of the paper's top speed (FastFiz's 0.075 m/s is 8% of it)."""


def run(args: argparse.Namespace) -> int:
    from pix2pockets.physics import make_simulator

    if args.layouts < 1:
        raise ValueError(f"--layouts must be >= 1, got {args.layouts}")
    if args.time_budget is not None and not args.time_budget > 0:
        raise ValueError(f"--time-budget must be positive, got {args.time_budget}")
    noise = noise_model(args.noise)
    planning = args.planning_noise
    if planning == "auto":
        planning = (PAPER_PLANNING_NOISE if args.physics == "paper" else "fastfiz") if noise.is_zero else args.noise
    noise_model(planning)
    protocol_name = args.protocol
    if protocol_name == "auto":
        protocol_name = "paper" if args.physics == "paper" else "ours"
    defects = {d.strip() for d in args.paper_defects.split(",") if d.strip()}
    unknown = defects - set(PAPER_DEFECTS)
    if unknown:
        raise ValueError(f"unknown --paper-defects {sorted(unknown)}; known: {', '.join(PAPER_DEFECTS)}")
    if defects and protocol_name != "paper":
        raise ValueError("--paper-defects applies to the paper protocol")
    if protocol_name == "paper":
        protocol = paper_protocol("spawn-in-pocket" in defects, "early-eight-wins" in defects)
        seed = 12345 if args.seed is None else args.seed
    else:
        from pix2pockets.geometry.raster import paper_table

        protocol = ours_protocol(paper_table() if args.physics == "paper" else None)
        seed = 0 if args.seed is None else args.seed
    check_output(args.json, args.force)
    out = Path(args.json) if args.json else None
    sim = make_simulator(args.physics)
    planner = make_planner(
        args.planner, physics=args.physics, noise=planning, time_budget=args.time_budget,
        oracle_speed=args.oracle_speed,
    )  # fmt: skip
    summary = evaluate_planner(
        planner, sim.simulate, args.balls, args.layouts, seed, noise, args.physics, not args.no_progress, protocol
    )
    data = summary.to_dict()
    data["planning_noise"] = planning if args.planner.startswith("search") else None
    data["time_budget_s"] = args.time_budget
    lo, hi = data["per_shot_success_ci95"]
    clo, chi = data["full_turn_clear_ci95"]
    print(
        f"{data['planner']} | {args.balls}-ball | noise {data['noise']} | physics {args.physics} | "
        f"protocol {summary.protocol} | seed {seed} | {summary.turns} layouts, {summary.shots} shots"
    )
    print(f"  per-shot success  {data['per_shot_success']:.4f}  (95% CI {lo:.4f}-{hi:.4f})")
    print(f"  full-turn clear   {data['full_turn_clear']:.4f}  (95% CI {clo:.4f}-{chi:.4f})")
    print(
        f"  decision time     mean {data['decision_time_mean_s'] * 1000:.1f} ms, "
        f"p95 {data['decision_time_p95_s'] * 1000:.1f} ms, max {data['decision_time_max_s'] * 1000:.1f} ms"
    )
    if out is not None:
        write_json(out, data)
    return 0

"""``pix2pockets evaluate planner``: the paper's Table 3 protocol for any planner.

Example::

    pix2pockets evaluate planner --planner search --balls 16 --layouts 1000 --seed 0 --noise fastfiz \\
        --json search-fastfiz.json
    pix2pockets evaluate planner --physics paper --planner oracle --layouts 1000 --json paper-oracle.json
    pix2pockets evaluate planner --planner search --layouts 1000 --skill club --json search-club.json
    pix2pockets evaluate planner --planner search --layouts 100000 --ray auto --json search-100k.json
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

from pix2pockets.files import check_output, write_json
from pix2pockets.geometry.table import TABLE_PRESETS, table_preset
from pix2pockets.planner.evaluation import (
    BALL_SETS,
    EvaluationSummary,
    Protocol,
    evaluate_planner,
    merge_summaries,
    ours_protocol,
    paper_protocol,
)
from pix2pockets.planner.noise import noise_model
from pix2pockets.planner.registry import PLANNER_NAMES, make_planner
from pix2pockets.rules import judge_for
from pix2pockets.scale.ray_pool import add_ray_arguments


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
        "--table",
        choices=sorted(TABLE_PRESETS),
        default=None,
        help="the table of our protocol's layouts (default 9ft, uk7 with --set blackball; uk7 and uk6 are UK "
        "tables for 2 in balls)",
    )
    parser.add_argument(
        "--set",
        dest="ball_set",
        choices=("american", "blackball"),
        default="american",
        help="the rules of our protocol: american (8-ball) or blackball (WEPF: an opponent's ball down is a foul)",
    )
    parser.add_argument(
        "--seed",
        type=int,
        default=None,
        help="seed of the layouts and noise (default 0; 12345 with the paper protocol, whose layout i is "
        "drawn after np.random.seed(seed + i))",
    )
    parser.add_argument(
        "--noise",
        default="none",
        help="execution noise: none, fastfiz, fastfiz5x, a skill level (pro, club, beginner), aim:<deg>, "
        "gauss:<deg>:<m/s> or FILE.json (a custom skill level)",
    )
    parser.add_argument(
        "--skill",
        default=None,
        help="the player's skill level (pro, club, beginner or FILE.json): the same as --noise LEVEL, so the "
        "search planner plans for the noise it is played with",
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
    add_ray_arguments(parser, "split the layouts over Ray workers, the same numbers as one process")
    parser.set_defaults(func=run)


register_target = register

PAPER_DEFECTS = ("spawn-in-pocket", "early-eight-wins")
"""Defects of the paper's environment that ``--paper-defects`` can switch back on."""
PAPER_PLANNING_NOISE = "gauss:0.125:0.01"
"""The search planner's planning noise on the paper physics when execution is noiseless: FastFiz's aim
noise and 1% of the paper's top speed (FastFiz's 0.075 m/s is 8% of it)."""


@dataclass(frozen=True, slots=True)
class PlannerJob:
    """Everything one evaluation's layouts share, as plain values (sent to Ray workers).

    Attributes:
        planner: planner name.
        physics: simulator backend.
        balls: environment (1, 2 or 16).
        seed: seed of the layouts and noise.
        noise: execution noise spec.
        planning_noise: the noise the search planner plans for.
        protocol: ``ours`` or ``paper``.
        defects: the paper protocol's defects switched on.
        time_budget: search decision limit [s].
        oracle_speed: the Oracle's max-power speed [m/s].
        table: preset name of our protocol's table (``None``: 9-foot, or the paper's table on its physics).
        ball_set: ``american`` (8-ball rules) or ``blackball`` (WEPF rules; the search plans by them too).
    """

    planner: str
    physics: str
    balls: int
    seed: int
    noise: str = "none"
    planning_noise: str = "fastfiz"
    protocol: str = "ours"
    defects: tuple[str, ...] = ()
    time_budget: float | None = None
    oracle_speed: float | None = None
    table: str | None = None
    ball_set: str = "american"

    def make_protocol(self) -> Protocol:
        """The :class:`Protocol` this job names."""
        if self.protocol == "paper":
            return paper_protocol("spawn-in-pocket" in self.defects, "early-eight-wins" in self.defects)
        from pix2pockets.geometry.raster import paper_table

        judge = judge_for(self.ball_set)
        if self.table is not None:
            return ours_protocol(table_preset(self.table), judge)
        if self.ball_set == "blackball":
            return ours_protocol(table_preset("uk7"), judge)
        return ours_protocol(paper_table() if self.physics == "paper" else None)


def evaluate_layouts(layouts: range, job: PlannerJob, progress: bool = False) -> EvaluationSummary:
    """Evaluate layouts ``layouts`` (consecutive indices) of ``job`` in this process."""
    from pix2pockets.physics import make_simulator

    sim = make_simulator(job.physics)
    rules = {"rules": "blackball"} if job.ball_set == "blackball" and job.planner.startswith("search") else {}
    planner = make_planner(
        job.planner, physics=job.physics, noise=job.planning_noise, time_budget=job.time_budget,
        oracle_speed=job.oracle_speed, **rules,
    )  # fmt: skip
    return evaluate_planner(
        planner, sim.simulate, job.balls, len(layouts), job.seed, noise_model(job.noise), job.physics, progress,
        job.make_protocol(), first=layouts.start,
    )  # fmt: skip


PIECES_PER_CPU = 4
"""Layout ranges per Ray CPU: turns differ in length, so smaller pieces keep every worker busy to the end."""


def evaluate_on_ray(job: PlannerJob, layouts: int, address: str, workers: int | None = None) -> EvaluationSummary:
    """Evaluate layouts ``0 .. layouts - 1`` split over Ray workers; the same counts as one process."""
    from pix2pockets.scale import RayPool, split_range

    with RayPool(address, workers) as pool:
        pieces = split_range(0, layouts, pool.cpus * PIECES_PER_CPU)
        return merge_summaries(list(pool.map(evaluate_layouts, pieces, job)))


def run(args: argparse.Namespace) -> int:
    if args.layouts < 1:
        raise ValueError(f"--layouts must be >= 1, got {args.layouts}")
    if args.time_budget is not None and not args.time_budget > 0:
        raise ValueError(f"--time-budget must be positive, got {args.time_budget}")
    if args.skill is not None:
        if args.noise != "none":
            raise ValueError("give either --skill or --noise, not both")
        args.noise = args.skill
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
    default_seed = 12345 if protocol_name == "paper" else 0
    seed = default_seed if args.seed is None else args.seed
    check_output(args.json, args.force)
    out = Path(args.json) if args.json else None
    job = PlannerJob(
        planner=args.planner, physics=args.physics, balls=args.balls, seed=seed, noise=args.noise,
        planning_noise=planning, protocol=protocol_name, defects=tuple(sorted(defects)), time_budget=args.time_budget,
        oracle_speed=args.oracle_speed, table=args.table, ball_set=args.ball_set,
    )  # fmt: skip
    if args.table is not None and protocol_name == "paper":
        raise ValueError("--table applies to our protocol (the paper's protocol plays on its own table)")
    if args.ball_set != "american" and protocol_name == "paper":
        raise ValueError("--set applies to our protocol (the paper plays American 8-ball)")
    if args.ray is None:
        if args.workers is not None:
            raise ValueError("--workers applies with --ray")
        summary = evaluate_layouts(range(args.layouts), job, progress=not args.no_progress)
    else:
        summary = evaluate_on_ray(job, args.layouts, args.ray, args.workers)
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

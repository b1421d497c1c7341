"""``pix2pockets experiment``: the paper's planner experiments, printed as tables.

``aim-precision`` (Fig. 4b: one-shot success vs aim sigma, 1-ball and 2-ball) and ``ball-shift`` (2-ball
success with the target ball shifted by the location error and by 2.5 cm).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from pix2pockets.files import check_output, write_json
from pix2pockets.planner.experiments import (
    PAPER_SHIFT1,
    PAPER_SHIFT2,
    PAPER_SIGMAS_DEG,
    aim_precision,
    ball_shift,
    cue_pot_precision,
)
from pix2pockets.planner.registry import PLANNER_NAMES, make_planner


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("experiment", help="the paper's planner experiments (aim precision, ball shift)")
    exps = parser.add_subparsers(dest="experiment", metavar="EXPERIMENT")

    aim = exps.add_parser("aim-precision", help="one-shot success vs aim noise sigma (paper Fig. 4b)")
    aim.add_argument(
        "--planners", nargs="+", default=["oracle"], choices=PLANNER_NAMES, help="planners for 2-ball (oracle)"
    )
    aim.add_argument("--sigmas", nargs="+", type=float, default=list(PAPER_SIGMAS_DEG), help="degrees")
    aim.add_argument(
        "--balls",
        nargs="+",
        type=int,
        default=[1, 2],
        choices=[1, 2],
        help="1: pot the lone cue ball (paper); 2: cue + 8 (1 2)",
    )
    _common(aim)
    aim.set_defaults(func=run_aim)

    shift = exps.add_parser("ball-shift", help="2-ball success with the target ball shifted (paper sec. 6.2)")
    shift.add_argument("--planners", nargs="+", default=["oracle", "oracle-mirror", "search"], choices=PLANNER_NAMES)
    shift.add_argument("--shift1", nargs=2, type=float, default=list(PAPER_SHIFT1), metavar=("LO", "HI"),
                       help="uniform shift range [m] (paper: 0.0022 0.0076)")  # fmt: skip
    shift.add_argument("--shift2", type=float, default=PAPER_SHIFT2, help="fixed shift [m] (0.025)")
    _common(shift)
    shift.set_defaults(func=run_shift)
    parser.set_defaults(func=lambda args: (parser.print_help(), 2)[1])


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--layouts", type=int, default=200, help="layouts per cell (200)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--physics", default="event", help="simulator backend (event)")
    p.add_argument("--json", metavar="OUT.json", help="write the table as JSON")
    p.add_argument("--force", action="store_true", help="overwrite an existing --json file")


def _check(args: argparse.Namespace) -> Path | None:
    if args.layouts < 1:
        raise ValueError(f"--layouts must be >= 1, got {args.layouts}")
    check_output(args.json, args.force)
    return Path(args.json) if args.json else None


def _write(out: Path | None, data: dict) -> None:
    if out is None:
        return
    write_json(out, data)


def run_aim(args: argparse.Namespace) -> int:
    from pix2pockets.physics import make_simulator

    out = _check(args)
    sim = make_simulator(args.physics)
    rows = {}
    if 1 in args.balls:  # the paper's 1-ball: pot the lone cue ball (no planner involved)
        rows["1-ball (pot the cue ball)"] = cue_pot_precision(sim.simulate, args.sigmas, args.layouts, args.seed)
    for name in args.planners if 2 in args.balls else ():

        def make(sigma: float, name: str = name):
            noise = f"aim:{sigma:g}" if sigma > 0 else "fastfiz"
            return make_planner(name, physics=args.physics, noise=noise, time_budget=None)

        rows[f"{name} 2-ball"] = aim_precision(make, sim.simulate, 2, args.sigmas, args.layouts, args.seed)
    header = "planner / env".ljust(28) + "".join(f"{s:>8g}" for s in args.sigmas)
    print(f"one-shot success vs aim sigma [deg], {args.layouts} layouts each, physics {args.physics}")
    print(header)
    for key, rates in rows.items():
        print(key.ljust(28) + "".join(f"{rates[float(s)].value:8.3f}" for s in args.sigmas))
    _write(out, {k: {str(s): r.to_dict() for s, r in v.items()} for k, v in rows.items()} | {"layouts": args.layouts})
    return 0


def run_shift(args: argparse.Namespace) -> int:
    from pix2pockets.physics import make_simulator

    out = _check(args)
    sim = make_simulator(args.physics)
    lo, hi = args.shift1
    print(f"2-ball success, target shifted: none | shift-1 U({lo * 100:g}-{hi * 100:g} cm) | shift-2 "
          f"{args.shift2 * 100:g} cm; {args.layouts} layouts, physics {args.physics}")  # fmt: skip
    print("planner".ljust(26) + f"{'none':>10}{'shift-1':>10}{'shift-2':>10}")
    data = {}
    for name in args.planners:
        planner = make_planner(name, physics=args.physics, time_budget=None)
        rates = ball_shift(planner, sim.simulate, args.layouts, args.seed, (lo, hi), args.shift2)
        data[name] = {k: r.to_dict() for k, r in rates.items()}
        print(name.ljust(26) + "".join(f"{rates[k].value:10.3f}" for k in ("none", "shift1", "shift2")))
    _write(out, data | {"layouts": args.layouts, "shift1": [lo, hi], "shift2": args.shift2})
    return 0

"""``pix2pockets suggest``: the best shot for a photo of a pool table, drawn and as JSON."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from pix2pockets.cli.detector_options import add_model_options, chosen_detector
from pix2pockets.cli.warmup_cmd import AfterCompile, compile_in_background
from pix2pockets.data.examples import example_photo_path
from pix2pockets.files import check_output, write_atomic
from pix2pockets.geometry.table import TABLE_PRESETS
from pix2pockets.rules import InHand
from pix2pockets.state.ball_set import BALL_SET_CHOICES, group_choices, parse_ball_set, parse_group

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".webp")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "suggest",
        help="suggest the best shot for a photo of a pool table",
        description="Detect balls and diamonds, fit the table, locate the balls, plan and draw the best shot.",
    )
    parser.add_argument("image", nargs="?", help="photo of the table (default: the bundled example)")
    parser.add_argument(
        "--group",
        choices=group_choices(),
        default="auto",
        help="your group: solids or stripes (American set), reds or yellows (blackball set); auto: the better shot",
    )
    parser.add_argument(
        "--set",
        dest="ball_set",
        choices=BALL_SET_CHOICES,
        default="auto",
        help="the balls: american (solids and stripes), blackball (reds and yellows) or auto (read from the photo)",
    )
    parser.add_argument("--out", help="write the result picture here (.png or .jpg)")
    parser.add_argument("--json", dest="json_out", help="write the result as JSON here ('-' for stdout)")
    add_model_options(parser)
    parser.add_argument(
        "--time-budget",
        type=float,
        metavar="SECONDS",
        help="cap the planner's search per group (default: none, so results are reproducible)",
    )
    parser.add_argument(
        "--agent", help="plan with a trained RL agent file (pix2pockets rl train) instead of the search planner"
    )
    parser.add_argument(
        "--skill",
        default="pro",
        help="your skill level: pro (FastFiz noise), club, beginner or a noise FILE.json; the shot is chosen and "
        "its chance measured for it (default pro)",
    )
    parser.add_argument("--method", choices=["sphere", "contact", "linear"], default="sphere", help="ball location")
    parser.add_argument(
        "--table",
        choices=["auto", *TABLE_PRESETS],
        default="auto",
        help="table size (default auto: from the balls' size when the table is found without diamonds, else 9ft)",
    )
    parser.add_argument(
        "--ball-in-hand",
        default="none",
        choices=[a.value for a in InHand],
        help="you have the cue ball in hand: the planner puts it anywhere free on the table (table) or behind the "
        "baulk line at the table's head end (baulk); the photo's cue ball, if any, is picked up. none (default): "
        "the cue ball is played from where it lies (a rack is broken from hand when the cue ball is off the table or "
        "outside the break area)",
    )
    parser.add_argument("--force", action="store_true", help="overwrite existing output files")
    parser.set_defaults(func=run)


def load_agent_planner(path: str):
    """A planner backed by an RL agent file; clear errors for a missing file or a missing ``rl`` extra."""
    try:
        from pix2pockets.rl.agent import AgentPlanner, load_agent
    except ImportError as err:
        raise ValueError(f"--agent needs the 'rl' extra (pip install '.[rl]'): {err}") from None
    try:
        return AgentPlanner(load_agent(path))
    except ImportError as err:
        raise ValueError(f"--agent needs the 'rl' extra (pip install '.[rl]'): {err}") from None


def run(args: argparse.Namespace) -> int:
    check_output(args.out, args.force, IMAGE_SUFFIXES)
    check_output(args.json_out, args.force)
    if (
        args.out
        and args.json_out
        and args.json_out != "-"
        and Path(args.out).resolve() == Path(args.json_out).resolve()
    ):
        raise ValueError("--out and --json must be different files")
    image = args.image or example_photo_path()
    if args.image is None and not Path(image).is_file():
        raise ValueError("no IMAGE given and the bundled example photo is missing from this build")

    if args.ball_set != "auto":  # a group of another set: one line, before the photo is read
        parse_group(args.group, parse_ball_set(args.ball_set))
    if args.time_budget is not None and not args.time_budget > 0:
        raise ValueError(f"--time-budget must be a positive number of seconds, got {args.time_budget}")
    # first run after an install: say so, and compile the physics while the photo is read
    compiling = compile_in_background()

    from pix2pockets.pipeline.draw import encode_picture, render_result
    from pix2pockets.pipeline.photo import load_image, suggest
    from pix2pockets.pipeline.planning import default_planner

    detector = chosen_detector(args)  # None: the pipeline's default
    planner = None  # the pipeline's default planner
    if args.agent:
        planner = load_agent_planner(args.agent)
    else:
        from pix2pockets.planner.noise import noise_model

        noise_model(args.skill)  # a bad level or file: one line, before the photo is read
        planner = default_planner(args.time_budget, skill=args.skill)
    if compiling is not None:
        planner = AfterCompile(planner, compiling)
    rgb = load_image(image)
    from pix2pockets.geometry import table_preset

    result = suggest(
        rgb,
        group=args.group,
        detector=detector,
        planner=planner,
        spec=None if args.table == "auto" else table_preset(args.table),
        locate_method=args.method,
        number_reader=(args.numbers or "").lower() != "none",
        ball_set=args.ball_set,
        ball_in_hand=args.ball_in_hand,
    )
    # everything is computed before anything is written: errors leave no partial outputs
    picture = encode_picture(render_result(rgb, result), Path(args.out).suffix) if args.out else None
    doc = result.to_dict()
    doc["image"]["path"] = str(image)
    text = json.dumps(doc, indent=2)
    if picture is not None:
        write_atomic(args.out, picture)
    if args.json_out == "-":
        print(text)
    elif args.json_out:
        write_atomic(args.json_out, (text + "\n").encode())
    if args.json_out != "-":
        print(result.text)
    return 0

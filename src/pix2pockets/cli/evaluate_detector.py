"""``pix2pockets evaluate detector``: Table-1 metrics of a detector on a YOLO dataset."""

from __future__ import annotations

import argparse

from pix2pockets.cli.detector_options import add_detector_options, detector_from_args
from pix2pockets.files import check_output, write_json


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "detector",
        help="precision, recall, F1, AP50, AP50:95 per class, before | after post-processing",
        description="Evaluate on a YOLO-format dataset (Roboflow layout). --agnostic scores class-agnostic "
        "balls, e.g. on ball-only photos: --ball-classes 0 for a set whose class 0 is 'Ball'.",
    )
    parser.add_argument("--data", required=True, help="YOLO dataset folder")
    parser.add_argument("--json", required=True, dest="json_out", help="output JSON file")
    parser.add_argument("--split", default="test", help="split folder (default test)")
    add_detector_options(parser)
    parser.add_argument("--detector", choices=["onnx", "hough"], default="onnx", help="onnx (default) or hough")
    parser.add_argument("--hough-radii", default="15,30", help="hough: min ball radius, max radius px (paper 15,30)")
    parser.add_argument("--agnostic", action="store_true", help="class-agnostic ball metrics")
    parser.add_argument("--ball-classes", default="0,1,2,3", help="dataset ids that are balls (agnostic mode)")
    parser.add_argument(
        "--table-class",
        type=int,
        default=None,
        help="agnostic mode: dataset id of a whole-table box; diamonds found outside it are counted (false)",
    )
    parser.add_argument("--conf", type=float, default=0.25, help="confidence threshold for P/R/F1 (default 0.25)")
    parser.add_argument("--limit", type=int, default=None, help="only the first N images")
    parser.add_argument(
        "--post",
        choices=["paper", "class-aware"],
        default="paper",
        help="post-processing of the 'after' column: the paper's NMS + caps (default) or the pipeline's "
        "class-aware one",
    )
    parser.add_argument(
        "--cameras",
        default=None,
        help="rendered datasets: score only images taken with these camera kinds, comma-separated, e.g. "
        "'broadcast' (top,high,jib) or 'phone,phone_low,low' (read from meta/*.json; default: all images)",
    )
    parser.add_argument("--force", action="store_true", help="overwrite an existing --json file")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from pix2pockets.synth.cameras import camera_kinds
    from pix2pockets.vision.metrics.evaluation import EvalOptions, evaluate_detector, format_table

    check_output(args.json_out, args.force)
    try:
        ball_classes = tuple(int(v) for v in args.ball_classes.split(",") if v.strip())
    except ValueError as err:
        raise ValueError(f"--ball-classes must be comma-separated integers, got {args.ball_classes!r}") from err
    if args.detector == "hough":
        from pix2pockets.vision.metrics.hough import HoughDetector, HoughParams

        try:
            r_min, r_max = (int(v) for v in args.hough_radii.split(","))
        except ValueError as err:
            raise ValueError(f"--hough-radii must be two integers like 15,30, got {args.hough_radii!r}") from err
        detector = HoughDetector(HoughParams(min_radius_ball=r_min, max_radius=r_max), diamonds=not args.agnostic)
        model = "hough"
    else:
        detector = detector_from_args(args, 0.01)
        model = str(detector.model_path)
        for stage in (detector.ball_refiner, detector.classifier, detector.number_reader, detector.diamond_refiner):
            if stage is not None:
                model += f" + {stage.model_path}"
    if args.table_class is not None and not args.agnostic:
        raise ValueError("--table-class works with --agnostic (ball-only photos with a table box)")
    opts = EvalOptions(
        args.split,
        args.agnostic,
        ball_classes,
        args.conf,
        limit=args.limit,
        post=args.post,
        table_class=args.table_class,
        camera_kinds=None if args.cameras is None else camera_kinds(args.cameras),
    )
    report = evaluate_detector(detector, args.data, opts, progress=not args.quiet)
    report.update({"data": str(args.data), "model": model, "conf_threshold": args.conf})
    write_json(args.json_out, report, indent=1)
    print(format_table(report))
    return 0

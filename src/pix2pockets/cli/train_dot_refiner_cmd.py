"""``pix2pockets train-dot-refiner``: train the second-stage diamond refiner on crops (needs torch)."""

from __future__ import annotations

import argparse

from pix2pockets.cli.train_ball_classifier_cmd import parse_widths


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "train-dot-refiner",
        help="train the diamond refiner (a diamond's centre from a crop) and export ONNX ('train' extra)",
        description="Cut 32 px crops around every labelled diamond, shifted and scaled as the detector's would be, "
        "from YOLO datasets, train a small CNN to find the diamond's centre and write OUT/dot-refiner.onnx and "
        "OUT/metrics.json (centre errors on the datasets' test splits).",
    )
    parser.add_argument("--data", action="append", default=[], help="YOLO dataset with diamond labels (repeatable)")
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--epochs", type=int, default=10, help="passes over the crops (default 10)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--batch", type=int, default=256, help="crops per step (default 256)")
    parser.add_argument("--lr", type=float, default=3e-3, help="peak learning rate (default 3e-3)")
    parser.add_argument("--threads", type=int, default=1, help="torch CPU threads (default 1)")
    parser.add_argument("--widths", default="16,32,64", help="channels of the three network stages (default 16,32,64)")
    parser.add_argument("--copies", type=int, default=3, help="shifted crops per labelled diamond (default 3)")
    parser.add_argument(
        "--centre-jitter", type=float, default=0.6, help="largest crop centre shift in diamond sides (default 0.6)"
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        from pix2pockets.vision.train.dot_trainer import DotTrainConfig, train_dot_refiner
    except ImportError as err:
        raise ValueError(f"train-dot-refiner needs torch (pip install 'pix2pockets[train]'): {err}") from err
    cfg = DotTrainConfig(
        data=tuple(args.data),
        out=args.out,
        epochs=args.epochs,
        seed=args.seed,
        batch=args.batch,
        lr=args.lr,
        threads=args.threads,
        widths=parse_widths(args.widths),
        copies=args.copies,
        centre_jitter=args.centre_jitter,
    )
    print(f"wrote {train_dot_refiner(cfg, progress=not args.quiet)}")
    return 0

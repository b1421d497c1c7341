"""``pix2pockets train-table``: train the table model (playing surface, corners, side pockets) on renders."""

from __future__ import annotations

import argparse


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "train-table",
        help="train the table model (surface, corners, side pockets) on renders and export ONNX ('train' extra)",
        description="Read 'pix2pockets synth' datasets (images and meta/*.json), train the table model on their "
        "train splits (targets from each render's camera: the playing surface, its four corners and its two side "
        "pockets), measure it on their valid splits and write OUT/table.onnx, OUT/metrics.json and OUT/last.pt.",
    )
    parser.add_argument("--data", action="append", default=[], help="'pix2pockets synth' dataset (repeatable)")
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument(
        "--init",
        default=None,
        help="fp32 ONNX that starts the network: a table model (fine-tune) or a detector (its trunk and neck)",
    )
    parser.add_argument("--epochs", type=int, default=12, help="passes over the renders (default 12)")
    parser.add_argument("--batch", type=int, default=32, help="renders per step (default 32)")
    parser.add_argument("--lr", type=float, default=2e-3, help="peak learning rate (default 2e-3)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--workers", type=int, default=0, help="data-loading processes (default 0)")
    parser.add_argument("--device", default="auto", help="cpu, cuda or auto (default auto)")
    parser.add_argument("--quiet", action="store_true", help="no per-epoch report")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        from pix2pockets.vision.train.table import TableTrainConfig, train_table
    except ImportError as err:
        raise ValueError(f"train-table needs torch (pip install 'pix2pockets[train]'): {err}") from err
    cfg = TableTrainConfig(
        data=tuple(args.data),
        out=args.out,
        init=args.init,
        epochs=args.epochs,
        batch=args.batch,
        lr=args.lr,
        seed=args.seed,
        workers=args.workers,
        device=args.device,
    )
    print(f"wrote {train_table(cfg, progress=not args.quiet)}")
    return 0

"""``pix2pockets train-ball-numbers``: train the ball-number reader on render crops (needs torch)."""

from __future__ import annotations

import argparse

from pix2pockets.cli.crop_training_options import add_crop_training_options, crop_training_settings


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "train-ball-numbers",
        help="train the ball-number reader (which of the 16 balls a crop shows) and export ONNX ('train' extra)",
        description="Cut 32 px crops around every labelled ball of 'pix2pockets synth' renders (their meta/ "
        "sidecars hold the numbers), train a small CNN to tell the 16 balls apart and write "
        "OUT/ball-numbers.onnx and OUT/metrics.json (accuracy on the datasets' test splits, overall and within "
        "each ball's class).",
    )
    add_crop_training_options(
        parser,
        data_help="'pix2pockets synth' dataset",
        epochs=6,
        copies=1,
        centre_jitter=0.06,
        thing="ball",
        size_unit="ball diameters",
    )
    parser.add_argument(
        "--min-visible",
        type=float,
        default=0.3,
        help="leave out balls showing less of their outline than this (default 0.3)",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        from pix2pockets.vision.train.number_reader_trainer import NumberTrainConfig, train_number_reader
    except ImportError as err:
        raise ValueError(f"train-ball-numbers needs torch (pip install 'pix2pockets[train]'): {err}") from err
    cfg = NumberTrainConfig(**crop_training_settings(args), min_visible=args.min_visible)
    print(f"wrote {train_number_reader(cfg, progress=not args.quiet)}")
    return 0

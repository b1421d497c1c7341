"""``pix2pockets train-ball-refiner``: train the second-stage ball box refiner on crops (needs torch)."""

from __future__ import annotations

import argparse

from pix2pockets.cli.crop_training_options import add_crop_training_options, crop_training_settings


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "train-ball-refiner",
        help="train the ball box refiner (a ball's box from a crop) and export ONNX ('train' extra)",
        description="Cut 32 px crops around every labelled ball, shifted and scaled as the detector's boxes would be, "
        "from YOLO datasets, train a small CNN to find the ball's box and write OUT/ball-refiner.onnx and "
        "OUT/metrics.json (box IoUs on the datasets' test splits before and after).",
    )
    add_crop_training_options(
        parser,
        data_help="YOLO dataset with ball labels",
        epochs=6,
        copies=3,
        centre_jitter=0.1,
        thing="ball",
        size_unit="ball diameters (standard deviation)",
    )
    parser.add_argument(
        "--stretch",
        type=float,
        default=0.3,
        help="share of crops cut with a window of another aspect (0.5-2), the ball squashed in them as in a "
        "stretched photo (default 0.3)",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        from pix2pockets.vision.train.ball_refiner_trainer import BallRefinerTrainConfig, train_ball_refiner
    except ImportError as err:
        raise ValueError(f"train-ball-refiner needs torch (pip install 'pix2pockets[train]'): {err}") from err
    cfg = BallRefinerTrainConfig(**crop_training_settings(args), stretch=args.stretch)
    print(f"wrote {train_ball_refiner(cfg, progress=not args.quiet)}")
    return 0

"""``pix2pockets train-diamond-refiner``: train the second-stage diamond refiner on crops (needs torch)."""

from __future__ import annotations

import argparse

from pix2pockets.cli.crop_training_options import add_crop_training_options, crop_training_settings


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "train-diamond-refiner",
        help="train the diamond refiner (a diamond's box from a crop) and export ONNX ('train' extra)",
        description="Cut 32 px crops around every labelled diamond, shifted and scaled as the detector's would be, "
        "from YOLO datasets, train a small CNN to find the diamond's centre and box and write OUT/diamond-refiner.onnx "
        "and OUT/metrics.json (centre errors and box IoUs on the datasets' test splits).",
    )
    add_crop_training_options(
        parser,
        data_help="YOLO dataset with diamond labels",
        epochs=10,
        copies=3,
        centre_jitter=0.6,
        thing="diamond",
        size_unit="diamond sides",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        from pix2pockets.vision.train.diamond_trainer import DiamondTrainConfig, train_diamond_refiner
    except ImportError as err:
        raise ValueError(f"train-diamond-refiner needs torch (pip install 'pix2pockets[train]'): {err}") from err
    cfg = DiamondTrainConfig(**crop_training_settings(args))
    print(f"wrote {train_diamond_refiner(cfg, progress=not args.quiet)}")
    return 0

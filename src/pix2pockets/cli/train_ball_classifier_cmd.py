"""``pix2pockets train-ball-classifier``: train the second-stage ball classifier on crops (needs torch)."""

from __future__ import annotations

import argparse

from pix2pockets.cli.crop_training_options import add_crop_training_options, crop_training_settings
from pix2pockets.cli.parsing import parse_number_pair


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "train-ball-classifier",
        help="train the crop classifier (cue, black, solid, stripe, no ball) and export ONNX ('train' extra)",
        description="Cut square crops (32 px by default) around every labelled ball (and ball-sized crops with no "
        "ball) from YOLO datasets, train a small CNN on them and write OUT/ball-classifier.onnx and "
        "OUT/metrics.json (confusion matrix on the datasets' test splits).",
    )
    add_crop_training_options(
        parser,
        data_help="YOLO dataset with the five classes",
        epochs=6,
        copies=1,
        centre_jitter=0.06,
        thing="ball",
        size_unit="ball diameters",
    )
    parser.add_argument("--negatives", action="append", default=[], help="ball-only dataset for 'no ball' crops")
    parser.add_argument("--negatives-exclude", action="append", default=[], help="file-name glob left out")
    parser.add_argument(
        "--head",
        choices=("grid", "mean"),
        default="grid",
        help="read the 4x4-pooled feature map (grid, default) or its mean over the crop (mean, the v2 classifier)",
    )
    parser.add_argument("--crop-size", type=int, default=32, help="crop side in px, a multiple of 8 (default 32)")
    parser.add_argument("--scale-jitter", default="0.92,1.09", help="crop scale range lo,hi (default 0.92,1.09)")
    parser.add_argument(
        "--low-res", type=float, default=0.4, help="share of crops re-sampled through 7-20 px (default 0.4)"
    )
    parser.add_argument(
        "--class-power",
        type=float,
        default=0.5,
        help="loss weight of a class = frequency ** -POWER (default 0.5; 0: unweighted)",
    )
    parser.add_argument(
        "--icon-negatives",
        type=float,
        default=0.0,
        help="flat ball icons of broadcast graphics as 'no ball' crops, per labelled-ball crop (default 0)",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        from pix2pockets.vision.train.crop_classifier import CropTrainConfig, train_crop_classifier
    except ImportError as err:
        raise ValueError(f"train-ball-classifier needs torch (pip install 'pix2pockets[train]'): {err}") from err
    cfg = CropTrainConfig(
        **crop_training_settings(args),
        negatives=tuple(args.negatives),
        negatives_exclude=tuple(args.negatives_exclude),
        head=args.head,
        scale_jitter=parse_number_pair(args.scale_jitter, "--scale-jitter", "0.92,1.09"),
        low_res=args.low_res,
        class_power=args.class_power,
        crop_size=args.crop_size,
        icon_negatives=args.icon_negatives,
    )
    print(f"wrote {train_crop_classifier(cfg, progress=not args.quiet)}")
    return 0

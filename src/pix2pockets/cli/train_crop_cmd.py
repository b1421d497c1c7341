"""``pix2pockets train-ball-classifier | train-ball-refiner | train-diamond-refiner | train-ball-numbers``: train a
second-stage crop network and export it to ONNX (needs the ``train`` extra).

The four commands share their options and their run; each is one :class:`CropTrainCommand` row of
:data:`CROP_COMMANDS`: its defaults, its own extra options, and the training function and config it runs.
"""

from __future__ import annotations

import argparse
import importlib
from collections.abc import Callable
from dataclasses import dataclass, field

from pix2pockets.cli.parsing import parse_number_pair


@dataclass(frozen=True)
class CropTrainCommand:
    """One crop-network training command.

    Attributes:
        name: the sub-command.
        help, description: its help texts.
        module: the training module under ``pix2pockets.vision.train``.
        config, train: the module's config class and training function (``train(cfg, progress) -> Path``).
        data_help: what a --data dataset must hold.
        epochs, copies, centre_jitter: defaults of the shared options.
        thing: one labelled object ("ball"), for the --copies help.
        size_unit: the unit of --centre-jitter.
        add_options: adds the command's own options to its parser.
        options: the command's own options as config keyword arguments.
    """

    name: str
    help: str
    description: str
    module: str
    config: str
    train: str
    data_help: str
    epochs: int
    copies: int
    centre_jitter: float
    thing: str
    size_unit: str
    add_options: Callable[[argparse.ArgumentParser], None] = field(default=lambda parser: None)
    options: Callable[[argparse.Namespace], dict] = field(default=lambda args: {})


def _classifier_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--negatives", action="append", default=[], help="ball-only dataset for 'no ball' crops")
    parser.add_argument("--negatives-exclude", action="append", default=[], help="file-name glob left out")
    parser.add_argument(
        "--head",
        choices=("grid", "mean"),
        default="grid",
        help="read the 4x4-pooled feature map (grid, default) or its mean over the crop (mean)",
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
    parser.add_argument(
        "--hard-negatives",
        type=int,
        default=0,
        help="copies of each false ball the bundled detector finds on the training images (pockets, cue tips) "
        "as 'no ball' crops (default 0)",
    )
    parser.add_argument(
        "--init",
        default=None,
        help="start from this fp32 classifier ONNX (e.g. the bundled one) instead of random weights; its widths, "
        "head and crop size must be the ones asked for",
    )


def _classifier_settings(args: argparse.Namespace) -> dict:
    return {
        "negatives": tuple(args.negatives),
        "negatives_exclude": tuple(args.negatives_exclude),
        "head": args.head,
        "scale_jitter": parse_number_pair(args.scale_jitter, "--scale-jitter", "0.92,1.09"),
        "low_res": args.low_res,
        "class_power": args.class_power,
        "crop_size": args.crop_size,
        "icon_negatives": args.icon_negatives,
        "hard_negatives": args.hard_negatives,
        "init": args.init,
    }


def _stretch_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--stretch",
        type=float,
        default=0.3,
        help="share of crops cut with a window of another aspect (0.5-2), the ball squashed in them as in a "
        "stretched photo (default 0.3)",
    )


def _min_visible_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--min-visible",
        type=float,
        default=0.3,
        help="leave out balls showing less of their outline than this (default 0.3)",
    )


CROP_COMMANDS: tuple[CropTrainCommand, ...] = (
    CropTrainCommand(
        "train-ball-classifier",
        "train the crop classifier (cue, black, solid, stripe, no ball) and export ONNX ('train' extra)",
        "Cut square crops (32 px by default) around every labelled ball (and ball-sized crops with no ball) from "
        "YOLO datasets, train a small CNN on them and write OUT/ball-classifier.onnx and OUT/metrics.json "
        "(confusion matrix on the datasets' test splits).",
        "ball_classifier",
        "CropTrainConfig",
        "train_crop_classifier",
        "YOLO dataset with the five classes",
        epochs=6,
        copies=1,
        centre_jitter=0.06,
        thing="ball",
        size_unit="ball diameters",
        add_options=_classifier_options,
        options=_classifier_settings,
    ),
    CropTrainCommand(
        "train-ball-refiner",
        "train the ball box refiner (a ball's box from a crop) and export ONNX ('train' extra)",
        "Cut 32 px crops around every labelled ball, shifted and scaled as the detector's boxes would be, from "
        "YOLO datasets, train a small CNN to find the ball's box and write OUT/ball-refiner.onnx and "
        "OUT/metrics.json (box IoUs on the datasets' test splits, of the crop's middle and of the refined box).",
        "ball_refiner",
        "BallRefinerTrainConfig",
        "train_ball_refiner",
        "YOLO dataset with ball labels",
        epochs=6,
        copies=3,
        centre_jitter=0.1,
        thing="ball",
        size_unit="ball diameters (standard deviation)",
        add_options=_stretch_option,
        options=lambda args: {"stretch": args.stretch},
    ),
    CropTrainCommand(
        "train-diamond-refiner",
        "train the diamond refiner (a diamond's box from a crop) and export ONNX ('train' extra)",
        "Cut 32 px crops around every labelled diamond, shifted and scaled as the detector's would be, from YOLO "
        "datasets, train a small CNN to find the diamond's centre and box and write OUT/diamond-refiner.onnx and "
        "OUT/metrics.json (centre errors and box IoUs on the datasets' test splits).",
        "diamond_refiner",
        "DiamondTrainConfig",
        "train_diamond_refiner",
        "YOLO dataset with diamond labels",
        epochs=10,
        copies=3,
        centre_jitter=0.6,
        thing="diamond",
        size_unit="diamond sides",
    ),
    CropTrainCommand(
        "train-ball-numbers",
        "train the ball-number reader (which of the 16 balls a crop shows) and export ONNX ('train' extra)",
        "Cut 32 px crops around every labelled ball of 'pix2pockets synth' renders (their meta/ sidecars hold the "
        "numbers), train a small CNN to tell the 16 balls apart and write OUT/ball-numbers.onnx and "
        "OUT/metrics.json (accuracy on the datasets' test splits, overall and within each ball's class).",
        "ball_numbers",
        "NumberTrainConfig",
        "train_number_reader",
        "'pix2pockets synth' dataset",
        epochs=6,
        copies=1,
        centre_jitter=0.06,
        thing="ball",
        size_unit="ball diameters",
        add_options=_min_visible_option,
        options=lambda args: {"min_visible": args.min_visible},
    ),
)


def register(sub: argparse._SubParsersAction) -> None:
    """Add every command of :data:`CROP_COMMANDS`."""
    for command in CROP_COMMANDS:
        parser = sub.add_parser(command.name, help=command.help, description=command.description)
        add_crop_training_options(
            parser,
            data_help=command.data_help,
            epochs=command.epochs,
            copies=command.copies,
            centre_jitter=command.centre_jitter,
            thing=command.thing,
            size_unit=command.size_unit,
        )
        command.add_options(parser)
        parser.set_defaults(func=run, crop_command=command)


def run(args: argparse.Namespace) -> int:
    command: CropTrainCommand = args.crop_command
    try:
        module = importlib.import_module(f"pix2pockets.vision.train.{command.module}")
    except ImportError as err:
        raise ValueError(f"{command.name} needs torch (pip install 'pix2pockets[train]'): {err}") from err
    cfg = getattr(module, command.config)(**crop_training_settings(args), **command.options(args))
    print(f"wrote {getattr(module, command.train)(cfg, progress=not args.quiet)}")
    return 0


def add_crop_training_options(
    parser: argparse.ArgumentParser,
    *,
    data_help: str,
    epochs: int,
    copies: int,
    centre_jitter: float,
    thing: str,
    size_unit: str,
) -> None:
    """--data, --out, --epochs, --seed, --batch, --lr, --threads, --widths, --copies, --centre-jitter, --quiet.

    Args:
        parser: the sub-command's parser.
        data_help: what a --data dataset must hold.
        epochs, copies, centre_jitter: the command's defaults.
        thing: one labelled object ("ball"), for the --copies help.
        size_unit: the unit of --centre-jitter ("ball diameters").
    """
    parser.add_argument("--data", action="append", default=[], help=f"{data_help} (repeatable)")
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--epochs", type=int, default=epochs, help=f"passes over the crops (default {epochs})")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--batch", type=int, default=256, help="crops per step (default 256)")
    parser.add_argument("--lr", type=float, default=3e-3, help="peak learning rate (default 3e-3)")
    parser.add_argument("--threads", type=int, default=1, help="torch CPU threads (default 1)")
    parser.add_argument("--widths", default="16,32,64", help="channels of the three network stages (default 16,32,64)")
    parser.add_argument(
        "--copies", type=int, default=copies, help=f"shifted crops per labelled {thing} (default {copies})"
    )
    parser.add_argument(
        "--centre-jitter",
        type=float,
        default=centre_jitter,
        help=f"largest crop centre shift in {size_unit} (default {centre_jitter})",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def crop_training_settings(args: argparse.Namespace) -> dict:
    """The shared options as keyword arguments of the training configs."""
    return {
        "data": tuple(args.data),
        "out": args.out,
        "epochs": args.epochs,
        "seed": args.seed,
        "batch": args.batch,
        "lr": args.lr,
        "threads": args.threads,
        "widths": parse_widths(args.widths),
        "copies": args.copies,
        "centre_jitter": args.centre_jitter,
    }


def parse_widths(text: str) -> tuple[int, ...]:
    """Channel counts from ``24,48,96``; their number and range are checked by the training config."""
    try:
        return tuple(int(v) for v in text.split(","))
    except ValueError as err:
        raise ValueError(f"--widths needs three comma-separated channel counts like 24,48,96, got {text!r}") from err

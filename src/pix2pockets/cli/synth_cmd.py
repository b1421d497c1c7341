"""``pix2pockets synth``: render a labelled synthetic dataset (YOLO / Roboflow layout + JSON labels)."""

from __future__ import annotations

import argparse

from pix2pockets.scale.ray_pool import add_ray_arguments
from pix2pockets.synth.cameras import BROADCAST_KINDS, CAMERA_KINDS
from pix2pockets.synth.layouts import LAYOUT_MODES


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "synth",
        help="render synthetic pool-table photos with exact labels (YOLO dataset + JSON)",
        description="Render N labelled synthetic photos of 8-ball tables into a YOLO dataset in the Roboflow "
        "export layout (data.yaml, train|valid|test/images|labels) with one JSON label file per image.",
    )
    parser.add_argument("--n", type=int, required=True, help="number of scenes to render")
    parser.add_argument("--out", required=True, help="output folder (must be empty unless --force)")
    parser.add_argument("--seed", type=int, default=0, help="dataset seed (default 0); same seed, same images")
    parser.add_argument("--views", type=int, default=1, choices=[1, 3], help="3: each scene from top, 45 deg, front")
    parser.add_argument("--size", default="960x540", help="image size WxH (default 960x540)")
    parser.add_argument("--split", default="0.8,0.1,0.1", help="train,valid,test fractions (default 0.8,0.1,0.1)")
    parser.add_argument(
        "--only-split",
        choices=["train", "valid", "test"],
        default=None,
        help="render only the scenes of this split (the same images the whole dataset holds there)",
    )
    parser.add_argument(
        "--layout",
        choices=list(LAYOUT_MODES),
        default=None,
        help="every scene's ball layout of this kind, e.g. 'rack' (default: drawn per scene as in real games)",
    )
    parser.add_argument(
        "--cameras",
        default=None,
        help=f"draw each camera among these kinds, comma-separated: {', '.join(CAMERA_KINDS)}, or 'broadcast' "
        f"({','.join(BROADCAST_KINDS)}; default: all kinds)",
    )
    parser.add_argument(
        "--portrait",
        type=float,
        default=0.0,
        metavar="SHARE",
        help="share of phone views held upright, rendered at HxW (default 0: every frame is --size)",
    )
    parser.add_argument(
        "--blackball",
        type=float,
        default=0.0,
        metavar="SHARE",
        help="share of scenes with a blackball set (reds, yellows, black) on a UK table (default 0; 1: every scene); "
        "reds take the solid class id, yellows the stripe class id",
    )
    parser.add_argument("--force", action="store_true", help="overwrite a non-empty output folder")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    add_ray_arguments(parser, "render on Ray workers, the same bytes as one process")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from pix2pockets.synth.dataset import parse_split, write_dataset
    from pix2pockets.synth.renderer import parse_size

    size = parse_size(args.size)
    split = parse_split(args.split)
    options = {
        "seed": args.seed,
        "size": size,
        "views": args.views,
        "split": split,
        "force": args.force,
        "progress": not args.no_progress,
        "only_split": args.only_split,
        "layout_mode": args.layout,
        "camera_kinds": args.cameras,
        "portrait": args.portrait,
        "blackball": args.blackball,
    }
    if args.ray is None:
        if args.workers is not None:
            raise ValueError("--workers applies with --ray")
        manifest = write_dataset(args.out, args.n, **options)
    else:
        from pix2pockets.scale import RayPool
        from pix2pockets.scale.synth import ray_scene_map

        with RayPool(args.ray, args.workers) as pool:
            manifest = write_dataset(args.out, args.n, scene_map=ray_scene_map(pool), **options)
    counts = ", ".join(f"{k} {v}" for k, v in manifest["counts"].items())
    print(f"wrote {sum(manifest['counts'].values())} images to {args.out} ({counts})")
    return 0

"""Turn the real photos with labelled table corners into a table-model training set.

The labels (``benchmarks/data/real_table_corners.json``, read by eye: the cloth's outer edge of every whole-table
photo of ``../shared/data/real-snooker-vision``) fix the cloth outline in each photo. The table model learns the
playing surface, its corners and its side pockets, so each photo needs a camera: the pipeline's own table fit
(bundled detector and table model) gives a start, its corners are matched to the labelled ones, and the camera is
moved to see the cloth outline exactly there (the fit's way round the table, which its side pockets chose, else
turned a quarter). The output is a ``pix2pockets synth``-like folder that
``pix2pockets train-table --data`` reads: ``split/images/*.jpg`` and ``split/meta/*.json`` (camera and table size).

Photos are split into folds for an honest measure: frames of the pub video in contiguous blocks (neighbouring
frames look alike), the other photos in turn. ``--fold i`` puts fold ``i`` in ``valid`` and the rest in ``train``;
``--folds 1`` puts every photo in ``train``.

Usage:
    PYTHONPATH=src python scripts/real_table_dataset.py --out DIR [--folds 2 --fold 0] [--data DIR] [--draw DIR]
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

import cv2
import numpy as np

from pix2pockets.pipeline.photo import clean_detections, default_detector, read_surface
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.table.cloth_edge import MIN_FOCAL, camera_onto_outline
from pix2pockets.vision.table.estimate import estimate_table
from pix2pockets.vision.table.fit import TableFitError
from pix2pockets.vision.table.outline_camera import CUSHION_WIDTH, outline_rectangle
from pix2pockets.vision.table.quad_geometry import quad_length, quad_of_point_sets
from pix2pockets.vision.train.table_data import SIDE_POCKETS

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "benchmarks"))
from real_table_corners import match_corners  # noqa: E402

DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "real-snooker-vision"
DEFAULT_LABELS = HERE.parent / "benchmarks" / "data" / "real_table_corners.json"
MAX_MISFIT = 0.01
"""A camera must meet the labelled corners within this share of the table's length in the photo."""


def fold_of(names: list[str], folds: int) -> dict[str, int]:
    """Each photo's fold: video frames (``yt-<video>-<frame>``) in ``folds`` contiguous blocks of frame numbers,
    the other photos in turn by name."""
    frames = sorted((n for n in names if re.match(r"yt-.+-\d+_", n)), key=lambda n: int(n.split("-")[-1][:4]))
    others = sorted(n for n in names if n not in set(frames))
    out = {n: i * folds // len(frames) for i, n in enumerate(frames)}
    out.update({n: i % folds for i, n in enumerate(others)})
    return out


def labelled_camera(image: np.ndarray, labels_px: np.ndarray, detector):
    """(spec, camera) that see the labelled cloth outline, or None."""
    det = clean_detections(detector.detect(image))
    size = (image.shape[1], image.shape[0])
    try:
        fit = estimate_table(
            image, det, size, None, pixel_aspect=det.pixel_aspect, surface=read_surface(image, det, True)
        )
    except TableFitError:
        return None
    spec = fit.spec
    fitted = fit.camera.project_table(outline_rectangle(spec, CUSHION_WIDTH), spec.cushion_height)
    order = match_corners(labels_px, fitted)
    floor = MIN_FOCAL * max(size)
    for shift in (0, 1):  # the fit's way round the table, else turned a quarter
        corners = np.empty((4, 2))
        corners[np.roll(order, shift)] = labels_px
        camera = camera_onto_outline(fit.camera, spec, corners, floor)
        if camera is None:
            continue
        seen = camera.project_table(outline_rectangle(spec, CUSHION_WIDTH), spec.cushion_height)
        if np.abs(seen - corners).max() <= MAX_MISFIT * quad_length(labels_px):
            return spec, camera
    return None


def meta_of(spec, camera, image_name: str, split: str) -> dict:
    return {
        "image": image_name,
        "split": split,
        "source": "real photo, cloth outline labelled by eye",
        "camera": {"K": camera.K.tolist(), "R": camera.R.tolist(), "t": camera.t.tolist()},
        "table": {"name": spec.name, "length_m": spec.length, "width_m": spec.width},
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the real-snooker-vision folder")
    ap.add_argument("--labels", type=Path, default=DEFAULT_LABELS)
    ap.add_argument("--out", type=Path, required=True, help="new folder for the training set")
    ap.add_argument("--folds", type=int, default=1)
    ap.add_argument("--fold", type=int, default=0, help="the fold written to valid (with --folds > 1)")
    ap.add_argument("--draw", type=Path, default=None, help="folder for each photo with its surface drawn")
    args = ap.parse_args()
    if args.out.exists():
        raise SystemExit(f"{args.out} exists: give a new folder")
    entries = [e for e in json.loads(args.labels.read_text())["photos"] if e["whole_table"]]
    names = [Path(e["image"]).name for e in entries]
    folds = fold_of(names, args.folds)
    detector = default_detector()
    written = skipped = 0
    for entry, name in zip(entries, names, strict=True):
        split = "valid" if args.folds > 1 and folds[name] == args.fold else "train"
        image = read_image_rgb(args.data / entry["image"])
        found = labelled_camera(image, quad_of_point_sets(entry["lines"]), detector)
        if found is None:
            print(f"skipped (no camera meets the labels): {name}")
            skipped += 1
            continue
        spec, camera = found
        stem = Path(name).stem
        for sub in ("images", "meta"):
            (args.out / split / sub).mkdir(parents=True, exist_ok=True)
        bgr = cv2.cvtColor(image, cv2.COLOR_RGB2BGR)
        cv2.imwrite(str(args.out / split / "images" / f"{stem}.jpg"), bgr, [cv2.IMWRITE_JPEG_QUALITY, 95])
        meta = meta_of(spec, camera, f"{stem}.jpg", split)
        (args.out / split / "meta" / f"{stem}.json").write_text(json.dumps(meta, indent=1))
        written += 1
        if args.draw:
            args.draw.mkdir(parents=True, exist_ok=True)
            surface = camera.project_table(outline_rectangle(spec, 0.0), 0.0)
            cv2.polylines(bgr, [np.round(surface).astype(np.int32)], True, (255, 0, 255), 1, cv2.LINE_AA)
            for p in camera.project_table(spec.pocket_aims[list(SIDE_POCKETS)], 0.0):
                cv2.circle(bgr, tuple(int(v) for v in np.round(p)), 5, (0, 255, 255), 1)
            cv2.imwrite(str(args.draw / f"{stem}.png"), bgr)
    print(f"wrote {written} photos to {args.out} ({skipped} skipped)")


if __name__ == "__main__":
    main()

"""The whole pipeline on real phone photos: how often it gives a shot, and why not.

Runs ``pipeline.suggest`` (detect, fit the table, locate, plan) on every photo listed in
``benchmarks/data/real_ball_classes.json`` (30 phone photos of numbered pool sets in
``../shared/data/real-snooker-vision``, squashed to 640x640 by their export) and counts the photos that get a
shot and the reasons of the others (the first clause of the error). There is no truth for the table here: a
fitted table is drawn, not scored (``--draw DIR``).

Usage:
    PYTHONPATH=src python benchmarks/real_pipeline.py [--data DIR] [--labels FILE] [--table auto|9ft|8ft|7ft|6ft]
        [--draw DIR] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import collections
import json
import time
from pathlib import Path

import numpy as np

from pix2pockets.geometry import table_preset
from pix2pockets.pipeline.draw import render_result
from pix2pockets.pipeline.photo import suggest
from pix2pockets.vision.image_io import read_image_rgb

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "real-snooker-vision"
DEFAULT_LABELS = HERE / "data" / "real_ball_classes.json"


def reason(error: ValueError) -> str:
    """The error's first clause: what failed, without the numbers and advice that follow."""
    return str(error).split(":")[0].split(" (")[0]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the real-snooker-vision folder")
    ap.add_argument("--labels", type=Path, default=DEFAULT_LABELS, help="photo list (the ball classes JSON)")
    ap.add_argument("--table", default="auto", choices=["auto", "9ft", "8ft", "7ft", "6ft"])
    ap.add_argument("--draw", type=Path, default=None, help="folder for the drawn results of the photos that fit")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()

    spec = None if args.table == "auto" else table_preset(args.table)
    photos = [entry["image"] for entry in json.loads(args.labels.read_text())["images"]]
    if args.draw:
        args.draw.mkdir(parents=True, exist_ok=True)
    rows, seconds = [], []
    for name in photos:
        path = args.data / name
        if not path.is_file():
            raise SystemExit(f"{path} not found: pass --data, the real-snooker-vision folder")
        image = read_image_rgb(path)
        t = time.perf_counter()
        try:
            result = suggest(image, spec=spec, rng=np.random.default_rng(0))
        except ValueError as err:
            rows.append({"image": name, "shot": None, "reason": reason(err), "error": str(err)})
            continue
        finally:
            seconds.append(time.perf_counter() - t)
        rows.append({"image": name, "shot": result.text, "reason": None, "error": None})
        if args.draw:
            import cv2

            drawn = render_result(image, result)
            cv2.imwrite(str(args.draw / (Path(name).stem + ".png")), cv2.cvtColor(drawn, cv2.COLOR_RGB2BGR))
    reasons = collections.Counter(r["reason"] for r in rows if r["reason"])
    n_shot = sum(r["shot"] is not None for r in rows)
    print(f"{n_shot} of {len(rows)} photos get a shot ({args.table} table); median {np.median(seconds):.2f} s a photo")
    for text, count in reasons.most_common():
        print(f"{count:>4}  {text}")
    if args.json:
        report = {"table": args.table, "photos": len(rows), "with_shot": n_shot, "reasons": dict(reasons), "rows": rows}
        Path(args.json).write_text(json.dumps(report, indent=1) + "\n")


if __name__ == "__main__":
    main()

"""The chances shown for real photos, with and without the photo's ball-position errors.

Runs ``pipeline.suggest`` on the 30 real phone photos of ``benchmarks/data/real_ball_classes.json`` and the 30 real
video frames (the ``valid`` split) of ``../shared/data/real-snooker-vision``, and for each photo with a shot reads the
chance shown (measured over each ball's own position error, :mod:`pix2pockets.vision.locate.position_error`), the
chance with the balls where they were located, the table fit's error and the balls' position errors. Prints a table
per group and writes the rows as JSON.

Usage:
    PYTHONPATH=src python benchmarks/real_photo_chances.py [--data DIR] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from pix2pockets.pipeline.photo import suggest

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "real-snooker-vision"
PHONE_PHOTOS = HERE / "data" / "real_ball_classes.json"


def photos(data: Path) -> dict[str, list[Path]]:
    """The two groups of real photos."""
    phone = [data / e["image"] for e in json.loads(PHONE_PHOTOS.read_text())["images"]]
    frames = sorted((data / "valid" / "images").glob("*.jpg"))
    missing = [p for p in phone + frames[:1] if not p.is_file()]
    if missing or not frames:
        raise SystemExit(
            f"{missing[0] if missing else data / 'valid'} not found: pass --data, the real-snooker-vision folder"
        )
    return {"phone photos": phone, "video frames": frames}


def read(path: Path) -> dict | None:
    """One photo's shown chance, exact-position chance, fit error and ball errors; None without a shot or for a break
    (its chance is measured on the rack made tight, not over the balls' position errors)."""
    try:
        doc = suggest(path, rng=np.random.default_rng(0)).to_dict()
    except ValueError:
        return None
    s = doc["suggestion"]
    if s.get("success_chance") is None or s.get("kind") == "break":
        return None
    return {
        "image": path.name,
        "chance": s["success_chance"]["chance"],
        "text": s["success_chance"]["text"],
        "exact": s["success_chance_exact_positions"]["chance"],
        "fit_error_px": doc["table"]["fit_error_px"],
        "ball_sigma_m": [b["position_sigma_m"] for b in doc["balls"]],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the real-snooker-vision folder")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()

    out: dict[str, dict] = {}
    print(f"{'':<14} {'shots':>5} {'chance':>7} {'exact':>7} {'>99%':>5} {'exact >99%':>10} {'ball error':>10}")
    for name, paths in photos(args.data).items():
        rows = [r for r in map(read, paths) if r is not None]
        sigmas = np.concatenate([r["ball_sigma_m"] for r in rows]) if rows else np.array([np.nan])
        summary = {
            "photos": len(paths),
            "with_shot": len(rows),
            "chance_median": float(np.median([r["chance"] for r in rows])) if rows else None,
            "exact_median": float(np.median([r["exact"] for r in rows])) if rows else None,
            "shown_above_99": sum(r["text"] == ">99%" for r in rows),
            "exact_above_99": sum(r["exact"] > 0.99 for r in rows),
            "ball_sigma_median_m": float(np.median(sigmas)),
            "ball_sigma_p90_m": float(np.percentile(sigmas, 90)),
        }
        out[name] = {"summary": summary, "rows": rows}
        su = summary
        print(
            f"{name:<14} {su['with_shot']:>5} {su['chance_median'] or 0:>7.3f} {su['exact_median'] or 0:>7.3f} "
            f"{su['shown_above_99']:>5} {su['exact_above_99']:>10} {1000 * su['ball_sigma_median_m']:>7.1f} mm"
        )
    print("chance: shown (over each ball's position error); exact: with the balls where located; ball error: median")
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()

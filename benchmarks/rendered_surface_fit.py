"""Table fits on renders of tables without sights, through the shipped models (no diamonds to fit to).

Each render (:func:`pix2pockets.synth.renderer.render`, every camera kind, build, cloth and clutter the renderer
draws) whose rails carry no sights goes through the pipeline's own steps: the bundled detector, then ``find_table`` as
``suggest`` runs it (post-processing for the ball set read from the photo, the table model, ``estimate_table`` with the
table size from the balls). The fitted playing-surface corners (on the cloth) are
compared with the render's exact ones, either way round the table; a corner's error is divided by the table's length
in the photo (the true outline's longer pair of opposite sides). Only corners within the frame count; one the fit
puts behind the camera counts as infinitely far off.

``--cloth black,red,burgundy`` keeps only renders of those cloths (the scene is drawn first, without rendering).
``--stretch-to 640x640`` resizes each render (and its corners) first, as an export that squashes every photo to one
size.

A render whose frame shows fewer than three cushions (at least :data:`CUSHION_IN_VIEW` of each cushion's length) does
not fix the table for a person either; those are counted apart, with how many the estimate refused.

Usage:
    PYTHONPATH=src python benchmarks/rendered_surface_fit.py --n 100 [--seed 5000] [--size 960x540]
        [--with-sights] [--cloth NAMES] [--stretch-to WxH] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from collections import defaultdict
from pathlib import Path

import cv2
import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")

from pix2pockets.pipeline.photo import default_detector, find_table
from pix2pockets.synth.palette import CLOTH_COLOURS
from pix2pockets.vision.table.fit import TableFitError
from pix2pockets.vision.table.quad_geometry import quad_length

CUSHION_IN_VIEW = 0.2
"""Share of a cushion's length inside the frame for it to count as in view."""


def cushions_in_view(corners: np.ndarray, image_size: tuple[int, int], samples: int = 200) -> int:
    """How many sides of the outline ``corners`` (4, 2) [px] lie at least :data:`CUSHION_IN_VIEW` inside the frame."""
    w, h = image_size
    t = np.linspace(0.0, 1.0, samples)[:, None]
    count = 0
    for k in range(4):
        pts = corners[k] + t * (corners[(k + 1) % 4] - corners[k])
        inside = (pts[:, 0] >= 0) & (pts[:, 0] <= w) & (pts[:, 1] >= 0) & (pts[:, 1] <= h)
        count += int(inside.mean() >= CUSHION_IN_VIEW)
    return count


def main(argv: list[str] | None = None) -> int:
    from pix2pockets.synth.renderer import parse_size, render, scene_of

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=100, help="renders to fit")
    ap.add_argument("--seed", type=int, default=5000, help="first render seed")
    ap.add_argument("--size", default="960x540")
    ap.add_argument("--with-sights", action="store_true", help="fit renders with sights too (the table model alone)")
    ap.add_argument("--cloth", default=None, help="only renders of these cloths, comma-separated (e.g. black,red)")
    ap.add_argument("--stretch-to", default=None, help="resize each render to WxH first (e.g. 640x640: an export)")
    ap.add_argument("--json")
    args = ap.parse_args(argv)
    size = parse_size(args.size)
    out_size = parse_size(args.stretch_to) if args.stretch_to else size
    stretch = np.array(out_size, dtype=float) / np.array(size)
    detector = default_detector()
    cloths = None if args.cloth is None else set(args.cloth.split(","))
    unknown = (cloths or set()) - set(CLOTH_COLOURS)
    if unknown:
        raise SystemExit(f"unknown cloth {sorted(unknown)}: choose from {', '.join(sorted(CLOTH_COLOURS))}")
    rows, seconds = [], []
    seed = args.seed
    while len(rows) < args.n:
        if cloths is not None and scene_of(seed).style["cloth"] not in cloths:
            seed += 1
            continue
        out = render(seed, size)
        seed += 1
        labels = out.labels
        if labels["style"]["sights"] != "none" and not args.with_sights:
            continue
        truth = np.array([c["px_cloth"] or [np.nan, np.nan] for c in labels["corners"]], dtype=float) * stretch
        w, h = out_size
        image = out.image if out_size == size else cv2.resize(out.image, out_size, interpolation=cv2.INTER_AREA)
        if not np.all(np.isfinite(truth)):
            continue
        inside = (truth[:, 0] >= 0) & (truth[:, 0] <= w) & (truth[:, 1] >= 0) & (truth[:, 1] <= h)
        row = {
            "seed": seed - 1,
            "build": labels["style"]["build"],
            "cloth": labels["style"]["cloth"],
            "corners_in_frame": int(inside.sum()),
            "cushions_in_view": cushions_in_view(truth, (w, h)),
        }
        t = time.perf_counter()
        try:
            fit = find_table(image, detector.detect(image))[3]
        except TableFitError as err:
            row.update(fit=False, error=str(err).split(":")[0])
            rows.append(row)
            continue
        seconds.append(time.perf_counter() - t)
        fitted = fit.corners_px
        errors = min(
            (np.linalg.norm(np.roll(fitted, r, axis=0) - truth, axis=1) for r in (0, 2)),
            key=lambda e: float(np.nanmax(np.where(inside, e, 0.0))),
        )
        rel = errors / quad_length(truth)  # NaN: the fit puts that corner behind the camera
        row.update(fit=True, source=fit.source, errors=[round(float(e), 5) if e == e else None for e in rel[inside]])
        rows.append(row)

    fits = [r for r in rows if r["fit"]]
    fixed = [r for r in rows if r["cushions_in_view"] >= 3]
    unfixed = [r for r in rows if r["cushions_in_view"] < 3]
    errors = np.array([np.inf if e is None else e for r in fits for e in r["errors"]])
    by_build: dict[str, list[float]] = defaultdict(list)
    for r in fits:
        by_build[r["build"]].extend(np.inf if e is None else e for e in r["errors"])
    summary = {
        "renders": len(rows),
        "fitted": len(fits),
        "with_three_cushions": len(fixed),
        "fitted_with_three_cushions": sum(r["fit"] for r in fixed),
        "fewer_cushions_refused": sum(not r["fit"] for r in unfixed),
        "with_sights": args.with_sights,
        "cloths": sorted(cloths) if cloths else "all",
        "corner_error_median": float(np.median(errors)) if len(errors) else None,
        "corner_error_p90": float(np.percentile(errors, 90)) if len(errors) else None,
        "right_2pct": sum(bool(r["errors"]) and None not in r["errors"] and max(r["errors"]) <= 0.02 for r in fits),
        "fit_seconds_median": float(np.median(seconds)) if seconds else None,
        "by_build": {b: float(np.median(v)) for b, v in sorted(by_build.items())},
    }
    print(f"{'renders':<36} {summary['renders']}")
    print(f"{'fitted':<36} {summary['fitted']} ({summary['fitted'] / max(len(rows), 1):.0%})")
    print(
        f"{'  of views with >= 3 cushions':<36} {summary['fitted_with_three_cushions']} of {len(fixed)}; "
        f"fewer cushions: {len(unfixed)}, refused {summary['fewer_cushions_refused']}"
    )
    if len(errors):
        print(f"{'corner error, median / 90th pct':<36} {summary['corner_error_median']:.2%} / "
              f"{summary['corner_error_p90']:.2%} of the table length")  # fmt: skip
        print(f"{'all corners within 2 %':<36} {summary['right_2pct']}")
    for build, median in summary["by_build"].items():
        print(f"  {build:<12} median {median:.2%}")
    if args.json:
        Path(args.json).write_text(json.dumps({**summary, "rows": rows}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

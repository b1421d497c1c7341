"""Table fit and ball location on single synthetic renders of every camera kind (exact labels).

Each render (:func:`pix2pockets.synth.renderer.render`, random camera kind, occluders, crops, overlays)
gives its labelled diamonds and visible ball boxes to :func:`fit_table` and :func:`locate_balls`.
Reported per camera kind: fits, clear failures (``TableFitError``, with reasons), mean corner error [px]
(corners up to half an image outside the frame) and mean ball error [cm] (scaled to a 9-ft table;
assumed diamond height).

Usage:
    PYTHONPATH=src python benchmarks/rendered_fit.py --n 30 --json OUT.json [--size 960x540]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections import defaultdict

import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")

from pix2pockets.geometry import TableSpec, table_preset
from pix2pockets.vision.analytic import detections_from_synth_labels
from pix2pockets.vision.ball_location import locate_balls
from pix2pockets.vision.table_fit import TableFitError, fit_table


def main(argv: list[str] | None = None) -> int:
    from pix2pockets.synth.renderer import render

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=30)
    parser.add_argument("--seed", type=int, default=1000)
    parser.add_argument("--size", default="960x540")
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    size = tuple(int(v) for v in args.size.lower().split("x"))
    stats: dict[str, dict] = defaultdict(
        lambda: {"renders": 0, "fits": 0, "failures": [], "corner_px": [], "ball_cm": []}
    )
    for k in range(args.n):
        rend = render((args.seed, k), size=size)
        lab = rend.labels
        kind = lab["camera"]["kind"]
        s = stats[kind]
        s["renders"] += 1
        spec = table_preset(lab["table"]["name"])
        det = detections_from_synth_labels(lab)
        try:
            fit = fit_table(det, tuple(lab["image_size"]), spec)
        except TableFitError as err:
            s["failures"].append(f"{(args.seed, k)}: {err} ({int(det.is_dot.sum())} dots)")
            continue
        s["fits"] += 1
        truth_c = np.array([c["px_cloth"] or [np.nan, np.nan] for c in lab["corners"]], dtype=float)
        w, h = lab["image_size"]
        near = (np.abs(truth_c[:, 0] - w / 2) < w) & (np.abs(truth_c[:, 1] - h / 2) < h)  # within 1/2 image outside
        errs = []
        for r in (0, 2):
            diff = np.abs(np.roll(fit.corners_px, r, axis=0) - truth_c)[near]
            errs.append(float(np.nanmax(diff)) if np.isfinite(diff).any() else np.inf)
        s["corner_px"].append(min(errs))
        loc = locate_balls(fit.camera, det, spec)
        truth = np.array([b["centre_table_m"][:2] for b in lab["balls"] if b["labelled"]]).reshape(-1, 2)
        if len(loc.positions) and len(truth):
            best = np.inf
            for flip in (False, True):
                p = loc.positions
                if flip:
                    p = np.column_stack([spec.length - p[:, 0], spec.width - p[:, 1]])
                d = np.linalg.norm(p[:, None] - truth[None], axis=-1).min(axis=1).mean()
                best = min(best, d)
            s["ball_cm"].append(best * 100 * TableSpec().length / spec.length)
        print(f"{k:3d} {kind:10s} ok  corner {s['corner_px'][-1]:6.1f} px", flush=True)
    out = {}
    print(f"{'camera':<10} {'renders':>7} {'fits':>5} {'corner px (median)':>19} {'ball cm (mean)':>15}")
    for kind, s in sorted(stats.items()):
        out[kind] = {
            "renders": s["renders"],
            "fits": s["fits"],
            "corner_px_median": float(np.median(s["corner_px"])) if s["corner_px"] else None,
            "ball_cm_mean": float(np.mean(s["ball_cm"])) if s["ball_cm"] else None,
            "failures": s["failures"],
        }
        o = out[kind]
        print(
            f"{kind:<10} {o['renders']:7d} {o['fits']:5d} {o['corner_px_median'] or float('nan'):19.2f} "
            f"{o['ball_cm_mean'] or float('nan'):15.3f}"
        )
        for f in s["failures"]:
            print("    fail", f)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"n": args.n, "seed": args.seed, "size": list(size), "per_camera": out}, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())

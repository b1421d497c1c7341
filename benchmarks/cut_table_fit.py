"""How far off a table fit lies where the photo does not show the table: fits by the share of the table in view.

Each render (:func:`pix2pockets.synth.renderer.render`, every camera kind, build and cloth; without sights unless
``--with-sights``) goes through the pipeline's own steps (the bundled detector, post-processing, the table model,
``estimate_table``). The fitted table's four playing-surface corners are carried through the fit's camera into the
photo and back onto the true table through the render's own camera, and compared with the true corners (the nearest
of them) [m]: a corner outside the photo is where the fit puts a pocket the player cannot see. The fits are grouped
by the share of the fitted table inside the photo (the pipeline refuses a fit below ``MIN_TABLE_IN_VIEW``).

Usage:
    PYTHONPATH=src python benchmarks/cut_table_fit.py --n 200 [--seed 5000] [--with-sights] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
from pathlib import Path

import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.pipeline.photo import MIN_TABLE_IN_VIEW, clean_detections, default_detector, read_surface
from pix2pockets.pipeline.unseen_pockets import distances_out_of_photo, table_points_in_photo
from pix2pockets.vision.table.estimate import estimate_table
from pix2pockets.vision.table.fit import TableFitError
from pix2pockets.vision.table.quad_geometry import share_in_frame

IN_VIEW_BINS = (0.0, 0.25, 0.5, 0.75, 0.95, 1.0001)
"""Edges of the groups by the share of the fitted table in the photo."""
NEAR_M = 0.1
"""A corner within this of the true one [m] counts as near (a pocket mouth is about 0.12 m wide)."""


def corner_errors_m(fit, camera: PinholeCamera, truth_m: np.ndarray) -> np.ndarray:
    """Each fitted playing-surface corner's distance from the nearest true corner ``truth_m`` (4, 2) [m], on the
    true table seen by the render's ``camera``; inf for a corner that does not map (behind a camera)."""
    px = fit.camera.project_table(fit.spec.corners, 0.0)
    h = np.column_stack([px, np.ones(len(px))]) @ np.linalg.inv(camera.table_homography(0.0)).T
    with np.errstate(divide="ignore", invalid="ignore"):
        on_table = h[:, :2] / h[:, 2:3]
    d = np.linalg.norm(on_table[:, None, :] - truth_m[None], axis=-1).min(axis=1)
    return np.where(np.isfinite(d), d, np.inf)


def main(argv: list[str] | None = None) -> int:
    from pix2pockets.synth.renderer import render

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=200, help="renders to draw (those with sights are passed over)")
    ap.add_argument("--seed", type=int, default=5000, help="first render seed")
    ap.add_argument("--with-sights", action="store_true", help="fit renders with sights too")
    ap.add_argument("--json")
    args = ap.parse_args(argv)
    size = (960, 540)
    detector = default_detector()
    rows = []
    for seed in range(args.seed, args.seed + args.n):
        out = render(seed, size)
        labels = out.labels
        if labels["style"]["sights"] != "none" and not args.with_sights:
            continue
        cam = labels["camera"]
        camera = PinholeCamera(np.array(cam["K"]), np.array(cam["R"]), np.array(cam["t"]), tuple(cam["image_size"]))
        truth_m = np.array([c["table_m"][:2] for c in labels["corners"]])
        det = clean_detections(detector.detect(out.image))
        try:
            surface = read_surface(out.image, det, True)
            fit = estimate_table(out.image, det, size, pixel_aspect=det.pixel_aspect, surface=surface)
        except TableFitError:
            continue
        errors = corner_errors_m(fit, camera, truth_m)
        in_view = share_in_frame(fit.corners_px, size)
        errors_m = [round(float(e), 4) if np.isfinite(e) else None for e in errors]  # None: behind a camera
        in_photo = table_points_in_photo(fit.camera, fit.spec.corners, size).tolist()
        out_m = distances_out_of_photo(fit.camera, fit.spec, size, fit.spec.corners)
        rows.append(
            {
                "seed": seed,
                "in_view": round(in_view, 3),
                "corner_errors_m": errors_m,
                "corner_in_photo": in_photo,
                "corner_out_m": [round(float(d), 3) for d in out_m],
            }
        )

    groups = []
    print(f"{len(rows)} fits; corner error on the true table [m], by the share of the fitted table in the photo")
    print(f"{'in view':<12} {'fits':>5} {'worst, median':>14} {'all within 0.1 m':>17} {'median corner':>14}")
    for lo, hi in itertools.pairwise(IN_VIEW_BINS):
        group = [r for r in rows if lo <= r["in_view"] < hi]
        errors = [[np.inf if e is None else e for e in r["corner_errors_m"]] for r in group]
        worst = np.array([max(e) for e in errors]) if group else np.zeros(0)
        corner = np.array([np.median(e) for e in errors]) if group else np.zeros(0)
        summary = {
            "in_view": [lo, min(hi, 1.0)],
            "fits": len(group),
            "worst_corner_median_m": float(np.median(worst)) if len(worst) else None,
            "all_near": float(np.mean(worst <= NEAR_M)) if len(worst) else None,
            "corner_median_m": float(np.median(corner)) if len(corner) else None,
        }
        groups.append(summary)
        if group:
            print(
                f"{lo:>4.0%}-{min(hi, 1.0):<6.0%} {len(group):>5} {summary['worst_corner_median_m']:>14.3f} "
                f"{summary['all_near']:>17.0%} {summary['corner_median_m']:>14.3f}"
            )
    print(f"(the pipeline refuses fits with less than {MIN_TABLE_IN_VIEW:.0%} of the table in the photo)")
    accepted = [r for r in rows if r["in_view"] >= MIN_TABLE_IN_VIEW]
    by_place = {}
    for place, seen in (("in the photo", True), ("out of the photo", False)):
        errors = np.array(
            [
                np.inf if e is None else e
                for r in accepted
                for e, s in zip(r["corner_errors_m"], r["corner_in_photo"], strict=True)
                if s is seen
            ]
        )
        finite = errors[np.isfinite(errors)]
        by_place[place] = {
            "corners": len(errors),
            "median_m": float(np.median(errors)) if len(errors) else None,
            "rms_m": float(np.sqrt(np.mean(finite**2))) if len(finite) else None,
            "p90_m": float(np.quantile(errors, 0.9)) if len(errors) else None,
        }
    print("corners of the accepted fits:")
    print(f"{'':<18} {'corners':>8} {'median':>8} {'rms':>8} {'p90':>8}")
    for place, g in by_place.items():
        if g["corners"]:
            print(f"{place:<18} {g['corners']:>8} {g['median_m']:>8.3f} {g['rms_m']:>8.3f} {g['p90_m']:>8.3f}")
    if args.json:
        report = {
            "first_seed": args.seed,
            "with_sights": args.with_sights,
            "groups": groups,
            "accepted_corners": by_place,
            "rows": rows,
        }
        Path(args.json).write_text(json.dumps(report, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

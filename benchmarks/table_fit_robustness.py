"""Table fitting under dot noise, hidden dots and false-positive dots (analytic views).

For each setting, ``--trials`` random draws per view (top, 45, front): Gaussian noise on the 18 projected
diamond centres, a random fraction of them hidden, and some false-positive dots inside the image. Reports
clear failures (``TableFitError``), wrong fits (a corner more than 10 px off) and fit time.

Usage:
    PYTHONPATH=src python benchmarks/table_fit_robustness.py --json OUT.json [--trials 20]
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np

from pix2pockets.geometry import TableSpec
from pix2pockets.vision.analytic import standard_views
from pix2pockets.vision.table_fit import TableFitError, diamond_height, fit_table


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    spec = TableSpec()
    views = standard_views(spec)
    rng = np.random.default_rng(args.seed)
    rows = []
    print(f"{'noise px':>8} {'hidden':>6} {'false +':>7} {'fail':>6} {'wrong':>6} {'median s':>9} {'max s':>6}")
    for noise in (1.0, 2.0):
        for hidden in (0.0, 0.3, 0.5):
            for fp in (0, 3):
                fails = wrong = 0
                times = []
                for _ in range(args.trials):
                    for cam in views.values():
                        d = cam.project_table(spec.diamonds, diamond_height(spec)) + rng.normal(0, noise, (18, 2))
                        keep = rng.random(18) >= hidden
                        pts = np.vstack([d[keep], rng.uniform([200, 150], [1080, 600], (fp, 2))])
                        t = time.perf_counter()
                        try:
                            fit = fit_table(pts, cam.image_size, spec)
                        except TableFitError:
                            fails += 1
                            continue
                        times.append(time.perf_counter() - t)
                        if np.abs(fit.corners_px - cam.project_table(spec.corners, 0.0)).max() > 10:
                            wrong += 1
                n = args.trials * len(views)
                row = {
                    "noise_px": noise,
                    "hidden_fraction": hidden,
                    "false_positives": fp,
                    "fits": n,
                    "failures": fails,
                    "wrong": wrong,
                    "median_s": float(np.median(times)) if times else None,
                    "max_s": float(np.max(times)) if times else None,
                }
                rows.append(row)
                print(
                    f"{noise:8.1f} {hidden:6.1f} {fp:7d} {fails:3d}/{n:<3d}{wrong:3d}/{n:<3d}"
                    f"{row['median_s'] or 0:9.3f} {row['max_s'] or 0:6.3f}"
                )
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())

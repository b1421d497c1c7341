"""Table fit and ball location on single synthetic renders of every camera kind (exact labels).

Each render (:func:`pix2pockets.synth.renderer.render`, random camera kind, occluders, crops, overlays) of a table
with sights (renders of pub and home builds without sights are passed over: the diamonds are what is fitted here;
``rendered_surface_fit.py`` fits those) gives its labelled diamonds and visible ball boxes to :func:`fit_table` and
:func:`locate_balls`.
Reported per camera kind: fits, clear failures (``TableFitError``, with reasons), mean corner error [px]
(corners up to half an image outside the frame) and mean ball error [cm] (scaled to a 9-ft table), with the
diamond height assumed and measured from the render (:mod:`pix2pockets.vision.table.rail_height`).

With ``--stretch-to WxH`` each render (and its labels) is resized to WxH before the fit, as an export that
squashes every photo to one size does (the paper's Roboflow dataset: 640x640); the pixel aspect the fit
finds is reported too.

Usage:
    PYTHONPATH=src python benchmarks/rendered_fit.py --n 30 --json OUT.json [--size 960x540] [--stretch-to 640x640]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections import defaultdict

import cv2
import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")

from pix2pockets.geometry import TableSpec, table_preset
from pix2pockets.vision.detect.analytic import detections_from_synth_labels
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.locate.balls import locate_balls
from pix2pockets.vision.table.fit import TableFitError, fit_table
from pix2pockets.vision.table.rail_height import refine_fit_height


def _scaled(det: Detections, scale: np.ndarray) -> Detections:
    """Detections of a photo resized by ``scale`` (x, y)."""
    return Detections(det.boxes * np.tile(scale, 2), det.confidence, det.class_id, det.contact * scale)


def _errors(fit, det, lab: dict, spec: TableSpec, scale: np.ndarray) -> tuple[float, float | None]:
    """Corner error [px] (corners within half an image of the frame) and mean ball error [cm, 9-ft scale];
    ``scale`` (x, y) maps the render's pixels to the fitted photo's."""
    truth_c = np.array([c["px_cloth"] or [np.nan, np.nan] for c in lab["corners"]], dtype=float) * scale
    w, h = np.array(lab["image_size"]) * scale
    near = (np.abs(truth_c[:, 0] - w / 2) < w) & (np.abs(truth_c[:, 1] - h / 2) < h)  # within 1/2 image outside
    errs = []
    for r in (0, 2):
        diff = np.abs(np.roll(fit.corners_px, r, axis=0) - truth_c)[near]
        errs.append(float(np.nanmax(diff)) if np.isfinite(diff).any() else np.inf)
    loc = locate_balls(fit.camera, det, spec, diamond_z=fit.diamond_z)
    truth = np.array([b["centre_table_m"][:2] for b in lab["balls"] if b["labelled"]]).reshape(-1, 2)
    if not (len(loc.positions) and len(truth)):
        return min(errs), None
    best = np.inf
    for flip in (False, True):
        p = loc.positions
        if flip:
            p = np.column_stack([spec.length - p[:, 0], spec.width - p[:, 1]])
        d = np.linalg.norm(p[:, None] - truth[None], axis=-1).min(axis=1).mean()
        best = min(best, d)
    return min(errs), float(best * 100 * TableSpec().length / spec.length)


def main(argv: list[str] | None = None) -> int:
    from pix2pockets.synth.renderer import render, scene_of

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=30)
    parser.add_argument("--seed", type=int, default=1000)
    parser.add_argument("--size", default="960x540")
    parser.add_argument("--stretch-to", default=None, help="resize each render to WxH before the fit")
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    size = tuple(int(v) for v in args.size.lower().split("x"))
    out_size = tuple(int(v) for v in args.stretch_to.lower().split("x")) if args.stretch_to else size
    scale = np.array(out_size, dtype=float) / np.array(size)
    stats: dict[str, dict] = defaultdict(
        lambda: {
            "renders": 0,
            "fits": 0,
            "failures": [],
            "corner_px": [],
            "ball_cm": [],
            "corner_px_image": [],
            "ball_cm_image": [],
            "measured": 0,
            "pixel_aspect": [],
        }
    )
    k, done, passed = -1, 0, 0
    while done < args.n:
        k += 1
        if not scene_of((args.seed, k)).has_sights:
            passed += 1
            continue
        done += 1
        rend = render((args.seed, k), size=size)
        lab = rend.labels
        kind = lab["camera"]["kind"]
        s = stats[kind]
        s["renders"] += 1
        spec = table_preset(lab["table"]["name"])
        det = _scaled(detections_from_synth_labels(lab), scale)
        image = rend.image if out_size == size else cv2.resize(rend.image, out_size, interpolation=cv2.INTER_AREA)
        try:
            fit = fit_table(det, out_size, spec)
        except TableFitError as err:
            s["failures"].append(f"{(args.seed, k)}: {err} ({int(det.is_diamond.sum())} diamonds)")
            continue
        s["fits"] += 1
        assumed = fit
        fit, est = refine_fit_height(image, assumed, det[det.is_ball].boxes)
        s["measured"] += est.measured
        s["pixel_aspect"].append(float(fit.camera.K[0, 0] / fit.camera.K[1, 1]))
        for suffix, f in (("", assumed), ("_image", fit)):
            corner, ball = _errors(f, det, lab, spec, scale)
            s["corner_px" + suffix].append(corner)
            if ball is not None:
                s["ball_cm" + suffix].append(ball)
        print(f"{k:3d} {kind:10s} ok  corner {s['corner_px'][-1]:6.1f} px", flush=True)
    print(f"{args.n} renders with sights; {passed} without sights passed over")
    out = {}

    def med(x: list) -> float | None:
        return float(np.median(x)) if x else None

    def mean(x: list) -> float | None:
        return float(np.mean(x)) if x else None

    print(
        f"{'camera':<10} {'renders':>7} {'fits':>5} {'measured':>8} {'corner px':>10} {'(measured)':>10} "
        f"{'ball cm':>8} {'(measured)':>10} {'aspect':>7}"
    )
    for kind, s in sorted(stats.items()):
        out[kind] = {
            "renders": s["renders"],
            "fits": s["fits"],
            "height_measured": s["measured"],
            "corner_px_median": med(s["corner_px"]),
            "corner_px_median_measured_height": med(s["corner_px_image"]),
            "ball_cm_mean": mean(s["ball_cm"]),
            "ball_cm_mean_measured_height": mean(s["ball_cm_image"]),
            "pixel_aspect_median": med(s["pixel_aspect"]),
            "failures": s["failures"],
        }
        o = out[kind]
        nan = float("nan")
        print(
            f"{kind:<10} {o['renders']:7d} {o['fits']:5d} {o['height_measured']:8d} "
            f"{o['corner_px_median'] or nan:10.2f} {o['corner_px_median_measured_height'] or nan:10.2f} "
            f"{o['ball_cm_mean'] or nan:8.3f} {o['ball_cm_mean_measured_height'] or nan:10.3f} "
            f"{o['pixel_aspect_median'] or nan:7.3f}"
        )
        for f in s["failures"]:
            print("    fail", f)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(
                {
                    "n": args.n,
                    "seed": args.seed,
                    "without_sights_passed": passed,
                    "size": list(size),
                    "fitted_size": list(out_size),
                    "per_camera": out,
                },
                fh,
                indent=2,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Ball location of partly hidden balls on renders: each ball's table centre against the truth, by how much of it is
hidden, with the hidden parts modelled (``locate_sphere(..., occlusion=True)``, the default) and without.

A ball behind another ball, or beside the cushion nearest a low camera, shows only part of its silhouette; its box
stops where the hidden part begins, and the box's centre is not the ball's. Two readings of ``--n`` renders
(``render(seed, size)``, every camera kind, players and props as in any render; seeds from ``--seed``):

- *labels*: the render's labelled boxes (the visible part of each ball) and its own camera and table, so only the
  locating is measured;
- *pipeline*: the bundled detector and ``find_table`` as ``suggest`` runs it, with the render's table size given;
  each labelled ball is matched to the kept ball that boxes it (IoU >= 0.5), and the fitted table's two readings
  (it and its half turn) are compared with the truth, the nearer kept. Only fits that put the balls seen whole
  within ``GOOD_FIT`` of the truth on median count, so that the table fit's own misses do not swamp the locating.

Reported per hidden share (``occluded_fraction`` of the labels: the share of the ball's in-frame silhouette that
something in front hides; balls cut by the image border left out): balls, median and 90th percentile error [mm].

And how honest each pipeline ball's position error is (``position_covariances``, the spread a shot's chance is
measured over), without and with the part of a box that nothing modelled explains (``unexplained_shortfall``: a
player or a cue over the ball): the share of balls whose error lies within twice their larger sigma, for the balls
so widened and the others.

Usage:
    PYTHONPATH=src python benchmarks/hidden_ball_location.py [--n 100] [--seed 5000] [--size 960x540] [--json OUT]
"""

from __future__ import annotations

import json
import os
import time

import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")

from pix2pockets.geometry import table_preset
from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.pipeline.photo import default_detector, find_table
from pix2pockets.synth.renderer import parse_size, render
from pix2pockets.vision.detect.postprocess import box_iou
from pix2pockets.vision.locate.balls import locate_sphere
from pix2pockets.vision.locate.position_error import position_covariances, position_sigmas
from pix2pockets.vision.locate.visibility import unexplained_shortfall
from pix2pockets.vision.table.fit import TableFitError
from rendered_blackball import render_options

BINS = ((0.0, 0.02), (0.02, 0.1), (0.1, 0.3), (0.3, 0.6), (0.6, 1.01))
"""Hidden-share bins of the report."""

GOOD_FIT = 0.02
"""A pipeline fit counts when its balls hidden by under 2 % lie this near the truth on median [m]."""

MODES = ("without", "with")
"""Locating with the hidden parts left out of the model, and modelled."""


def render_camera(labels: dict) -> PinholeCamera:
    """The camera a render was made with."""
    c = labels["camera"]
    return PinholeCamera(np.array(c["K"]), np.array(c["R"]), np.array(c["t"]), tuple(c["image_size"]))


def errors_of(
    camera: PinholeCamera, boxes: np.ndarray, truth: np.ndarray, spec, flips: bool
) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """Each ball's location error [m] for both modes, and the centres located with the hidden parts modelled (n, 2)
    [m]; with ``flips`` the half-turned table's reading too, the nearer on median kept."""
    out = {}
    located = np.zeros((len(boxes), 2))
    for mode in MODES:
        xy = locate_sphere(camera, boxes, spec.ball_radius, spec=spec, occlusion=mode == "with")
        err = np.linalg.norm(xy - truth, axis=1)
        if flips:
            turned = np.column_stack([spec.length - xy[:, 0], spec.width - xy[:, 1]])
            err_turned = np.linalg.norm(turned - truth, axis=1)
            err = err_turned if np.median(err_turned) < np.median(err) else err
        out[mode] = err
        located = xy
    return out, located


def honesty(rows: list[tuple[float, float, float, bool]]) -> dict:
    """Balls' errors against their position sigmas: per group (widened by a shortfall or not), the ball count, the
    median error and sigmas [mm] and the share within twice the sigma, without / with the shortfall."""
    r = np.array(rows, dtype=float).reshape(-1, 4)
    out = {}
    for name, m in (("widened", r[:, 3] > 0), ("others", r[:, 3] == 0)):
        e, before, after = r[m, 0], r[m, 1], r[m, 2]
        out[name] = {
            "balls": int(m.sum()),
            "error_median_mm": float(np.median(e) * 1000) if m.any() else None,
            "sigma_median_mm": [float(np.median(v) * 1000) if m.any() else None for v in (before, after)],
            "within_2_sigma": [float(np.mean(e < 2 * v)) if m.any() else None for v in (before, after)],
        }
    return out


def summary(shares: np.ndarray, errors: dict[str, np.ndarray]) -> list[dict]:
    """Rows of the report: per hidden-share bin, the ball count and each mode's median and 90th percentile [mm]."""
    rows = []
    for lo, hi in BINS:
        m = (shares >= lo) & (shares < hi)
        row: dict = {"hidden_from": lo, "hidden_to": min(hi, 1.0), "balls": int(m.sum())}
        for mode in MODES:
            e = errors[mode][m] * 1000
            row[f"{mode}_median_mm"] = float(np.median(e)) if len(e) else None
            row[f"{mode}_p90_mm"] = float(np.percentile(e, 90)) if len(e) else None
        rows.append(row)
    return rows


def print_rows(title: str, rows: list[dict]) -> None:
    print(f"{title}: error [mm], median / 90th percentile")
    print(f"{'hidden':>10} {'balls':>6} {'without model':>16} {'with model':>16}")
    for r in rows:
        cells = [f"{r[m + '_median_mm']:6.1f} / {r[m + '_p90_mm']:6.1f}" if r["balls"] else f"{'-':>15}" for m in MODES]
        print(f"{r['hidden_from']:4.2f}-{r['hidden_to']:4.2f} {r['balls']:6d} {cells[0]:>16} {cells[1]:>16}")


def main() -> None:
    args = render_options(__doc__, 100, seed=5000)
    size = parse_size(args.size)
    detector = default_detector()
    found: dict[str, list] = {"labels": [], "pipeline": []}
    errs: dict[str, dict[str, list]] = {k: {m: [] for m in MODES} for k in found}
    fitted = good = 0
    sigmas: list[tuple[float, float, float, bool]] = []
    start = time.perf_counter()
    for k in range(args.n):
        out = render((args.seed, k), size)
        lab = out.labels
        spec = table_preset(lab["table"]["name"])
        balls = [b for b in lab["balls"] if b["labelled"] and b["in_frame_fraction"] > 0.99]
        if not balls:
            continue
        boxes = np.array([b["box_px"] for b in balls], dtype=float)
        truth = np.array([b["centre_table_m"][:2] for b in balls])
        shares = np.array([b["occluded_fraction"] for b in balls])
        by_labels, _ = errors_of(render_camera(lab), boxes, truth, spec, flips=False)
        found["labels"].extend(shares)
        for m in MODES:
            errs["labels"][m].extend(by_labels[m])
        raw = detector.detect(out.image)
        try:
            det, _, _, fit = find_table(out.image, raw, spec=spec)
        except TableFitError:
            continue
        fitted += 1
        det = det[det.is_ball]
        if len(det) == 0:
            continue
        iou = box_iou(boxes, det.boxes)
        best = iou.argmax(axis=1)
        matched = iou[np.arange(len(boxes)), best] >= 0.5
        if not matched.any():
            continue
        kept = det.boxes[best[matched]]
        by_pipeline, xy = errors_of(fit.camera, kept, truth[matched], fit.spec, flips=True)
        whole = shares[matched] < BINS[0][1]
        if not whole.any() or np.median(by_pipeline["without"][whole]) > GOOD_FIT:
            continue
        good += 1
        found["pipeline"].extend(shares[matched])
        for m in MODES:
            errs["pipeline"][m].extend(by_pipeline[m])
        r = fit.spec.ball_radius
        short = unexplained_shortfall(fit.camera, kept, xy, r, fit.spec)
        before = position_sigmas(position_covariances(fit.camera, xy, r, fit.rms_px))
        after = position_sigmas(position_covariances(fit.camera, xy, r, fit.rms_px, short))
        sigmas.extend(zip(by_pipeline["with"], before, after, short.max(axis=1) > 0, strict=True))
    report: dict = {
        "n_renders": args.n,
        "first_seed": args.seed,
        "size": list(size),
        "pipeline_fits": fitted,
        "pipeline_fits_counted": good,
    }
    for reading in found:
        rows = summary(np.array(found[reading]), {m: np.array(errs[reading][m]) for m in MODES})
        report[reading] = rows
        print_rows(f"{reading} ({len(found[reading])} balls)", rows)
    report["position_error"] = honesty(sigmas)
    print("pipeline balls within twice their position sigma, without / with the unexplained shortfall:")
    for name, h in report["position_error"].items():
        if h["balls"]:
            b, a = h["sigma_median_mm"]
            w0, w1 = h["within_2_sigma"]
            print(
                f"  {name:8s} {h['balls']:4d} balls, error {h['error_median_mm']:5.1f} mm, "
                f"sigma {b:5.1f} / {a:5.1f} mm, within 2 sigma {w0:.2f} / {w1:.2f}"
            )
    took = time.perf_counter() - start
    print(f"{fitted} of {args.n} renders fitted, {good} within {GOOD_FIT * 100:.0f} cm; {took:.0f} s")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(report, f, indent=1)


if __name__ == "__main__":
    main()

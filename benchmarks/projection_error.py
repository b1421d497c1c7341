"""The paper's projection-error experiment: one layout seen from 3 views (top, 45 degrees, front).

For each of ``--sets`` random layouts (16 balls) the three views' detections are made analytically
(exact projected sphere boxes and diamond centres from :class:`PinholeCamera`, plus Gaussian pixel noise),
the table is fitted from the diamonds alone and each ball is located. Reported: mean ball error against the
ground truth per view and method [cm, 9-ft table], and view to view (45 and front against top, as in the
paper, which found 0.4 cm).

With ``--rendered N`` the views are instead N multi-view sets from the synthetic renderer
(:func:`pix2pockets.synth.renderer.render_views`: top, high ~45 degrees, front; random table size, scene and
camera per set), and the detections are the renders' exact labels (visible ball boxes, diamond boxes;
with ``--onnx`` the bundled detector's instead). The rail-cap height of the renders varies (3-12 mm
above the cushion nose); ``--height`` says where the fit takes it from: ``assumed``
(:func:`~pix2pockets.vision.table.fit.diamond_height`), ``image`` (measured from the cushion noses in
the render, :mod:`pix2pockets.vision.table.rail_height`, as the pipeline does) or ``known`` (the render's true
height).

Usage:
    PYTHONPATH=src python benchmarks/projection_error.py --json OUT.json [--sets 25] [--noise 0.5]
    PYTHONPATH=src python benchmarks/projection_error.py --rendered 8 --json OUT.json [--height image] \
        [--onnx [--model M]]
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np
from scipy.optimize import linear_sum_assignment

from pix2pockets.geometry import TableSpec, table_preset
from pix2pockets.state import random_layout
from pix2pockets.vision.detect.analytic import analytic_detections, detections_from_synth_labels, standard_views
from pix2pockets.vision.locate.balls import LocateMethod, locate_balls
from pix2pockets.vision.stages.ball_classifier import BallClassifier
from pix2pockets.vision.stages.ball_refiner import BallRefiner
from pix2pockets.vision.stages.diamond_refiner import DiamondRefiner
from pix2pockets.vision.table.fit import TableFitError, fit_table

METHODS = (LocateMethod.SPHERE, LocateMethod.CONTACT, LocateMethod.LINEAR)


def matched_errors(est: np.ndarray, truth: np.ndarray, spec: TableSpec) -> np.ndarray:
    """Per-ball distances [m] after matching balls one-to-one (min(len(est), len(truth)) pairs); the
    180-degree turn of the table frame (the inherent ambiguity) is undone when it matches better."""
    best = None
    for flip in (False, True):
        e = np.column_stack([spec.length - est[:, 0], spec.width - est[:, 1]]) if flip else est
        d = np.linalg.norm(e[:, None] - truth[None], axis=-1)
        r, c = linear_sum_assignment(d)
        errs = d[r, c]
        if best is None or errs.mean() < best.mean():
            best = errs
    return best


def run(sets: int, noise: float, seed: int) -> dict:
    spec = TableSpec()
    views = standard_views(spec)
    rng = np.random.default_rng(seed)
    truth_err: dict[str, dict[str, list[float]]] = {m.value: {v: [] for v in views} for m in METHODS}
    v2v: dict[str, dict[str, list[float]]] = {m.value: {v: [] for v in views if v != "top"} for m in METHODS}
    failures = 0
    for _ in range(sets):
        layout = random_layout(rng, list(range(16)), spec)
        per_view: dict[str, dict[str, np.ndarray]] = {}
        for name, cam in views.items():
            det = analytic_detections(cam, layout, rng, box_noise_px=noise, diamond_noise_px=noise)
            try:
                fit = fit_table(det, cam.image_size, spec)
            except TableFitError:
                failures += 1
                continue
            per_view[name] = {}
            for m in METHODS:
                loc = locate_balls(fit.camera, det, spec, m, diamond_z=fit.diamond_z)
                per_view[name][m.value] = loc.positions
                truth_err[m.value][name].extend(matched_errors(loc.positions, layout.positions, spec))
        for m in METHODS:
            if "top" not in per_view:
                continue
            for name in per_view:
                if name != "top":
                    v2v[m.value][name].extend(matched_errors(per_view[name][m.value], per_view["top"][m.value], spec))
    return summarise(truth_err, v2v, {"sets": sets, "noise_px": noise, "seed": seed, "fit_failures": failures})


def run_rendered(
    sets: int,
    seed: int,
    height: str,
    size: tuple[int, int],
    onnx: bool = False,
    model: str | None = None,
    diamond_refiner: str | None = None,
    ball_refiner: str | None = None,
) -> dict:
    from pix2pockets.synth.renderer import render_views
    from pix2pockets.vision.table.rail_height import refine_fit_height

    detector = None
    if onnx:
        from pix2pockets.pipeline.photo import clean_detections, default_detector
        from pix2pockets.vision.detect.onnx_detector import (
            OnnxDetector,
            default_model_path,
        )

        if model is None and diamond_refiner is None and ball_refiner is None:
            detector = default_detector()
        else:
            detector = OnnxDetector(
                model or default_model_path(),
                classifier=BallClassifier.from_option(None),
                diamond_refiner=DiamondRefiner.from_option(diamond_refiner),
                ball_refiner=BallRefiner.from_option(ball_refiner),
            )

    views = ("top", "high", "front")
    truth_err: dict[str, dict[str, list[float]]] = {m.value: {v: [] for v in views} for m in METHODS}
    v2v: dict[str, dict[str, list[float]]] = {m.value: {v: [] for v in views[1:]} for m in METHODS}
    failures: list[str] = []
    rise_err: dict[str, list[float]] = {v: [] for v in views}
    counts = {"truth": 0, "located": 0, "found": 0}  # sphere method: a truth ball is found within a diameter
    measured = 0
    view_means: list[dict] = []  # mean sphere error of each view that fitted, to find the outliers
    for k in range(sets):
        renders = render_views((seed, k), size=size, views=views)
        per_view: dict[str, dict[str, np.ndarray]] = {}
        for rend in renders:
            lab = rend.labels
            spec = table_preset(lab["table"]["name"])
            scale = TableSpec().length / spec.length  # errors scaled to a 9-ft table, as in the paper
            if detector is None:
                det = detections_from_synth_labels(lab)
            else:
                det = clean_detections(detector.detect(rend.image))
            truth = np.array([b["centre_table_m"][:2] for b in lab["balls"] if b["labelled"]])
            z_true = lab["heights_m"]["diamonds"]
            try:
                fit = fit_table(det, tuple(lab["image_size"]), spec, diamond_z=z_true if height == "known" else None)
            except TableFitError as err:
                failures.append(f"set {k} {lab['view']}: {err}")
                continue
            if height == "image":
                fit, est = refine_fit_height(rend.image, fit, det[det.is_ball].boxes)
                measured += est.measured
            rise_err[lab["view"]].append(abs(fit.diamond_z - z_true) * scale)
            per_view[lab["view"]] = {}
            for m in METHODS:
                loc = locate_balls(fit.camera, det, spec, m, diamond_z=fit.diamond_z)
                per_view[lab["view"]][m.value] = loc.positions * scale
                errs = matched_errors(loc.positions, truth, spec) if len(loc.positions) and len(truth) else []
                truth_err[m.value][lab["view"]].extend(np.asarray(errs) * scale)
                if m is LocateMethod.SPHERE:
                    if len(errs):
                        view_means.append({"set": k, "view": lab["view"], "cm": float(np.mean(errs) * scale * 100)})
                    counts["truth"] += len(truth)
                    counts["located"] += len(loc.positions)
                    counts["found"] += int(np.sum(np.asarray(errs) < 2 * spec.ball_radius))
        for m in METHODS:
            if "top" not in per_view:
                continue
            for name in per_view:
                if name != "top" and len(per_view[name][m.value]) and len(per_view["top"][m.value]):
                    v2v[m.value][name].extend(
                        matched_errors(per_view[name][m.value], per_view["top"][m.value], TableSpec())
                    )
    return summarise(
        truth_err,
        v2v,
        {
            "sets": sets,
            "seed": seed,
            "rendered": True,
            "height": height,
            "detections": "onnx" if onnx else "labels",
            "height_measured": measured,
            "height_error_mm": {v: float(np.mean(e) * 1000) if e else None for v, e in rise_err.items()},
            "size": list(size),
            "fit_failures": len(failures),
            "failures": failures,
            "worst_views_sphere_cm": sorted(view_means, key=lambda w: -w["cm"])[:5],
            "balls": {
                **counts,
                "missed": counts["truth"] - counts["found"],
                "extra": counts["located"] - counts["found"],
            },
        },
    )


def summarise(truth_err: dict, v2v: dict, meta: dict) -> dict:
    cm = 100.0

    def mean(values) -> float | None:
        values = list(values)
        return float(np.mean(values) * cm) if values else None

    def median(values) -> float | None:
        values = list(values)
        return float(np.median(values) * cm) if values else None

    return {
        **meta,
        "vs_truth_cm": {m: {v: mean(e) for v, e in d.items()} for m, d in truth_err.items()},
        "vs_truth_median_cm": {m: {v: median(e) for v, e in d.items()} for m, d in truth_err.items()},
        "vs_truth_all_views_cm": {m: mean(x for e in d.values() for x in e) for m, d in truth_err.items()},
        "view_to_view_cm": {m: {v: mean(e) for v, e in d.items()} for m, d in v2v.items()},
        "view_to_view_all_cm": {m: mean(x for e in d.values() for x in e) for m, d in v2v.items()},
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sets", type=int, default=25, help="number of layouts (3 views each)")
    parser.add_argument("--noise", type=float, default=0.5, help="pixel noise (std) on box edges and diamonds")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--rendered", type=int, default=0, help="use N rendered multi-view sets instead")
    parser.add_argument(
        "--height",
        choices=("assumed", "image", "known"),
        default="assumed",
        help="rendered: diamond-plane height assumed, measured from the image, or the render's true one",
    )
    parser.add_argument("--known-height", action="store_true", help="rendered: same as --height known")
    parser.add_argument(
        "--onnx", action="store_true", help="rendered: detections from the bundled ONNX detector, not the labels"
    )
    parser.add_argument("--model", default=None, help="rendered, --onnx: this detector ONNX instead of the bundled one")
    parser.add_argument(
        "--diamond-refiner", default=None, help="rendered, --onnx: this diamond refiner ONNX ('none': without one)"
    )
    parser.add_argument(
        "--ball-refiner", default=None, help="rendered, --onnx: this ball refiner ONNX ('none': without one)"
    )
    parser.add_argument("--size", default="1280x720", help="rendered: image size WxH")
    parser.add_argument("--json", help="write results to this JSON file")
    args = parser.parse_args(argv)
    if args.rendered:
        size = tuple(int(v) for v in args.size.lower().split("x"))
        height = "known" if args.known_height else args.height
        stages = args.model, args.diamond_refiner, args.ball_refiner
        res = run_rendered(args.rendered, args.seed, height, size, args.onnx, *stages)
        print(
            f"projection error, {res['sets']} rendered sets x 3 views ({res['detections']}, "
            f"{height} diamond height), scaled to a 9-ft table [cm]"
        )
        print(
            f"diamond height error [mm, 9-ft scale]: {res['height_error_mm']}; "
            f"measured from the image in {res['height_measured']} views"
        )
        b = res["balls"]
        print(
            f"balls (sphere): {b['truth']} labelled, {b['located']} located, {b['missed']} missed, "
            f"{b['extra']} extra (none within a ball diameter)"
        )
    else:
        res = run(args.sets, args.noise, args.seed)
        print(f"projection error, {res['sets']} layouts x 3 views, noise {res['noise_px']} px, 9-ft table [cm]")
    views = list(next(iter(res["vs_truth_cm"].values())))

    def f(x: float | None) -> str:
        return "   n/a" if x is None else f"{x:6.3f}"

    print(
        f"{'method':<8} "
        + " ".join(f"{v:>6}" for v in views)
        + f" {'all':>6} | "
        + " ".join(f"{'v2v ' + v:>9}" for v in views[1:])
        + f" {'v2v':>6}"
    )
    for m in res["vs_truth_cm"]:
        t = res["vs_truth_cm"][m]
        v = res["view_to_view_cm"][m]
        print(
            f"{m:<8} "
            + " ".join(f(t[x]) for x in views)
            + f" {f(res['vs_truth_all_views_cm'][m])} | "
            + " ".join(f"   {f(v[x])}" for x in views[1:])
            + f" {f(res['view_to_view_all_cm'][m])}"
        )
    medians = res.get("vs_truth_median_cm", {})
    if medians:
        print("medians")
    for m, t in medians.items():
        print(f"{m:<8} " + " ".join(f(t[x]) for x in views))
    worst = res.get("worst_views_sphere_cm", [])
    if worst:
        print(
            "worst views (sphere, mean error per view [cm]): "
            + ", ".join(f"{w['set']} {w['view']} {w['cm']:.1f}" for w in worst)
        )
    print(f"table fit failures: {res['fit_failures']}")
    for line in res.get("failures", []):
        print("  ", line)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(res, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())

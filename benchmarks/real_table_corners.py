"""Table fits on real photos against corners labelled by eye.

``benchmarks/data/real_table_corners.json`` holds, for one copy of every source photo of
``../shared/data/real-snooker-vision`` (train and valid), whether the whole table is in view and, where it is, the
four lines of the cloth's outer edge (where the cushion cloth meets the rails), read by eye with
``scripts/table_corner_labels.py`` (its docstring says how; ``draw`` puts the labels back on the photos). Their
crossings are the labelled corners.

For every whole-table photo the pipeline's own steps fit the table (bundled detector, then ``find_table`` as
``suggest`` runs it: post-processing for the ball set read from the photo, table model, ``estimate_table`` with
``--table``, a blackball set's table sized among the UK ones); the fitted cloth outline (the playing surface grown by
the cushion width, at cushion height) is projected into the photo and its corners matched to the labelled ones. A
corner's error is its distance in the photo divided by the table's length in the photo (the labelled outline's longer
pair of opposite sides); a photo is *right* when all four corners are within ``--tolerance`` (2 %) of it. The median
distance on the table itself (through the homography of the labelled corners) is reported too: there a pixel of
reading error at the far end of an oblique view is several centimetres. ``suggest`` then runs on the same
detections and a photo *has a shot* when it returns one. ``--scale`` enlarges (or shrinks) each photo and its labels
first, to see the fit at other resolutions (a 640 px photo at 3 is a 1920 px one, the largest fitted as it is), and
``--blur`` blurs it (a Gaussian of that many pixels).

Usage:
    PYTHONPATH=src python benchmarks/real_table_corners.py [--data DIR] [--labels FILE] [--table auto|9ft|...]
        [--tolerance 0.02] [--table-model ONNX] [--scale 1] [--blur 0] [--draw DIR] [--sheet PNG] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import itertools
import json
import time
from pathlib import Path

import cv2
import numpy as np

from pix2pockets.geometry import table_preset
from pix2pockets.pipeline.photo import default_detector, find_table, suggest
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.image_io import image_grid, read_image_rgb
from pix2pockets.vision.table.fit import TableFit, TableFitError
from pix2pockets.vision.table.keypoints import TableModel
from pix2pockets.vision.table.outline_camera import CUSHION_WIDTH, outline_rectangle
from pix2pockets.vision.table.quad_geometry import quad_length, quad_of_point_sets

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "real-snooker-vision"
DEFAULT_LABELS = HERE / "data" / "real_table_corners.json"
SHEET_COLUMNS, SHEET_TILE = 8, 200  # contact sheet: photos per row, tile size [px]


def fitted_outline(fit: TableFit) -> tuple[np.ndarray, np.ndarray]:
    """The fitted cloth outline: its corners in the photo (4, 2) [px] and on the table (4, 2) [m]."""
    table_xy = outline_rectangle(fit.spec, CUSHION_WIDTH)
    return fit.camera.project_table(table_xy, fit.spec.cushion_height), table_xy


def match_corners(labels_px: np.ndarray, fitted_px: np.ndarray) -> np.ndarray:
    """The order of the fitted corners (cyclic, either direction) closest to the labelled ones."""
    orders = [np.roll(np.arange(4), s) for s in range(4)] + [np.roll(np.arange(4)[::-1], s) for s in range(4)]
    return min(orders, key=lambda o: float(np.linalg.norm(fitted_px[o] - labels_px, axis=1).sum()))


def corner_errors(labels_px: np.ndarray, fitted_px: np.ndarray) -> np.ndarray:
    """Each fitted corner's distance from its labelled corner in the photo, as a fraction of the table's length
    there (:func:`table_length_px` of the labels)."""
    if not np.all(np.isfinite(fitted_px)):
        return np.full(4, np.inf)
    order = match_corners(labels_px, fitted_px)
    return np.linalg.norm(fitted_px[order] - labels_px, axis=1) / quad_length(labels_px)


def table_errors(labels_px: np.ndarray, fitted_px: np.ndarray, table_xy: np.ndarray) -> np.ndarray:
    """Each fitted corner's distance from its labelled corner on the table [m]: the homography from the labelled
    corners to the fitted outline's table coordinates maps the fitted corner onto the table. Far corners of an
    oblique view weigh a pixel of reading error as many centimetres."""
    if not np.all(np.isfinite(fitted_px)):
        return np.full(4, np.inf)
    order = match_corners(labels_px, fitted_px)
    H, _ = cv2.findHomography(labels_px.astype(np.float64), table_xy[order].astype(np.float64))
    if H is None:
        return np.full(4, np.inf)
    on_table = cv2.perspectiveTransform(fitted_px[order].reshape(-1, 1, 2).astype(np.float64), H).reshape(-1, 2)
    return np.linalg.norm(on_table - table_xy[order], axis=1)


def is_phone_photo(image: str) -> bool:
    """Whether a photo is one of the dataset's phone photos of varied tables (the rest are frames of one video of
    one pub table, named ``yt-...``)."""
    return not Path(image).name.startswith("yt-")


class CachedDetector:
    """A detector that returns detections found before (so ``suggest`` does not detect twice)."""

    def __init__(self, detections: Detections) -> None:
        self.detections = detections

    def detect(self, rgb: np.ndarray) -> Detections:
        return self.detections


def draw_fit(image_rgb: np.ndarray, labels_px: np.ndarray, fitted_px: np.ndarray | None, right: bool) -> np.ndarray:
    """The photo with the labelled outline (green) and the fitted one (magenta if right, red if not)."""
    out = cv2.cvtColor(image_rgb, cv2.COLOR_RGB2BGR)
    cv2.polylines(out, [np.round(labels_px).astype(np.int32)], True, (0, 255, 0), 1, cv2.LINE_AA)
    if fitted_px is not None and np.all(np.isfinite(fitted_px)) and np.abs(fitted_px).max() < 1e5:
        colour = (255, 0, 255) if right else (0, 0, 255)
        cv2.polylines(out, [np.round(fitted_px).astype(np.int32)], True, colour, 2, cv2.LINE_AA)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the real-snooker-vision folder")
    ap.add_argument("--labels", type=Path, default=DEFAULT_LABELS, help="labelled corners JSON")
    ap.add_argument("--table", default="auto", choices=["auto", "9ft", "8ft", "7ft", "6ft"])
    ap.add_argument("--tolerance", type=float, default=0.02, help="corner error that counts as right [table length]")
    ap.add_argument("--no-shots", action="store_true", help="fit only; do not run the planner")
    ap.add_argument("--draw", type=Path, default=None, help="folder for each photo with its labelled and fitted table")
    ap.add_argument(
        "--sheet", type=Path, default=None, help="contact sheet of the phone photos and every tenth video frame"
    )
    ap.add_argument(
        "--table-model", default=None, help="table model ONNX to fit with (default: the bundled one; 'none': without)"
    )
    ap.add_argument(
        "--scale", type=float, default=1.0, help="resize each photo (and its labels) by this factor first (e.g. 2, 3)"
    )
    ap.add_argument("--blur", type=float, default=0.0, help="Gaussian blur [px] on each photo (after --scale)")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    if not 0.25 <= args.scale <= 8:
        raise SystemExit(f"--scale must be within 0.25-8, got {args.scale}")

    spec = None if args.table == "auto" else table_preset(args.table)
    entries = [e for e in json.loads(args.labels.read_text())["photos"] if e["whole_table"]]
    detector = default_detector()
    table_model = TableModel.from_option(args.table_model) if args.table_model else True
    rows, drawn, seconds = [], [], []
    for entry in entries:
        path = args.data / entry["image"]
        if not path.is_file():
            raise SystemExit(f"{path} not found: pass --data, the real-snooker-vision folder")
        image = read_image_rgb(path)
        labels_px = quad_of_point_sets(entry["lines"])
        if args.scale != 1.0:  # pixel corners at the origin: a point scales with the photo
            h0, w0 = image.shape[:2]
            image = cv2.resize(image, None, fx=args.scale, fy=args.scale, interpolation=cv2.INTER_CUBIC)
            labels_px = labels_px * np.array([image.shape[1] / w0, image.shape[0] / h0])
        if args.blur > 0:
            image = cv2.GaussianBlur(image, (0, 0), args.blur)
        t = time.perf_counter()
        raw = detector.detect(image)
        row: dict = {"image": entry["image"]}
        fitted_px = None
        try:
            _, ball_set, _, fit = find_table(image, raw, spec, table_model)
        except TableFitError as err:
            row.update(fit=False, error=str(err).split(":")[0], right=False, shot=False)
        else:
            seconds.append(time.perf_counter() - t)
            fitted_px, table_xy = fitted_outline(fit)
            errors = corner_errors(labels_px, fitted_px)
            row.update(
                fit=True,
                source=fit.source,
                table=fit.spec.name,
                ball_set=ball_set.value,
                corner_errors=[round(float(e), 4) for e in errors],
                table_errors_m=[round(float(e), 3) for e in table_errors(labels_px, fitted_px, table_xy)],
                right=bool(np.all(errors <= args.tolerance)),
            )
            if not args.no_shots:
                try:
                    suggest(
                        image,
                        detector=CachedDetector(raw),
                        spec=spec,
                        rng=np.random.default_rng(0),
                        table_model=table_model,
                    )
                    row["shot"] = True
                except ValueError as err:
                    row.update(shot=False, shot_error=str(err).split(":")[0])
        rows.append(row)
        if args.draw or args.sheet:
            drawn.append(draw_fit(image, labels_px, fitted_px, row["right"]))
            if args.draw:
                args.draw.mkdir(parents=True, exist_ok=True)
                cv2.imwrite(str(args.draw / (Path(entry["image"]).name.split(".rf.")[0] + ".png")), drawn[-1])

    fits = [r for r in rows if r["fit"]]
    errors = np.array(list(itertools.chain.from_iterable(r["corner_errors"] for r in fits)) or [np.nan])
    on_table = np.array(list(itertools.chain.from_iterable(r["table_errors_m"] for r in fits)) or [np.nan])
    errors, on_table = errors[np.isfinite(errors)], on_table[np.isfinite(on_table)]
    summary = {
        "photos": len(rows),
        "fitted": len(fits),
        "right": sum(r["right"] for r in rows),
        "with_shot": None if args.no_shots else sum(r.get("shot", False) for r in rows),
        "tolerance": args.tolerance,
        "corner_error_median": float(np.median(errors[np.isfinite(errors)])) if np.isfinite(errors).any() else None,
        "table_error_median_m": float(np.median(on_table[np.isfinite(on_table)]))
        if np.isfinite(on_table).any()
        else None,
        "fit_seconds_median": float(np.median(seconds)) if seconds else None,
        "fit_seconds_mean": float(np.mean(seconds)) if seconds else None,
        "fit_seconds_max": float(np.max(seconds)) if seconds else None,
    }
    groups = {"all": rows}
    for name, test in (("phone photos", is_phone_photo), ("video frames", lambda image: not is_phone_photo(image))):
        groups[name] = [r for r in rows if test(r["image"])]
    summary["groups"] = {
        name: {
            "photos": len(group),
            "fitted": sum(r["fit"] for r in group),
            "right": sum(r["right"] for r in group),
            "with_shot": None if args.no_shots else sum(r.get("shot", False) for r in group),
        }
        for name, group in groups.items()
    }
    print(f"{'':<30} {'photos':>7} {'fitted':>7} {'right':>7} {'shot':>7}")
    for name, g in summary["groups"].items():
        shot = "-" if g["with_shot"] is None else g["with_shot"]
        print(f"{name:<30} {g['photos']:>7} {g['fitted']:>7} {g['right']:>7} {shot:>7}")
    print(f"right: all four corners within {args.tolerance:.0%} of the table's length in the photo")
    if summary["corner_error_median"] is not None:
        print(f"{'corner error, median':<34} {summary['corner_error_median']:.2%} of the table length in the photo")
        print(f"{'corner error on the table, median':<34} {summary['table_error_median_m'] * 100:.1f} cm")
    if seconds:
        print(
            f"{'detect + fit a photo, one process':<34} median {summary['fit_seconds_median']:.3f} s, "
            f"mean {summary['fit_seconds_mean']:.3f} s, slowest {summary['fit_seconds_max']:.2f} s"
        )
    wrong = [r for r in rows if not r["right"]]
    for r in wrong:
        why = r.get("error") or f"worst corner {max(r['corner_errors']):.1%}"
        print(f"  not right: {Path(r['image']).name[:24]:<24} {why}")
    if args.sheet:
        video = itertools.count()
        shown = [d for d, r in zip(drawn, rows, strict=True) if is_phone_photo(r["image"]) or next(video) % 10 == 0]
        cv2.imwrite(str(args.sheet), image_grid(shown, SHEET_COLUMNS, (SHEET_TILE, SHEET_TILE)))
    if args.json:
        Path(args.json).write_text(json.dumps({**summary, "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()

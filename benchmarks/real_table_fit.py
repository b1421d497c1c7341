"""Table fits on real phone photos, checked against the dataset's whole-table boxes.

The snooker-vision photos carry no diamonds, but each has a box around the whole table (class 1). A fitted table
(the bundled detector's diamonds and balls; with ``--cues all``, the default, ``find_table`` as ``suggest`` runs it;
else the pipeline's post-processing and ``estimate_table`` over the diamonds alone, the cloth outline alone or the
table model's surface alone, on the photo as it is) is drawn into
the photo as the outer edge of
its rails (yellow; the playing surface magenta, the head rail red); the bounding box of that outline's part in
front of the camera, cut to the photo, should cover the labelled box. A fit *agrees* when their IoU is at least
``--min-iou``. A labelled box may be cut by the frame or, in a mosaic, drawn round pasted content,
so a low IoU is a flag to look at (``--draw DIR``), not proof of a wrong fit.

Photos: ``benchmarks/data/real_phone_photos.json`` (one copy of each of the 80 phone photos).

Usage:
    PYTHONPATH=src python benchmarks/real_table_fit.py [--data DIR] [--photos FILE] [--min-iou 0.6] [--draw DIR]
        [--json OUT.json] [--cues diamonds|cloth|surface|all]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from pix2pockets.pipeline.photo import clean_detections, find_table, read_surface
from pix2pockets.vision.detect.onnx_detector import OnnxDetector
from pix2pockets.vision.detect.postprocess import box_iou
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.metrics.yolo_data import read_yolo_labels
from pix2pockets.vision.table.estimate import CUES, estimate_table
from pix2pockets.vision.table.fit import TableFit, TableFitError

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parent.parent / "shared" / "data" / "real-snooker-vision"
DEFAULT_PHOTOS = HERE / "data" / "real_phone_photos.json"
TABLE_CLASS = 1  # the dataset's "Billiard table" box


def rail_outline_px(fit: TableFit) -> np.ndarray:
    """The outer edge of the fitted table's rails in the photo (4, 2) [px], at cushion height."""
    spec = fit.spec
    corners = np.asarray(spec.corners, dtype=float)
    outward = np.sign(corners - corners.mean(axis=0)) * spec.rail_width
    return fit.camera.project_table(corners + outward, spec.cushion_height)


def table_box_iou(fit: TableFit, table_boxes: np.ndarray) -> float:
    """Best IoU of the bounding box of the fitted rails' outer edge (the part in front of the camera), cut to the photo
    as the labels are, with the labelled table boxes (NaN without any)."""
    if not len(table_boxes):
        return float("nan")
    # points along the rails' outer edge, those in front of the camera (a close table's near corners may not be)
    spec = fit.spec
    corners = np.asarray(spec.corners, dtype=float)
    corners = corners + np.sign(corners - corners.mean(axis=0)) * spec.rail_width
    t = np.linspace(0.0, 1.0, 41)[:, None, None]
    edges = (corners[None] + t * (np.roll(corners, -1, axis=0) - corners)[None]).reshape(-1, 2)
    outline = fit.camera.project_table(edges, spec.cushion_height)
    outline = outline[np.all(np.isfinite(outline), axis=1)]
    if not len(outline):
        return 0.0
    w, h = fit.camera.image_size
    box = np.clip(np.concatenate([outline.min(axis=0), outline.max(axis=0)]), 0, [w, h, w, h])
    return float(box_iou(box[None], table_boxes).max())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the real-snooker-vision folder")
    ap.add_argument("--photos", type=Path, default=DEFAULT_PHOTOS, help="photo list JSON")
    ap.add_argument("--min-iou", type=float, default=0.6, help="IoU at which a fit agrees with the table box")
    ap.add_argument("--draw", type=Path, default=None, help="folder for the photos with their fitted outline")
    ap.add_argument("--json", default=None)
    ap.add_argument(
        "--cues", choices=CUES, default="all", help="fit the diamonds, the cloth, the table model's surface or all"
    )
    args = ap.parse_args()

    detector = OnnxDetector.from_default()
    rows = []
    for name in json.loads(args.photos.read_text())["images"]:
        path = args.data / name
        if not path.is_file():
            raise SystemExit(f"{path} not found: pass --data, the real-snooker-vision folder")
        image = read_image_rgb(path)
        size = (image.shape[1], image.shape[0])
        boxes, classes = read_yolo_labels(path.parent.parent / "labels" / (path.stem + ".txt"), size)
        try:
            if args.cues == "all":  # as suggest finds it
                fit = find_table(image, detector.detect(image))[3]
            else:
                det = clean_detections(detector.detect(image))
                surface = read_surface(image, det, True) if args.cues == "surface" else None
                fit = estimate_table(image, det, size, cues=args.cues, pixel_aspect=det.pixel_aspect, surface=surface)
        except TableFitError as err:
            rows.append({"image": name, "fit": False, "error": str(err)})
            continue
        iou = table_box_iou(fit, boxes[classes == TABLE_CLASS])
        rows.append(
            {
                "image": name,
                "fit": True,
                "source": fit.source,
                "table": fit.spec.name,
                "size_source": fit.size_source,
                "diamonds": fit.n_matched,
                "rms_px": fit.rms_px,
                "table_box_iou": iou,
            }
        )
        if args.draw:
            import cv2

            args.draw.mkdir(parents=True, exist_ok=True)
            drawn = cv2.cvtColor(image, cv2.COLOR_RGB2BGR)
            outlines = ((rail_outline_px(fit), (0, 255, 255), 2), (fit.corners_px, (255, 0, 255), 1))
            for outline, colour, width in outlines:
                if np.all(np.isfinite(outline)):  # a close table's near corners may lie behind the camera
                    cv2.polylines(drawn, [outline.astype(np.int32).reshape(-1, 1, 2)], True, colour, width)
            head = fit.table_to_image(np.array([[0.0, 0.0], [0.0, fit.spec.width]]))  # the head rail, red
            if np.all(np.isfinite(head)):
                cv2.line(drawn, tuple(int(v) for v in head[0]), tuple(int(v) for v in head[1]), (0, 0, 255), 2)
            cv2.imwrite(str(args.draw / (path.stem + ".png")), drawn)
    fits = [r for r in rows if r["fit"]]
    agree = [r for r in fits if r["table_box_iou"] >= args.min_iou]
    print(f"{len(fits)} of {len(rows)} photos fit; {len(agree)} agree with the table box (IoU >= {args.min_iou})")
    for r in fits:
        flag = "" if r["table_box_iou"] >= args.min_iou else "   <- look"
        name = Path(r["image"]).name[:16]
        print(
            f"  {name}  {r['source']:>14}  {r['table']:>5} ({r['size_source']})  {r['diamonds']:>2} diamonds  "
            f"{r['rms_px']:4.1f} px  IoU {r['table_box_iou']:.2f}{flag}"
        )
    if args.json:
        report = {"photos": len(rows), "fits": len(fits), "agree": len(agree), "min_iou": args.min_iou, "rows": rows}
        Path(args.json).write_text(json.dumps(report, indent=1) + "\n")


if __name__ == "__main__":
    main()

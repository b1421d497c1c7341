"""Evaluate a detector on a YOLO-format dataset, before and after post-processing (the paper's Table 1)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from tqdm import tqdm

from pix2pockets.vision.classes import BALL_IDS, CLASS_NAMES
from pix2pockets.vision.detect.base import Detector
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.postprocess import DEFAULT_NMS_IOU, class_agnostic_nms, postprocess, resolve_ball_classes
from pix2pockets.vision.image_io import read_image_rgb
from pix2pockets.vision.metrics.detection import GroundTruth, evaluate_class, evaluate_classes, mean_metrics
from pix2pockets.vision.metrics.table_box import inside_table_boxes
from pix2pockets.vision.metrics.yolo_data import camera_kind_of, dataset_class_map, load_split

TABLE_ORDER = (3, 2, 0, 1, 4)  # the paper's column order: stripes, solids, cue, black, diamonds
TABLE_TITLES = {0: "Cue", 1: "Black", 2: "Solids", 3: "Stripes", 4: "Diamonds"}
POSTPROCESSORS: dict[str, Callable[[Detections, float], Detections]] = {
    "paper": postprocess,  # section 6.1: class-agnostic NMS, then the class caps
    "class-aware": resolve_ball_classes,  # the product pipeline's: one class per ball, cue and 8 once each
}
METRIC_ROWS = (("Precision", "precision"), ("Recall", "recall"), ("F1", "f1"), ("AP50", "ap50"), ("AP50:95", "ap50_95"))


@dataclass(frozen=True, slots=True)
class EvalOptions:
    """Evaluation settings.

    Attributes:
        split: dataset split folder.
        agnostic: class-agnostic ball metrics instead of per-class ones.
        ball_classes: dataset class ids that are balls in agnostic mode (others, e.g. a table box, ignored).
        conf_threshold: confidence above which detections count for precision / recall / F1.
        nms_iou: IoU of the post-processing NMS.
        limit: evaluate only the first ``limit`` images.
        post: the post-processing for the "after" column, a key of :data:`POSTPROCESSORS`.
        table_class: in agnostic mode, the dataset class id of a whole-table box: diamonds found outside it
            (widened by :data:`~pix2pockets.vision.metrics.table_box.TABLE_MARGIN`) are counted as false ("diamonds" in
            the report).
        camera_kinds: score only rendered images taken with these camera kinds (read from their ``meta/*.json``
            sidecars, :func:`~pix2pockets.vision.metrics.yolo_data.camera_kind_of`), e.g. the broadcast views
            ``("top", "high", "jib")``; all images when None.
    """

    split: str = "test"
    agnostic: bool = False
    ball_classes: tuple[int, ...] = BALL_IDS
    conf_threshold: float = 0.25
    nms_iou: float = DEFAULT_NMS_IOU
    limit: int | None = None
    post: str = "paper"
    table_class: int | None = None
    camera_kinds: tuple[str, ...] | None = None

    def __post_init__(self) -> None:
        if self.post not in POSTPROCESSORS:
            raise ValueError(f"unknown post-processing {self.post!r}; choose from {sorted(POSTPROCESSORS)}")


def evaluate_detector(detector: Detector, root: str, options: EvalOptions | None = None, progress: bool = True) -> dict:
    """Run ``detector`` on a dataset split and compute metrics before | after post-processing.

    Returns:
        A JSON-ready report: ``{"mode", "n_images", "before", "after"}`` with per-class (or agnostic) metrics as
        fractions in [0, 1]. In agnostic mode a detector with ``detect_balls`` (the any-ball heatmap) is also scored as
        ``"ball_head"``.
    """
    opt = options or EvalOptions()
    items = load_split(root, opt.split, None if opt.camera_kinds else opt.limit)
    if opt.camera_kinds:
        items = [it for it in items if camera_kind_of(it.image_path) in opt.camera_kinds][: opt.limit]
        if not items:
            raise ValueError(f"no {opt.split} images in {root} were taken with {', '.join(opt.camera_kinds)} cameras")
    cmap = {} if opt.agnostic else dataset_class_map(root)
    gts, raws, heads, tables = [], [], [], []
    use_head = opt.agnostic and hasattr(detector, "detect_balls")
    for it in tqdm(items, disable=not progress, desc="evaluate", unit="img"):
        image = read_image_rgb(it.image_path)
        if opt.agnostic:
            keep = np.isin(it.class_id, opt.ball_classes)
            gts.append(GroundTruth(it.boxes[keep], np.zeros(int(keep.sum()), dtype=int)))
        else:
            keep = np.isin(it.class_id, list(cmap))
            gts.append(GroundTruth(it.boxes[keep], np.array([cmap[k] for k in it.class_id[keep]], dtype=int)))
        tables.append(it.boxes[it.class_id == opt.table_class] if opt.table_class is not None else None)
        raws.append(detector.detect(image))
        if use_head:
            heads.append(detector.detect_balls(image))  # type: ignore[attr-defined]
    afters = [POSTPROCESSORS[opt.post](d, opt.nms_iou) for d in raws]
    report: dict = {"mode": "agnostic" if opt.agnostic else "classes", "n_images": len(items), "split": opt.split}
    report["post"] = opt.post
    if opt.camera_kinds:
        report["camera_kinds"] = list(opt.camera_kinds)
    if opt.agnostic:
        report["before"] = _agnostic(raws, gts, opt.conf_threshold)
        report["after"] = _agnostic(afters, gts, opt.conf_threshold)
        if opt.table_class is not None:
            report["diamonds"] = diamonds_off_table(afters, tables, opt.conf_threshold)
        if use_head:
            report["ball_head"] = {
                "before": _agnostic(heads, gts, opt.conf_threshold, balls_only=False),
                "after": _agnostic([class_agnostic_nms(d, opt.nms_iou) for d in heads], gts, opt.conf_threshold, False),
            }
        return report
    for tag, dets in (("before", raws), ("after", afters)):
        per = evaluate_classes(dets, gts, range(len(CLASS_NAMES)), opt.conf_threshold)
        report[tag] = {CLASS_NAMES[k]: m.as_dict() for k, m in per.items()}
        report[tag]["average"] = {k: round(v, 4) if np.isfinite(v) else None for k, v in mean_metrics(per).items()}
    return report


def diamonds_off_table(dets: Sequence[Detections], tables: Sequence[np.ndarray | None], conf: float) -> dict:
    """Diamonds per image found on and off the (widened) table box, over images that have a table box.

    With no diamond labels (ball-only photos), diamonds off the table are still certainly false.
    """
    on, off, n = 0, 0, 0
    for d, boxes in zip(dets, tables, strict=True):
        if boxes is None or not len(boxes):
            continue
        n += 1
        inside = inside_table_boxes(d.centres[d.is_diamond & (d.confidence >= conf)], boxes)
        on += int(inside.sum())
        off += int((~inside).sum())
    return {
        "images": n,
        "on_table_per_image": round(on / max(n, 1), 3),
        "off_table_per_image": round(off / max(n, 1), 3),
    }


def _agnostic(dets: Sequence[Detections], gts: Sequence[GroundTruth], conf: float, balls_only: bool = True) -> dict:
    pooled = [d[d.is_ball] if balls_only else d for d in dets]
    pooled = [Detections(d.boxes, d.own_score, np.zeros(len(d), int)) for d in pooled]  # a ball's own evidence
    return {"ball": evaluate_class(pooled, gts, None, conf).as_dict()}


def format_table(report: dict) -> str:
    """A Markdown table in the paper's Table 1 layout (values in percent, ``before | after``)."""
    fmt: Callable[[float | None], str] = lambda v: "-" if v is None else f"{100 * v:.1f}"  # noqa: E731
    if report["mode"] == "agnostic":
        rows = ["| source | " + " | ".join(t for t, _ in METRIC_ROWS) + " |", "|---" * (len(METRIC_ROWS) + 1) + "|"]
        sources = [("ball classes", report)]
        if "ball_head" in report:
            sources.append(("any-ball head", report["ball_head"]))
        for name, src in sources:
            b, a = src["before"]["ball"], src["after"]["ball"]
            rows.append(f"| {name} | " + " | ".join(f"{fmt(b[k])} \\| {fmt(a[k])}" for _, k in METRIC_ROWS) + " |")
        if "diamonds" in report:
            d = report["diamonds"]
            rows.append(
                f"\nDiamonds per image (after post-processing, {d['images']} images with a table box): "
                f"{d['on_table_per_image']:.2f} on the table, {d['off_table_per_image']:.2f} off it (false)."
            )
        return "\n".join(rows)
    cols = [CLASS_NAMES[k] for k in TABLE_ORDER] + ["average"]
    titles = [TABLE_TITLES[k] for k in TABLE_ORDER] + ["Average"]
    rows = ["| b \\| b' | " + " | ".join(titles) + " |", "|---" * (len(cols) + 1) + "|"]
    for title, key in METRIC_ROWS:
        cells = [f"{fmt(report['before'][c][key])} \\| {fmt(report['after'][c][key])}" for c in cols]
        rows.append(f"| {title} | " + " | ".join(cells) + " |")
    return "\n".join(rows)

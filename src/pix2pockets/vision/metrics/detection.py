"""Detection metrics: precision, recall, F1 at a confidence threshold, AP50 and AP50:95 (COCO-style).

AP is the area under the monotone (interpolated) precision-recall curve sampled at 101 recall points, as in
COCO and YOLOv5; a detection is a true positive when it overlaps a not-yet-matched ground-truth box of the
same class with IoU >= the threshold (greedy, highest confidence first).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.postprocess import box_iou

IOU_THRESHOLDS = tuple(np.round(np.arange(0.5, 0.96, 0.05), 2))


@dataclass(frozen=True, slots=True)
class GroundTruth:
    """Ground truth of one image: boxes xyxy [px] (n, 4) and class ids (n,)."""

    boxes: np.ndarray
    class_id: np.ndarray


@dataclass(frozen=True, slots=True)
class ClassMetrics:
    """Metrics of one class (fractions in [0, 1]; NaN when the class has no ground truth)."""

    precision: float
    recall: float
    f1: float
    ap50: float
    ap50_95: float
    n_gt: int
    n_det: int

    def as_dict(self) -> dict[str, float | int]:
        return {
            k: (
                round(float(v), 4) if isinstance(v, float) and np.isfinite(v) else (None if isinstance(v, float) else v)
            )
            for k, v in (
                ("precision", self.precision),
                ("recall", self.recall),
                ("f1", self.f1),
                ("ap50", self.ap50),
                ("ap50_95", self.ap50_95),
                ("n_gt", self.n_gt),
                ("n_det", self.n_det),
            )
        }


def average_precision(tp: np.ndarray, scores: np.ndarray, n_gt: int) -> float:
    """101-point interpolated AP from per-detection true-positive flags and scores; NaN if ``n_gt`` is 0."""
    if n_gt == 0:
        return float("nan")
    if len(tp) == 0:
        return 0.0
    order = np.argsort(-scores, kind="stable")
    tp = np.asarray(tp, dtype=float)[order]
    ctp, cfp = np.cumsum(tp), np.cumsum(1 - tp)
    recall = ctp / n_gt
    precision = ctp / np.maximum(ctp + cfp, 1e-12)
    # Monotone envelope: precision at recall r is the best precision at any recall >= r.
    envelope = np.maximum.accumulate(precision[::-1])[::-1]
    points = np.linspace(0, 1, 101)
    idx = np.searchsorted(recall, points, side="left")
    sampled = np.where(idx < len(envelope), envelope[np.minimum(idx, len(envelope) - 1)], 0.0)
    return float(np.mean(sampled))


def match_image(
    det_boxes: np.ndarray, det_scores: np.ndarray, gt_boxes: np.ndarray, thresholds: Sequence[float]
) -> np.ndarray:
    """True-positive flags (n_det, n_thresholds) for one image and one class, greedy by score."""
    n, m = len(det_boxes), len(gt_boxes)
    tp = np.zeros((n, len(thresholds)), dtype=bool)
    if n == 0 or m == 0:
        return tp
    ious = box_iou(det_boxes, gt_boxes)
    order = np.argsort(-det_scores, kind="stable")
    for t, thr in enumerate(thresholds):
        used = np.zeros(m, dtype=bool)
        for i in order:
            cand = np.where(~used, ious[i], -1.0)
            j = int(np.argmax(cand))
            if cand[j] >= thr:
                used[j] = True
                tp[i, t] = True
    return tp


def evaluate_class(
    dets: Sequence[Detections], gts: Sequence[GroundTruth], class_id: int | None, conf_threshold: float = 0.25
) -> ClassMetrics:
    """Metrics of one class over a dataset; ``class_id=None`` pools all classes (class-agnostic).

    Raises:
        ValueError: if the detection and ground-truth lists differ in length.
    """
    if len(dets) != len(gts):
        raise ValueError(f"{len(dets)} detection sets for {len(gts)} ground truths")
    all_tp, all_scores, n_gt = [], [], 0
    for d, g in zip(dets, gts, strict=True):
        dm = np.ones(len(d), bool) if class_id is None else d.class_id == class_id
        gm = np.ones(len(g.class_id), bool) if class_id is None else g.class_id == class_id
        n_gt += int(gm.sum())
        all_tp.append(match_image(d.boxes[dm], d.confidence[dm], np.asarray(g.boxes)[gm], IOU_THRESHOLDS))
        all_scores.append(d.confidence[dm])
    tp = np.vstack(all_tp) if all_tp else np.zeros((0, len(IOU_THRESHOLDS)), bool)
    scores = np.concatenate(all_scores) if all_scores else np.zeros(0)
    aps = [average_precision(tp[:, t], scores, n_gt) for t in range(len(IOU_THRESHOLDS))]
    sel = scores >= conf_threshold
    n_tp = int(tp[sel, 0].sum())
    n_det = int(sel.sum())
    precision = n_tp / n_det if n_det else (float("nan") if n_gt == 0 else 0.0)
    recall = n_tp / n_gt if n_gt else float("nan")
    f1 = 2 * precision * recall / (precision + recall) if (precision + recall) > 0 else 0.0
    if not np.isfinite(precision) or not np.isfinite(recall):
        f1 = float("nan")
    return ClassMetrics(precision, recall, f1, aps[0], float(np.mean(aps)), n_gt, n_det)


def evaluate_classes(
    dets: Sequence[Detections], gts: Sequence[GroundTruth], class_ids: Sequence[int], conf_threshold: float = 0.25
) -> dict[int, ClassMetrics]:
    """Per-class metrics for the given class ids."""
    return {c: evaluate_class(dets, gts, c, conf_threshold) for c in class_ids}


def mean_metrics(per_class: dict[int, ClassMetrics]) -> dict[str, float]:
    """Unweighted mean over classes that have ground truth (the paper's "Average" column)."""
    keys = ("precision", "recall", "f1", "ap50", "ap50_95")
    rows = [m for m in per_class.values() if m.n_gt > 0]
    return {k: (float(np.nanmean([getattr(m, k) for m in rows])) if rows else float("nan")) for k in keys}

"""Whole-table boxes of ball-only photos: which points lie on the table (used to score and train diamonds)."""

from __future__ import annotations

import numpy as np

TABLE_MARGIN = 0.04
"""A table box is widened by this fraction of its size on each side (hand-drawn boxes sometimes clip the far
rail) before a point counts as off the table."""


def inside_table_boxes(points: np.ndarray, boxes: np.ndarray, margin: float = TABLE_MARGIN) -> np.ndarray:
    """Mask (n,) of points (n, 2) [px] inside at least one widened xyxy table box (m, 4) [px]."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    inside = np.zeros(len(points), dtype=bool)
    for x0, y0, x1, y1 in np.asarray(boxes, dtype=float).reshape(-1, 4):
        mx, my = margin * (x1 - x0), margin * (y1 - y0)
        inside |= (
            (points[:, 0] >= x0 - mx)
            & (points[:, 0] <= x1 + mx)
            & (points[:, 1] >= y0 - my)
            & (points[:, 1] <= y1 + my)
        )
    return inside

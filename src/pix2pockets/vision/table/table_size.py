"""The table's size from the balls: a photo without diamonds fixes the table only up to scale.

Object balls are 57.15 mm across on every pool table, so balls that look this big stand this far from the camera.
A camera fitted to a table of the wrong size sees the same photo from a distance off by the same factor, and the
balls it predicts are off in size by that factor too (:func:`size_from_balls`). The measured table is snapped to
the nearest preset (:data:`~pix2pockets.geometry.table.TABLE_PRESETS`) when close (:func:`spec_of_length`).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.table import INCH, TABLE_PRESETS, TableSpec, same_balls

SNAP_TOLERANCE = 0.18
"""A table measured from the balls within this log-ratio of a preset's length is taken as that preset (real ball
boxes are loose or tight by 10-15 %)."""
SIZE_MARGIN = 1.15
"""Tables are made from 6 to 9 ft: a measured length this factor beyond that range is held at it."""
MIN_BALLS_FOR_SIZE = 2
"""Balls on the table needed to measure its size."""


def ball_sizes_px(boxes: np.ndarray, pixel_aspect: float = 1.0) -> np.ndarray:
    """Apparent ball diameters [px of image height] from boxes (n, 4): the larger box side once unstretched (a ball
    cut by another or by the frame keeps its other side)."""
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    return np.maximum((boxes[:, 2] - boxes[:, 0]) / pixel_aspect, boxes[:, 3] - boxes[:, 1])


def size_from_balls(
    camera: PinholeCamera, boxes: np.ndarray, spec: TableSpec, pixel_aspect: float = 1.0
) -> float | None:
    """The factor by which the real table is larger than ``spec`` as fitted by ``camera``, read from the balls'
    apparent size (``spec.ball_radius`` balls), or None with fewer than :data:`MIN_BALLS_FOR_SIZE` balls on the table.

    A world ``k`` times larger seen in the same photo puts the camera ``k`` times further away, so balls of the real
    radius look ``k`` times smaller than those the fitted camera predicts. The median over the balls is used.
    """
    from pix2pockets.vision.locate.balls import locate_sphere, sphere_boxes  # locate imports this package

    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    if len(boxes) < MIN_BALLS_FOR_SIZE:
        return None
    observed = ball_sizes_px(boxes, pixel_aspect)
    k = 1.0
    for _ in range(3):
        r = spec.ball_radius / k
        xy = locate_sphere(camera, boxes, r)
        ok = np.all(np.isfinite(xy), axis=1) & spec.contains(np.nan_to_num(xy, nan=-1e9), margin=-0.05)
        if ok.sum() < MIN_BALLS_FOR_SIZE:
            return None
        centres = np.column_stack([xy[ok], np.full(int(ok.sum()), r)])
        predicted = ball_sizes_px(sphere_boxes(camera, centres, r), pixel_aspect)
        k *= float(np.median(predicted / np.maximum(observed[ok], 1e-6)))
        if not 0.2 < k < 5.0:
            return None
    return k


def spec_of_length(length: float, base: TableSpec | None = None) -> TableSpec:
    """The table of playing-surface ``length`` [m]: the nearest preset for balls of ``base``'s size (American or UK)
    within :data:`SNAP_TOLERANCE`, else ``base`` (default 9-foot) resized to that length with the usual 2:1
    proportions, named by its nominal size. A length beyond those presets' range by more than :data:`SIZE_MARGIN`
    is a misread (loose ball boxes, a wrong outline) and is held at that margin first."""
    base = base or TableSpec()
    family = [p for p in TABLE_PRESETS.values() if same_balls(p, base)] or [base]
    lengths = [p.length for p in family]
    length = float(np.clip(length, min(lengths) / SIZE_MARGIN, max(lengths) * SIZE_MARGIN))
    nearest = min(family, key=lambda p: abs(math.log(p.length / length)))
    if abs(math.log(nearest.length / length)) <= SNAP_TOLERANCE:
        return nearest
    feet = length / (12 * INCH) + 0.5  # nominal feet: the playing length plus about half a foot of rails
    return replace(base, name=f"{feet:.1f}ft (measured)", length=length, width=length / 2)

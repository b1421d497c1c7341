"""The table from its two long cushions alone: the two lines, their side pockets and a corner.

A close view across the table shows its two long cushions and little else: the far one with its side pocket, the near
one along the bottom of the frame, the short cushions cut away. Two lines that are a rectangle's opposite sides meet
at the vanishing point of its long direction; for a camera of known focal length (square pixels, principal point at
the image centre) that fixes the long direction in space, and the table's plane is one turn about it away (an angle
``theta``). The two lines then lie a fixed distance apart on that plane, which sets the scale, and every point seen on
them gets a place along the table. The side pockets are at the middle of the long cushions, the corners at their ends
(half a table's length from the pockets): two such marks fix the turn and the focal length, one fixes the turn for a
focal length taken from a prior.

Example:
    >>> quads = complete_two_long_cushions(far, near, marks, 900.0, (960, 540), 2.54, 1.27)  # doctest: +SKIP
    >>> quads[0].quad, quads[0].cost  # doctest: +SKIP
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from pix2pockets.vision.table.outline_camera import FOCAL_RANGE, cross3, intrinsics

THETA_STEPS = 360
"""Turns of the table's plane about its long direction tried before refining."""
MARK_SIGMA = 0.01
"""Expected error of a mark's place along the table, as a share of its length (a pocket or corner peak a pixel or
two off)."""


@dataclass(frozen=True, slots=True)
class CushionMark:
    """A point seen on one of the two long cushion lines whose place along the table is known.

    Attributes:
        px: (2,) the point [px] (moved onto its line).
        line: 0 or 1, which of the two lines it lies on.
        kind: ``"pocket"`` (a side pocket: the cushion's middle) or ``"corner"`` (a playing-surface corner: its end).
    """

    px: np.ndarray
    line: int
    kind: str


@dataclass(frozen=True, slots=True)
class TwoCushionTable:
    """One table the two lines and their marks allow.

    Attributes:
        quad: (4, 2) the rectangle's corners [px] in table corner order: the first two on line 0, the other two on
            line 1 (side 0 along line 0 is long).
        focal: the focal length it was found for [px].
        cost: the marks' misfit (squared, in :data:`MARK_SIGMA` units).
    """

    quad: np.ndarray
    focal: float
    cost: float


def _frame(line0: np.ndarray, line1: np.ndarray, Kinv: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The long direction ``d1`` (unit, camera frame) of two image lines, and two unit vectors at right angles to it
    and to each other (the plane's normal turns between them)."""
    d1 = Kinv @ cross3(line0, line1)
    d1 = d1 / np.linalg.norm(d1)
    helper = np.array([0.0, 0.0, 1.0]) if abs(d1[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1 = cross3(d1, helper)
    e1 = e1 / np.linalg.norm(e1)
    return d1, e1, cross3(d1, e1)


def _foot(line: np.ndarray, point: np.ndarray) -> np.ndarray:
    """The point of ``line`` (a, b, c) nearest ``point`` (2,) [px]."""
    n = line[:2] / np.hypot(line[0], line[1])
    c = line[2] / np.hypot(line[0], line[1])
    return point - (point @ n + c) * n


def complete_two_long_cushions(
    line0: np.ndarray,
    line1: np.ndarray,
    marks: list[CushionMark],
    focal: float,
    image_size: tuple[float, float],
    length: float,
    width: float,
    free_focal: bool = False,
) -> list[TwoCushionTable]:
    """The rectangles (``length`` by ``width`` [m]) whose long sides the camera sees on ``line0`` and ``line1``
    (lines ``a u + b v + c = 0``), placed by the ``marks`` on them.

    Args:
        line0, line1: the two long cushion lines (3,).
        marks: the side pockets and corners seen on them; at least one pocket and two marks in all.
        focal: focal length [px] (square pixels, principal point at the image centre); with ``free_focal`` the
            starting point of a refinement that moves it too (two marks or more beyond the first fix both).
        image_size: (width, height) [px].
        length, width: the rectangle's sides [m].
        free_focal: refine the focal length as well as the turn.

    Returns:
        The rectangles that fit the marks best, one per distinct turn, best first (empty when the lines meet inside
        the photo's view of the marks, or no turn puts the marks in front of the camera).
    """
    line0, line1 = (np.asarray(x, dtype=float) for x in (line0, line1))
    pockets = [k for k, m in enumerate(marks) if m.kind == "pocket"]
    if not pockets or len(marks) < 2:
        return []
    centre = np.array([image_size[0] / 2, image_size[1] / 2])
    feet = [_foot(line0, centre), _foot(line1, centre)]
    points = np.array([_foot(line0 if m.line == 0 else line1, np.asarray(m.px, dtype=float)) for m in marks])

    def geometry(theta: np.ndarray, f: float) -> tuple[np.ndarray, ...]:
        """Per turn: the marks' places along the table [m], the lines' places across it [m] and the unit plane's
        scale (metres per unit), with NaN where a point lies behind the camera."""
        K = intrinsics(f, image_size)
        Kinv = np.linalg.inv(K)
        d1, e1, e2 = _frame(line0, line1, Kinv)
        n = np.cos(theta)[:, None] * e1 + np.sin(theta)[:, None] * e2  # (T, 3) plane normals
        d2 = np.cross(n, d1)
        rays = np.column_stack([np.vstack([points, feet]), np.ones(len(points) + 2)]) @ Kinv.T  # (P, 3)
        depth = n @ rays.T  # (T, P): the unit plane n.X = 1 meets ray r at r / (n.r)
        with np.errstate(divide="ignore", invalid="ignore"):
            X = rays[None] / depth[:, :, None]
        X = np.where((depth > 1e-9)[:, :, None], X, np.nan)
        along = X @ d1  # (T, P)
        across = np.einsum("tpk,tk->tp", X[:, -2:], d2)
        scale = width / np.abs(across[:, 0] - across[:, 1])
        return along[:, :-2] * scale[:, None], across * scale[:, None], scale, n, d1, d2, K

    def residuals(theta: np.ndarray, f: float) -> np.ndarray:
        """(T, R) the marks' misfit along the table, in shares of its length."""
        along = geometry(theta, f)[0]
        at_pockets = _mean_of_finite(along[:, pockets])
        out = []
        for k, m in enumerate(marks):
            if m.kind == "pocket":
                out.append((along[:, k] - at_pockets) / length)
            else:
                out.append((np.abs(along[:, k] - at_pockets) - length / 2) / length)
        res = np.column_stack(out) / MARK_SIGMA
        return np.where(np.isfinite(res), res, 1e3)

    thetas = np.linspace(0.0, 2 * math.pi, THETA_STEPS, endpoint=False)
    costs = np.sum(residuals(thetas, focal) ** 2, axis=1)
    minima = [i for i in range(THETA_STEPS) if costs[i] <= costs[i - 1] and costs[i] <= costs[(i + 1) % THETA_STEPS]]
    found: list[TwoCushionTable] = []
    turns: list[float] = []
    for i in sorted(minima, key=lambda i: costs[i])[:4]:
        if costs[i] >= 1e5:
            continue
        if free_focal and len(marks) >= 3:
            side = max(image_size)
            bounds = (
                [-np.inf, math.log(FOCAL_RANGE[0] * side / focal)],
                [np.inf, math.log(FOCAL_RANGE[1] * side / focal)],
            )
            fit = least_squares(
                lambda p: residuals(np.array([p[0]]), focal * math.exp(p[1]))[0], [thetas[i], 0.0], bounds=bounds
            )
            theta, f = float(fit.x[0]), focal * math.exp(float(fit.x[1]))
        else:
            fit = least_squares(lambda p: residuals(p, focal)[0], [thetas[i]], method="lm")
            theta, f = float(fit.x[0]), focal
        quad = _rectangle(geometry, theta, f, pockets, length)
        if quad is None:
            continue
        if any(abs(math.remainder(theta - turn, 2 * math.pi)) < 1e-3 for turn in turns):
            continue  # two starting points refined onto one turn
        turns.append(theta)
        found.append(TwoCushionTable(quad, f, float(np.sum(residuals(np.array([theta]), f) ** 2))))
    found.sort(key=lambda t: t.cost)
    return found


def _rectangle(geometry, theta: float, f: float, pockets: list[int], length: float) -> np.ndarray | None:
    """The rectangle's image corners for one turn and focal length (None when a corner lies behind the camera)."""
    along, across, scale, n, d1, d2, K = geometry(np.array([theta]), f)
    mid = float(_mean_of_finite(along[:1, pockets])[0])
    if not math.isfinite(mid):
        return None
    s = float(scale[0])
    ends = (mid - length / 2, mid + length / 2)
    corners = [(ends[0], across[0, 0]), (ends[1], across[0, 0]), (ends[1], across[0, 1]), (ends[0], across[0, 1])]
    out = []
    for x, y in corners:
        X = n[0] + (x / s) * d1 + (y / s) * d2[0]
        p = K @ X
        if p[2] <= 1e-9:
            return None
        out.append(p[:2] / p[2])
    return np.array(out)


def _mean_of_finite(values: np.ndarray) -> np.ndarray:
    """Row means (T,) of ``values`` (T, k) over their finite entries; NaN for a row with none."""
    finite = np.isfinite(values)
    count = finite.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, np.where(finite, values, 0.0).sum(axis=1) / count, np.nan)

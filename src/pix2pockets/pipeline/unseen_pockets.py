"""Pockets the photo does not show: where the table fit is least sure, and what that does to a shot.

A table cut by the frame is fitted well where the photo shows it and the worse the further from it: on renders whose
fit the pipeline accepts (at least half the table in view), the fitted playing-surface corners in the photo lie 8 mm
from the true ones (median) and those beyond it a third of their distance from the part of the table in the photo
(``benchmarks/cut_table_fit.py``, 92 corners more than :data:`UNSEEN_MARGIN` beyond it). A shot sends its object
ball along the planned line to where the fit puts the pocket; a pocket beyond the photo may lie elsewhere by
:data:`POCKET_SIGMA_PER_METRE` times that distance per axis, so its chance is measured with that error
(:func:`pix2pockets.planner.chance.measure_chance`, ``pocket_sigma``) and shots are ranked by the share of such
errors their pocket still takes (:func:`pocket_hit_share`).

Example:
    >>> pocket_sigmas(fit.camera, spec, (1280, 720)).round(2)  # doctest: +SKIP
    array([0.34, 0.  , 0.  , 0.34, 0.  , 0.  ])
"""

from __future__ import annotations

import math

import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.table import TableSpec

POCKET_SIGMA_PER_METRE = 0.28
"""Error per axis of a pocket beyond the photo per metre it lies from the part of the table the photo shows [m/m]:
the Gaussian whose distance error has the measured median, a third of the distance (0.33; 0.33 / 1.18, the median of a
2-D Gaussian's distance being 1.18 sigma)."""
UNSEEN_MARGIN = 0.05
"""A pocket this close to the part of the table in the photo [m] counts as seen (corners within it are fitted as well
as those in the photo: 13 mm median over 507)."""
MAX_POCKET_SIGMA = 0.5
"""Largest pocket error per axis [m] (a shot to such a pocket is a guess either way)."""
UNSEEN_GRID = 0.02
"""Spacing of the playing-surface points tested for being in the photo [m]."""


def table_points_in_photo(camera: PinholeCamera, points: np.ndarray, image_size: tuple[int, int]) -> np.ndarray:
    """Whether each point on the cloth (n, 2) [m] lies inside the photo (n,) (``False`` behind the camera)."""
    w, h = image_size
    uv = camera.project_table(np.asarray(points, dtype=float).reshape(-1, 2), 0.0)  # NaN behind the camera
    with np.errstate(invalid="ignore"):
        return (uv[:, 0] >= 0) & (uv[:, 0] <= w) & (uv[:, 1] >= 0) & (uv[:, 1] <= h)


def pockets_in_photo(camera: PinholeCamera, spec: TableSpec, image_size: tuple[int, int]) -> np.ndarray:
    """Whether each pocket's centre (``spec.pockets`` order) lies inside the photo (6,)."""
    return table_points_in_photo(camera, spec.pocket_centres, image_size)


def distances_out_of_photo(
    camera: PinholeCamera, spec: TableSpec, image_size: tuple[int, int], points: np.ndarray
) -> np.ndarray:
    """How far each table point (n, 2) [m] lies from the part of the playing surface the photo shows (n,) [m]: 0 in
    the photo, inf when the photo shows none of it (within :data:`UNSEEN_GRID`)."""
    xs = np.arange(0.0, spec.length + 1e-9, UNSEEN_GRID)
    ys = np.arange(0.0, spec.width + 1e-9, UNSEEN_GRID)
    grid = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
    seen = grid[table_points_in_photo(camera, grid, image_size)]
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(seen) == 0:
        return np.full(len(points), np.inf)
    return np.linalg.norm(points[:, None, :] - seen[None], axis=-1).min(axis=1)


def pocket_sigmas(camera: PinholeCamera, spec: TableSpec, image_size: tuple[int, int]) -> np.ndarray:
    """Each pocket's position error per axis (``spec.pockets`` order) [m]: 0 where the photo shows it (within
    :data:`UNSEEN_MARGIN`), else :data:`POCKET_SIGMA_PER_METRE` times its distance from the part of the table in the
    photo, at most :data:`MAX_POCKET_SIGMA`. A pocket is placed where it meets the playing surface (a corner, or the
    middle of a long cushion)."""
    mouths = spec.pocket_centres
    mouths[:, 0] = np.clip(mouths[:, 0], 0.0, spec.length)
    mouths[:, 1] = np.clip(mouths[:, 1], 0.0, spec.width)
    out = distances_out_of_photo(camera, spec, image_size, mouths)
    return np.where(out < UNSEEN_MARGIN, 0.0, np.minimum(POCKET_SIGMA_PER_METRE * out, MAX_POCKET_SIGMA))


def pocket_hit_share(spec: TableSpec, pocket: int, sigma: float) -> float:
    """The share of pocket position errors (Gaussian, ``sigma`` [m] per axis) that a ball sent at the pocket's
    middle still drops into: the error across the line must stay within the mouth's free half-width (half the jaw
    gap less a ball radius)."""
    if sigma <= 0:
        return 1.0
    free = max(0.5 * spec.pockets[pocket].mouth_width - spec.ball_radius, 0.25 * spec.ball_radius)
    return math.erf(free / (sigma * math.sqrt(2.0)))

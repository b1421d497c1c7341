"""How far a ball located in a photo may lie from where it is: each ball's position error on the table.

A ball's centre is read from the photo to about :data:`BALL_CENTRE_SIGMA_PX`, and the fitted table reprojects the
cues it was fitted to with a root-mean-square error ``rms_px``; both are errors in the image. Through the camera a
pixel at the far end of a low view spans centimetres of cloth and one near the camera millimetres, so ball ``i``'s
error on the table is the image error mapped through the camera at that ball (``J_i``, metres per pixel, the inverse
of the table-to-image Jacobian at the ball centre's height), a 2 x 2 covariance

    Sigma_i = (BALL_CENTRE_SIGMA_PX**2 + (FIT_ERROR_SHARE rms_px)**2) J_i J_i^T + POSITION_FLOOR**2 I.

A fitted table is surer than any one of its cues (it averages over them), hence the share. The floor stands for what
no pixel shows (a ball's true radius, cloth that is not flat). A shaky fit (a large ``rms_px``) or a far ball thus
widens the spread of positions that a shot's chance is measured over. A ball whose box falls short of the part
of it that should be in view (a cue or a hand over it: what hides it is not modelled, so neither is the side) adds
half the shortfall ``s_i`` per image axis, ``J_i diag((s_i / 2)**2) J_i^T``.

Example:
    >>> cov = position_covariances(fit.camera, layout.positions, spec.ball_radius, fit.rms_px)  # doctest: +SKIP
    >>> position_sigmas(cov)  # doctest: +SKIP
    array([0.0031, 0.0046, ...])
"""

from __future__ import annotations

import math

import numpy as np

from pix2pockets.geometry.camera import PinholeCamera

BALL_CENTRE_SIGMA_PX = 1.0
"""Error of a ball centre read from a photo, per image axis [px]: about twice the detector's centre error on renders
(0.4-0.5 px), for real photos (an estimate)."""
FIT_ERROR_SHARE = 0.25
"""Share of the fit's reprojection error that a located position inherits. Chosen on the real photos whose table fit
is right (147 of the 166 with corners labelled by eye, ``benchmarks/data/real_table_corners.json``): there the fitted
cloth corners lie 13.6 mm (rms) from the labelled ones on the table, and this model predicts 12.5 mm at those
corners (10.3 mm with a share of 0, 17.5 mm with 0.5, 30 mm with 1)."""
POSITION_FLOOR = 0.001
"""Error of a located ball that no pixel shows, per table axis [m]."""
MAX_POSITION_SIGMA = 0.05
"""Largest position error per axis [m]: beyond a ball's diameter the table fit, not the ball, is in doubt."""


def position_covariances(
    camera: PinholeCamera,
    xy: np.ndarray,
    height: float,
    rms_px: float | None,
    shortfall_px: np.ndarray | None = None,
) -> np.ndarray:
    """Each ball's position covariance on the table (n, 2, 2) [m^2].

    Args:
        camera: the fitted camera.
        xy: ball centres on the table (n, 2) [m].
        height: height of the ball centres above the cloth [m] (the ball radius).
        rms_px: the fit's reprojection error [px] (``None`` or not finite: 0).
        shortfall_px: per ball and image axis, how much of it something the photo does not explain hides (n, 2)
            [px] (:func:`~pix2pockets.vision.locate.visibility.unexplained_shortfall`): its centre there is unsure
            by half of it more, on a side not known.
    """
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    fit_px = float(rms_px) if rms_px is not None and math.isfinite(rms_px) else 0.0
    pixel_var = BALL_CENTRE_SIGMA_PX**2 + (FIT_ERROR_SHARE * fit_px) ** 2
    H = camera.table_homography(height)
    pts = np.column_stack([xy, np.ones(len(xy))])
    w = pts @ H[2]
    uv = (pts @ H[:2].T) / w[:, None]
    # d(uv)/d(xy) of a homography: (H[:2, :2] - uv H[2, :2]) / w
    jac = (H[None, :2, :2] - uv[:, :, None] * H[None, None, 2, :2]) / w[:, None, None]
    cov = np.full((len(xy), 2, 2), np.nan)
    ok = np.isfinite(jac).all(axis=(1, 2)) & (np.abs(np.linalg.det(jac)) > 1e-12) & (w > 0)
    m_per_px = np.linalg.inv(jac[ok])
    image_var = np.zeros((len(xy), 2))
    if shortfall_px is not None:
        image_var += (np.asarray(shortfall_px, dtype=float).reshape(-1, 2) / 2) ** 2
    image_cov = (pixel_var + image_var[ok])[:, :, None] * np.eye(2)[None]
    cov[ok] = m_per_px @ image_cov @ np.transpose(m_per_px, (0, 2, 1))
    cov[~ok] = np.eye(2) * MAX_POSITION_SIGMA**2
    cov += np.eye(2) * POSITION_FLOOR**2
    return _capped(cov)


def position_sigmas(cov: np.ndarray) -> np.ndarray:
    """Each ball's error along its worst direction (n,) [m]: the square root of its covariance's larger
    eigenvalue."""
    return np.sqrt(np.linalg.eigvalsh(np.asarray(cov, dtype=float))[:, -1])


def _capped(cov: np.ndarray) -> np.ndarray:
    """Covariances whose larger axis is at most :data:`MAX_POSITION_SIGMA`, scaled down whole (shape kept)."""
    worst = position_sigmas(cov)
    scale = np.minimum(1.0, MAX_POSITION_SIGMA / np.maximum(worst, 1e-12)) ** 2
    return cov * scale[:, None, None]

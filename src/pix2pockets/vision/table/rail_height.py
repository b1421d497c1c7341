"""Height of the diamond plane (rail cap) above the cloth, measured from the cushion nose lines.

The diamonds fix the camera relative to the diamond plane only; where the cloth lies below it is a guess
(:func:`~pix2pockets.vision.table.fit.diamond_height`), and a wrong guess shifts every located ball by
about the error x ``1 / tan(camera elevation)``. The cushion noses are the strongest feature at a known
height: they run along the playing-surface boundary at ``spec.cushion_height`` above the cloth, and from
any view above the table they are an occluding edge (cushion top against cloth or cushion face).

For a candidate rise ``r`` of the diamonds above the nose, the nose segments between the pockets are
projected with the fitted camera and the image gradient across them is sampled (a 1-D search: the fitted
camera is exact for every ``r`` up to a vertical shift of the cloth, see
:meth:`~pix2pockets.vision.table.fit.TableFit.with_diamond_z`). Per nose segment the samples are reduced
by a median (balls, cues and hands on the rail are outliers), giving an edge-strength profile over ``r``;
the profiles of the segments are normalised by their noise and summed, and the best ``r`` is refined to
sub-step precision. The estimate is used only when the peak is clear and inside the searched range;
otherwise the fit's assumed height stays (graceful fallback).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from pix2pockets.vision.table.fit import TableFit

RISE_RANGE = (-0.004, 0.024)
"""Searched rise of the diamond plane above the cushion nose [m]."""
RISE_STEP = 0.00025  # [m]
SAMPLE_SPACING_PX = 2.0
END_MARGIN = 0.05  # nose length left out next to each pocket's jaws [m]
MIN_SENSITIVITY = 10.0  # least nose shift across itself per metre of rise [px / m]
MIN_SCORE = 8.0  # least combined peak strength to trust the estimate (noise units)


@dataclass(frozen=True, slots=True)
class RailHeight:
    """Result of :func:`estimate_rail_height`.

    Attributes:
        diamond_z: the diamond-plane height to use [m] (the estimate, or the fit's own when not ``measured``).
        rise: ``diamond_z - spec.cushion_height`` [m].
        measured: whether the image gave a usable estimate (``False``: the prior was kept).
        score: peak strength of the combined edge profile (noise units).
        segments: number of nose segments that took part.
        reason: why the prior was kept (empty when measured).
    """

    diamond_z: float
    rise: float
    measured: bool
    score: float
    segments: int
    reason: str = ""


def _gray_gradients(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Image gradients (gx, gy) of the luminance [levels / px], float32."""
    img = np.asarray(image)
    if img.ndim == 3:
        gray = cv2.cvtColor(img[:, :, :3].astype(np.float32), cv2.COLOR_RGB2GRAY)
    else:
        gray = img.astype(np.float32)
    gx = cv2.Sobel(gray, cv2.CV_32F, 1, 0, ksize=3, scale=0.125)
    gy = cv2.Sobel(gray, cv2.CV_32F, 0, 1, ksize=3, scale=0.125)
    return gx, gy


def _nose_samples(fit: TableFit, spacing_px: float) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per nose segment: sample points along it [m] (n, 2) and the inward unit normal (2,)."""
    spec = fit.spec
    out = []
    centre = spec.size / 2
    for a, b in spec.cushion_segments:
        d = b - a
        length = float(np.linalg.norm(d))
        if length <= 2 * END_MARGIN:
            continue
        u = d / length
        normal = np.array([-u[1], u[0]])
        if normal @ (centre - a) < 0:
            normal = -normal
        ends = np.array([a + END_MARGIN * u, b - END_MARGIN * u])
        px = fit.camera.project_table(ends, spec.cushion_height)
        if not np.all(np.isfinite(px)):
            continue
        n = int(np.clip(np.linalg.norm(px[1] - px[0]) / spacing_px, 2, 2000))
        s = np.linspace(0.0, 1.0, n)[:, None]
        out.append((ends[0] + s * (ends[1] - ends[0]), normal))
    return out


def edge_profiles(
    image: np.ndarray,
    fit: TableFit,
    rises: np.ndarray,
    ball_boxes: np.ndarray | None = None,
    spacing_px: float = SAMPLE_SPACING_PX,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Median signed edge strength across each nose segment for each candidate rise.

    Args:
        image: the photo, RGB or gray (H, W[, 3]).
        fit: the table fit (camera relative to the diamond plane).
        rises: candidate rises of the diamond plane above the cushion nose [m] (k,).
        ball_boxes: ball boxes [px] (n, 4); samples inside them (padded) are ignored.
        spacing_px: sample spacing along the noses [px].

    Returns:
        ``(profiles, noise, sensitivity)``: profiles (segments, k) [levels / px], each segment's noise
        level (segments,) and how far its nose moves across itself per metre of rise [px / m] (segments,).
    """
    gx, gy = _gray_gradients(image)
    h_img, w_img = gx.shape
    spec = fit.spec
    cam = fit.camera
    rises = np.asarray(rises, dtype=float)
    # a physical point at height z lies at z - (h - h_fit) in the fitted camera's frame
    z_fit = spec.cushion_height - (spec.cushion_height + rises - fit.diamond_z)
    boxes = np.zeros((0, 4)) if ball_boxes is None else np.asarray(ball_boxes, dtype=float).reshape(-1, 4)
    pad = 0.15 * (boxes[:, 2:] - boxes[:, :2]).max(axis=1, initial=0.0)[:, None] if len(boxes) else None
    profiles, noise, sens = [], [], []
    for xy, normal in _nose_samples(fit, spacing_px):
        pts = np.concatenate(
            [
                np.broadcast_to(xy[:, None, :], (len(xy), len(rises), 2)),
                np.broadcast_to(z_fit[None, :, None], (len(xy), len(rises), 1)),
            ],
            axis=-1,
        )
        uv = cam.project(pts)  # (n, k, 2)
        inner = cam.project(pts + np.array([normal[0], normal[1], 0.0]) * 0.01)
        d = inner - uv
        with np.errstate(invalid="ignore", divide="ignore"):
            d /= np.linalg.norm(d, axis=-1, keepdims=True)
        ok = np.all(np.isfinite(uv), axis=(1, 2)) & np.all(np.isfinite(d), axis=(1, 2))
        ok &= np.all((uv[..., 0] > 2) & (uv[..., 0] < w_img - 3) & (uv[..., 1] > 2) & (uv[..., 1] < h_img - 3), axis=1)
        if len(boxes):
            mid = uv[:, len(rises) // 2]
            inside = (
                (mid[:, None, 0] > boxes[None, :, 0] - pad[None, :, 0])
                & (mid[:, None, 0] < boxes[None, :, 2] + pad[None, :, 0])
                & (mid[:, None, 1] > boxes[None, :, 1] - pad[None, :, 0])
                & (mid[:, None, 1] < boxes[None, :, 3] + pad[None, :, 0])
            )
            ok &= ~inside.any(axis=1)
        if ok.sum() < 10:
            continue
        # pixel centres are at half-integer coordinates (origin at the top-left pixel corner)
        uv, d = (uv[ok] - 0.5).astype(np.float32), d[ok]
        sx = cv2.remap(gx, uv[..., 0], uv[..., 1], cv2.INTER_LINEAR)
        sy = cv2.remap(gy, uv[..., 0], uv[..., 1], cv2.INTER_LINEAR)
        g = sx * d[..., 0] + sy * d[..., 1]  # (n, k): derivative toward the table's inside
        # how far the nose moves across itself per metre of rise [px / m]
        shift = np.abs(np.sum((uv[:, -1] - uv[:, 0]) * d[:, len(rises) // 2], axis=-1)) / (rises[-1] - rises[0])
        sens.append(float(np.median(shift)))
        prof = np.median(g, axis=0)
        # noise of a median of n samples, from the spread of the samples
        mad = float(np.median(np.abs(g - np.median(g, axis=0)))) * 1.4826
        profiles.append(prof)
        noise.append(max(mad, 1e-3) * 1.2533 / math.sqrt(len(g)) + 0.02 * float(np.max(np.abs(prof))))
    if not profiles:
        return np.zeros((0, len(rises))), np.zeros(0), np.zeros(0)
    return np.array(profiles), np.array(noise), np.array(sens)


def estimate_rail_height(
    image: np.ndarray,
    fit: TableFit,
    ball_boxes: np.ndarray | None = None,
    rise_range: tuple[float, float] = RISE_RANGE,
    min_score: float | None = None,
) -> RailHeight:
    """Estimate the diamond-plane height above the cloth from the cushion nose edges.

    Args:
        image: the photo, RGB uint8 (H, W, 3) or gray.
        fit: the table fit from the diamonds (any assumed height).
        ball_boxes: ball boxes [px] (n, 4) to mask out.
        rise_range: searched rise of the diamonds above the cushion nose [m].
        min_score: least combined peak strength (noise units) to accept the estimate.

    Returns:
        A :class:`RailHeight`; ``measured`` is ``False`` (the fit's height kept) when fewer than two noses
        are in view across the line of sight, the edges are too weak or the peak lies at the end of the
        search range.
    """
    spec = fit.spec

    def fallback(reason: str, score: float = 0.0, n: int = 0) -> RailHeight:
        return RailHeight(fit.diamond_z, fit.diamond_z - spec.cushion_height, False, score, n, reason)

    rises = np.arange(rise_range[0], rise_range[1] + RISE_STEP / 2, RISE_STEP)
    profiles, noise, sens = edge_profiles(image, fit, rises, ball_boxes)
    use = sens >= MIN_SENSITIVITY
    profiles, noise, sens = profiles[use], noise[use], sens[use]
    if len(profiles) < 2:
        return fallback("fewer than two cushion noses in view across the line of sight", 0.0, len(profiles))
    # every segment counts alike: weighting by sensitivity lets one far rail (whose cushion top, face
    # and cap edges crowd together) decide alone, and a weighted median of per-segment peaks follows
    # single segments onto other edges; both were worse on the renders
    strength = np.abs(profiles) / noise[:, None]
    total = strength.sum(axis=0)
    k = int(np.argmax(total))
    base = float(np.median(total))
    score = float(total[k] - base) / math.sqrt(len(profiles))
    if not np.isfinite(score):
        return fallback("cushion nose edges could not be measured", 0.0, len(profiles))
    if k in (0, len(rises) - 1):
        return fallback("cushion nose edge at the end of the searched heights", score, len(profiles))
    if score < (MIN_SCORE if min_score is None else min_score):
        return fallback(f"cushion nose edges too weak (score {score:.1f})", score, len(profiles))
    rise = _peak(rises, total, k)
    return RailHeight(spec.cushion_height + rise, rise, True, score, len(profiles))


def _peak(rises: np.ndarray, values: np.ndarray, k: int) -> float:
    """Sub-step position of the maximum ``values[k]`` (parabola through its neighbours)."""
    y0, y1, y2 = values[k - 1], values[k], values[k + 1]
    den = y0 - 2 * y1 + y2
    offset = 0.5 * (y0 - y2) / den if den < 0 else 0.0
    return float(rises[k] + np.clip(offset, -0.5, 0.5) * (rises[1] - rises[0]))


def refine_fit_height(
    image: np.ndarray, fit: TableFit, ball_boxes: np.ndarray | None = None
) -> tuple[TableFit, RailHeight]:
    """The fit with its diamond-plane height measured from the image (unchanged when it cannot be).

    Returns:
        ``(fit, estimate)``.
    """
    est = estimate_rail_height(image, fit, ball_boxes)
    return (fit.with_diamond_z(est.diamond_z) if est.measured else fit), est

"""Image-space effects: occluders in front of the table (players, arms, cue sticks, chalk), broadcast
overlays, and the camera pipeline (tone curve, colour cast, defocus, motion blur, resampling, sensor noise,
sharpening, JPEG).

Occluders and overlays also return a boolean mask of the pixels they cover, so labels can flag objects
hidden behind them.
"""

from __future__ import annotations

import math
import string

import cv2
import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.synth.palette import jitter
from pix2pockets.synth.textures import FONTS, put_text

SKIN_TONES = ((0.87, 0.67, 0.53), (0.72, 0.5, 0.36), (0.45, 0.3, 0.2), (0.95, 0.8, 0.68), (0.6, 0.4, 0.28))


def _col(c: np.ndarray | tuple) -> tuple[float, float, float]:
    return tuple(float(x) for x in c)  # type: ignore[return-value]


def _edge_point(rng: np.random.Generator, w: int, h: int) -> tuple[np.ndarray, np.ndarray]:
    """A point on a random image border and the inward unit normal there."""
    side = int(rng.integers(4))
    if side == 0:
        return np.array([rng.uniform(0, w), h + 5.0]), np.array([0.0, -1.0])
    if side == 1:
        return np.array([rng.uniform(0, w), -5.0]), np.array([0.0, 1.0])
    if side == 2:
        return np.array([-5.0, rng.uniform(0, h)]), np.array([1.0, 0.0])
    return np.array([w + 5.0, rng.uniform(0, h)]), np.array([-1.0, 0.0])


def _shaded_fill(img: np.ndarray, mask_u8: np.ndarray, colour: np.ndarray, rng: np.random.Generator) -> None:
    """Paint ``colour`` with a soft brightness gradient and fabric noise where ``mask_u8`` is set."""
    h, w = mask_u8.shape
    ys, xs = np.nonzero(mask_u8)
    if len(xs) == 0:
        return
    a = rng.uniform(0, 2 * math.pi)
    proj = (xs * math.cos(a) + ys * math.sin(a)) / max(w, h)
    shade = 0.7 + 0.5 * (proj - proj.min()) / (np.ptp(proj) + 1e-6)
    noise = 1.0 + 0.05 * rng.normal(size=len(xs))
    img[ys, xs] = np.clip(colour[None, :] * (shade * noise)[:, None], 0, 1)


def draw_arm(img: np.ndarray, mask: np.ndarray, rng: np.random.Generator, towards: np.ndarray | None) -> None:
    """A forearm (sleeve and hand) reaching in from a border toward ``towards`` (pixels)."""
    h, w = mask.shape
    p, _n = _edge_point(rng, w, h)
    if towards is None or not np.all(np.isfinite(towards)):
        towards = np.array([rng.uniform(0.2, 0.8) * w, rng.uniform(0.2, 0.8) * h])
    d = towards - p
    length = np.linalg.norm(d) * rng.uniform(0.5, 0.95)
    d = d / (np.linalg.norm(d) + 1e-9)
    width = rng.uniform(0.04, 0.1) * h
    end = p + d * length
    perp = np.array([-d[1], d[0]])
    m = np.zeros((h, w), np.uint8)
    poly = np.array([p + perp * width, p - perp * width, end - perp * width * 0.6, end + perp * width * 0.6])
    cv2.fillConvexPoly(m, poly.astype(np.int32), 255)
    sleeve = m.copy()
    if rng.random() < 0.6:  # bare forearm from mid-way
        cut = p + d * length * rng.uniform(0.3, 0.7)
        poly2 = np.array([cut + perp * width * 1.2, cut - perp * width * 1.2, end - perp * width, end + perp * width])
        bare = np.zeros_like(m)
        cv2.fillConvexPoly(bare, poly2.astype(np.int32), 255)
        sleeve &= ~bare
    skin = jitter(rng, SKIN_TONES[int(rng.integers(len(SKIN_TONES)))], 0.08)
    _shaded_fill(img, m, skin, rng)
    _shaded_fill(img, sleeve, rng.uniform(0.02, 0.8, 3), rng)
    hand = np.zeros_like(m)
    cv2.ellipse(hand, (int(end[0]), int(end[1])), (int(width * 1.1), int(width * 0.8)),
                math.degrees(math.atan2(d[1], d[0])), 0, 360, 255, -1)  # fmt: skip
    _shaded_fill(img, hand, skin, rng)
    mask |= (m > 0) | (hand > 0)


def draw_chalk(
    img: np.ndarray, mask: np.ndarray, rng: np.random.Generator, cam: PinholeCamera, xyz: np.ndarray
) -> None:
    """A chalk cube (about 2 cm) standing at ``xyz`` [m]."""
    s = 0.011
    corners = np.array([[dx, dy, dz] for dx in (-s, s) for dy in (-s, s) for dz in (0.0, 2 * s)]) + xyz
    uv = cam.project(corners)
    if not np.all(np.isfinite(uv)) or np.abs(uv).max() > 1e5:
        return
    hull = cv2.convexHull(np.round(uv).astype(np.int32))
    m = np.zeros(mask.shape, np.uint8)
    cv2.fillConvexPoly(m, hull, 255)
    col = jitter(rng, (0.1, 0.35, 0.75), 0.15)
    _shaded_fill(img, m, col, rng)
    mask |= m > 0


def _random_name(rng: np.random.Generator) -> str:
    letters = string.ascii_uppercase
    return "".join(letters[int(rng.integers(26))] for _ in range(int(rng.integers(4, 10))))


def draw_scoreboard(img: np.ndarray, mask: np.ndarray, rng: np.random.Generator) -> None:
    """A broadcast score bar (names, scores, race-to) at the top or bottom, opaque or translucent."""
    h, w = mask.shape
    bh = int(h * rng.uniform(0.05, 0.09))
    bw = int(w * rng.uniform(0.35, 0.75))
    x0 = int(rng.uniform(0.02, 0.98) * (w - bw))
    y0 = int(h * rng.uniform(0.02, 0.06)) if rng.random() < 0.4 else h - bh - int(h * rng.uniform(0.02, 0.08))
    alpha = rng.uniform(0.75, 1.0)
    bg = rng.uniform(0.0, 0.35, 3)
    accent = rng.uniform(0.2, 1.0, 3)
    panel = img[y0 : y0 + bh, x0 : x0 + bw]
    panel[:] = panel * (1 - alpha) + bg * alpha
    cv2.rectangle(img, (x0, y0), (x0 + bw // 12, y0 + bh), _col(accent), -1)
    font = FONTS[int(rng.integers(len(FONTS)))]
    scale = bh / 45.0
    put_text(img, f"{_random_name(rng)}  {int(rng.integers(0, 10))}", (x0 + bw // 10, y0 + int(bh * 0.7)),
             font, scale, (0.95, 0.95, 0.95), max(1, int(scale * 2)))  # fmt: skip
    put_text(img, f"{int(rng.integers(0, 10))}  {_random_name(rng)}", (x0 + bw // 2 + bw // 12, y0 + int(bh * 0.7)),
             font, scale, (0.95, 0.95, 0.95), max(1, int(scale * 2)))  # fmt: skip
    mask[y0 : y0 + bh, x0 : x0 + bw] |= alpha > 0.5


def draw_logo(img: np.ndarray, mask: np.ndarray, rng: np.random.Generator) -> None:
    """A small channel logo / watermark in a corner."""
    h, w = mask.shape
    text = _random_name(rng)[:5]
    scale = h / 600 * rng.uniform(0.6, 1.2)
    (tw, th), _ = cv2.getTextSize(text, cv2.FONT_HERSHEY_DUPLEX, scale, 2)
    x = 10 if rng.random() < 0.5 else w - tw - 10
    y = th + 10 if rng.random() < 0.5 else h - 10
    alpha = rng.uniform(0.4, 0.9)
    layer = img.copy()
    put_text(layer, text, (x, y), cv2.FONT_HERSHEY_DUPLEX, scale, (1.0, 1.0, 1.0), 2)
    img[:] = img * (1 - alpha) + layer * alpha
    mask[max(0, y - th) : y + 4, max(0, x) : x + tw] |= alpha > 0.5


def channel_max(img: np.ndarray) -> np.ndarray:
    """Largest of the three channels per pixel (H, W); elementwise, far faster than ``max(axis=2)``."""
    return np.maximum(np.maximum(img[..., 0], img[..., 1]), img[..., 2])


def channel_mean(img: np.ndarray) -> np.ndarray:
    """Mean of the three channels per pixel (H, W); elementwise, far faster than ``mean(axis=2)``."""
    return (img[..., 0] + img[..., 1] + img[..., 2]) / 3


def tone_map(rgb: np.ndarray, exposure: float, contrast: float, saturation: float) -> np.ndarray:
    """Exposure, a soft highlight shoulder and saturation/contrast changes; returns [0, 1] float32."""
    x = np.maximum(rgb * exposure, 0.0)
    x = x / (1.0 + 0.3 * x) * 1.3
    x = np.clip(x, 0.0, 1.0) ** (1.0 / contrast)
    grey = channel_mean(x)[..., None]
    x = grey + (x - grey) * saturation
    return np.clip(x, 0.0, 1.0).astype(np.float32)


def camera_pipeline(img: np.ndarray, rng: np.random.Generator, strength: float = 1.0) -> tuple[np.ndarray, dict]:
    """Optics and sensor effects on a float RGB image in [0, 1]; returns uint8 RGB and what was applied.

    ``strength`` scales how often the heavier effects fire (multi-view sets use a lighter pipeline).
    """
    h, w = img.shape[:2]
    info: dict = {}
    x = img.astype(np.float32)
    if rng.random() < 0.6 * strength:  # white balance error: mostly warm (tungsten) or cool, plus a tint
        temp = rng.normal(0.05, 0.09)
        cast = np.array([1.0 + temp, 1.0, 1.0 - 1.3 * temp]) * (1.0 + rng.normal(0, 0.03, 3))
        cast = np.clip(cast, 0.7, 1.3).astype(np.float32)
        x = x * cast
        info["colour_cast"] = [round(float(c), 3) for c in cast]
    if rng.random() < 0.4 * strength:  # lens vignetting
        yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
        r2 = ((xx - w / 2) ** 2 + (yy - h / 2) ** 2) / (w * w / 4 + h * h / 4)
        k = rng.uniform(0.15, 0.5)
        x = x * (1 - k * r2)[..., None]
        info["vignette"] = round(float(k), 3)
    if rng.random() < 0.35 * strength:  # bloom / glare around highlights and lamps
        bright = np.clip(channel_max(x)[..., None] - 0.85, 0.0, None) * x
        glow = cv2.GaussianBlur(bright, (0, 0), rng.uniform(2.0, 8.0))
        if glow.ndim == 2:
            glow = glow[..., None]
        amount = rng.uniform(1.0, 4.0)
        x = x + amount * glow
        info["bloom"] = round(float(amount), 2)
    sigma = rng.uniform(0.35, 0.7)  # lens softness
    if rng.random() < 0.3 * strength:
        sigma = rng.uniform(0.8, 2.2)
        info["defocus_sigma"] = round(float(sigma), 2)
    x = cv2.GaussianBlur(x, (0, 0), sigma)
    if rng.random() < 0.15 * strength:
        n = int(rng.integers(3, 13))
        kernel = np.zeros((n, n), np.float32)
        a = rng.uniform(0, math.pi)
        c, s = math.cos(a), math.sin(a)
        for t in np.linspace(-(n - 1) / 2, (n - 1) / 2, 3 * n):
            kernel[round(n / 2 - 0.5 + t * s), round(n / 2 - 0.5 + t * c)] = 1.0
        x = cv2.filter2D(x, -1, kernel / kernel.sum())
        info["motion_blur_px"] = n
    if rng.random() < 0.25 * strength:  # low-resolution source upscaled
        f = rng.uniform(0.35, 0.7)
        small = cv2.resize(x, (max(8, int(w * f)), max(8, int(h * f))), interpolation=cv2.INTER_AREA)
        x = cv2.resize(small, (w, h), interpolation=cv2.INTER_LINEAR)
        info["resample"] = round(float(f), 2)
    if rng.random() < 0.3 * strength:  # phone sharpening halos
        blur = cv2.GaussianBlur(x, (0, 0), 1.5)
        amt = rng.uniform(0.3, 1.0)
        x = x + amt * (x - blur)
        info["sharpen"] = round(float(amt), 2)
    noise_sigma = rng.uniform(0.003, 0.03) * (1.0 if rng.random() < 0.8 else 2.0)
    x = x + rng.normal(0.0, noise_sigma, (h, w, 1)).astype(np.float32) * np.sqrt(np.clip(x, 0.02, 1.0))
    if rng.random() < 0.3:
        x = x + rng.normal(0.0, noise_sigma * 0.5, (h, w, 3)).astype(np.float32)
    info["noise_sigma"] = round(float(noise_sigma), 4)
    out = np.clip(x * 255.0 + 0.5, 0, 255).astype(np.uint8)
    if rng.random() < 0.6 * strength:
        q = int(rng.integers(30, 92))
        ok, buf = cv2.imencode(".jpg", cv2.cvtColor(out, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, q])
        if ok:
            out = cv2.cvtColor(cv2.imdecode(buf, cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)
            info["jpeg_quality"] = q
    return out, info

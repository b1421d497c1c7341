"""Procedural textures: noise tiles, wood grain, floors, room walls (crowds, ad boards), ball digits.

All textures are float32 arrays; colour textures are RGB in [0, 1]. Everything is drawn from an explicit
``np.random.Generator`` with OpenCV's built-in Hershey fonts, so nothing is read from disk.
"""

from __future__ import annotations

import functools
import itertools

import cv2
import numpy as np

from pix2pockets.synth.palette import jitter

FONTS = (
    cv2.FONT_HERSHEY_SIMPLEX,
    cv2.FONT_HERSHEY_DUPLEX,
    cv2.FONT_HERSHEY_TRIPLEX,
    cv2.FONT_HERSHEY_COMPLEX,
)


def put_text(
    img: np.ndarray,
    text: str,
    org: tuple[int, int],
    font: int,
    scale: float,
    colour: tuple[float, float, float],
    thickness: int = 1,
) -> np.ndarray:
    """Draw anti-aliased text on a float RGB image in place (OpenCV only draws text on 8-bit images).

    Returns the text coverage mask (H, W) float32 in [0, 1].
    """
    layer = np.zeros(img.shape[:2], np.uint8)
    cv2.putText(layer, text, org, font, scale, 255, thickness, cv2.LINE_AA)
    a = layer.astype(np.float32)[..., None] / 255.0
    img[:] = img * (1 - a) + np.asarray(colour, np.float32) * a
    return a[..., 0]


def value_noise(rng: np.random.Generator, size: int, octaves: tuple[int, ...] = (4, 8, 16, 32)) -> np.ndarray:
    """Tileable-ish fractal value noise in [-1, 1], shape (size, size) float32."""
    out = np.zeros((size, size), np.float32)
    amp, total = 1.0, 0.0
    for cells in octaves:
        grid = rng.normal(0.0, 1.0, (cells, cells)).astype(np.float32)
        grid = np.pad(grid, ((0, 1), (0, 1)), mode="wrap")
        up = cv2.resize(grid, (size + size // cells, size + size // cells), interpolation=cv2.INTER_CUBIC)
        out += amp * up[:size, :size]
        total += amp
        amp *= 0.55
    out /= total
    return np.clip(out / (3 * out.std() + 1e-6), -1.0, 1.0)


def wood_grain(rng: np.random.Generator, size: int = 256) -> np.ndarray:
    """Wood grain brightness factor around 1, shape (size, size); rows run along the grain (axis 1)."""
    y = np.arange(size, dtype=np.float32)[:, None]
    x = np.arange(size, dtype=np.float32)[None, :]
    warp = value_noise(rng, size, (2, 4, 8)) * 6.0
    freq = rng.uniform(0.15, 0.4)
    rings = np.sin((y + warp + 0.02 * x) * freq) * 0.5 + 0.5
    fine = value_noise(rng, size, (32, 64))
    return (0.82 + 0.22 * rings**3 + 0.05 * fine).astype(np.float32)


def floor_texture(rng: np.random.Generator, size: int = 256) -> np.ndarray:
    """A floor tile (RGB): wooden planks, carpet, tiles or concrete; covers about 2 m."""
    kind = rng.choice(["planks", "carpet", "tiles", "concrete", "patterned"], p=[0.4, 0.27, 0.13, 0.14, 0.06])
    noise = value_noise(rng, size)
    if kind == "planks":
        base = jitter(rng, (0.45, 0.30, 0.17), 0.25)
        img = np.zeros((size, size, 3), np.float32)
        n_planks = int(rng.integers(8, 14))
        edges = np.linspace(0, size, n_planks + 1).astype(int)
        grain = wood_grain(rng, size)
        for a, b in itertools.pairwise(edges):
            img[a:b] = base * rng.uniform(0.75, 1.15)
            img[a : a + 1] *= 0.4
        img *= grain[..., None]
    elif kind == "carpet":
        base = jitter(rng, (0.30, 0.12, 0.12) if rng.random() < 0.5 else (0.15, 0.18, 0.28), 0.4)
        fine = rng.normal(0.0, 1.0, (size, size)).astype(np.float32)
        img = base * (1 + 0.12 * noise + 0.08 * fine)[..., None]
        if rng.random() < 0.5:  # pub carpet pattern
            yy, xx = np.mgrid[0:size, 0:size]
            pat = (np.sin(xx * 0.3) * np.sin(yy * 0.3) > 0.3).astype(np.float32)
            img = img * (1 - 0.3 * pat[..., None]) + 0.3 * pat[..., None] * jitter(rng, (0.7, 0.5, 0.2), 0.3)
    elif kind == "tiles":
        base = jitter(rng, (0.7, 0.68, 0.62), 0.3)
        img = np.ones((size, size, 3), np.float32) * base * (1 + 0.05 * noise)[..., None]
        n = int(rng.integers(3, 7))
        step = size // n
        img[::step] *= 0.5
        img[:, ::step] *= 0.5
    elif kind == "concrete":
        base = jitter(rng, (0.45, 0.45, 0.45), 0.2)
        img = base * (1 + 0.15 * noise)[..., None] * np.ones((size, size, 3), np.float32)
    else:
        a, b = jitter(rng, (0.5, 0.2, 0.1), 0.4), jitter(rng, (0.15, 0.1, 0.08), 0.4)
        yy, xx = np.mgrid[0:size, 0:size]
        n = int(rng.integers(4, 9))
        pat = ((xx * n // size + yy * n // size) % 2).astype(np.float32)[..., None]
        img = (a * pat + b * (1 - pat)) * (1 + 0.1 * noise)[..., None]
    return np.clip(img, 0, 1).astype(np.float32)


def _draw_crowd(rng: np.random.Generator, img: np.ndarray, y0: int, y1: int) -> None:
    """Rows of head-and-shoulder blobs between rows ``y0`` and ``y1`` (in place)."""
    _h, w = img.shape[:2]
    row_h = max(6, int(rng.uniform(0.08, 0.16) * (y1 - y0)) + 4)
    skins = [(0.85, 0.65, 0.5), (0.65, 0.45, 0.32), (0.4, 0.27, 0.18), (0.95, 0.78, 0.66)]
    for yc in range(y1 - row_h // 2, y0, -int(row_h * 0.8)):
        x = int(rng.integers(0, row_h))
        while x < w:
            shirt = tuple(float(c) for c in rng.uniform(0.05, 0.8, 3))
            skin = tuple(float(c) for c in jitter(rng, skins[int(rng.integers(len(skins)))], 0.1))
            sw = int(row_h * rng.uniform(0.35, 0.55))
            cv2.ellipse(img, (x, yc + row_h // 2), (sw, row_h // 2), 0, 180, 360, shirt, -1)
            cv2.circle(img, (x, yc), max(2, int(row_h * 0.22)), skin, -1)
            if rng.random() < 0.4:
                hair = tuple(float(c) for c in rng.uniform(0.02, 0.3, 3))
                cv2.ellipse(img, (x, yc - row_h // 10), (max(2, int(row_h * 0.22)), row_h // 7), 0, 180, 360, hair, -1)
            x += int(sw * rng.uniform(1.6, 2.6))
    img[y0:y1] *= rng.uniform(0.3, 0.8)


def _draw_ad_boards(rng: np.random.Generator, img: np.ndarray, y0: int, y1: int) -> None:
    """A band of advertising boards with logos and words between rows ``y0`` and ``y1`` (in place)."""
    w = img.shape[1]
    x = 0
    words = ["PREDATOR", "WORLD 8-BALL", "CUE SPORTS", "POOL", "DIAMOND", "ARAMITH", "SIMONIS", "LIVE", "OPEN"]
    while x < w:
        bw = int(rng.uniform(0.1, 0.3) * w)
        bg = tuple(float(c) for c in rng.uniform(0.0, 1.0, 3) ** 1.5)
        fg = tuple(float(c) for c in (1.0 - np.array(bg)) * rng.uniform(0.7, 1.0))
        cv2.rectangle(img, (x, y0), (x + bw, y1), bg, -1)
        text = str(words[int(rng.integers(len(words)))])
        scale = (y1 - y0) / 40.0 * rng.uniform(0.6, 1.1)
        put_text(
            img,
            text,
            (x + int(bw * 0.08), y1 - int((y1 - y0) * 0.3)),
            FONTS[int(rng.integers(len(FONTS)))],
            max(scale, 0.3),
            fg,
            max(1, int(scale * 2)),
        )
        cv2.line(img, (x + bw, y0), (x + bw, y1), (0.0, 0.0, 0.0), 1)
        x += bw


def _wall_item(rng: np.random.Generator, img: np.ndarray, big: np.ndarray) -> None:
    """One piece of room clutter painted on the wall strip (in place)."""
    height, width = img.shape[:2]
    bw = int(rng.uniform(0.02, 0.12) * width)
    bh = int(rng.uniform(0.15, 0.6) * height)
    x0 = int(rng.integers(0, width - bw))
    y0 = int(rng.integers(int(0.1 * height), max(int(0.1 * height) + 1, height - bh)))
    kind = rng.random()
    if kind < 0.18:  # window: bright, with a frame and mullions
        col = tuple(float(c) for c in jitter(rng, (0.9, 0.95, 1.0), 0.1))
        cv2.rectangle(img, (x0, y0), (x0 + bw, y0 + bh), col, -1)
        frame = (0.9, 0.9, 0.9) if rng.random() < 0.6 else (0.2, 0.12, 0.06)
        cv2.rectangle(img, (x0, y0), (x0 + bw, y0 + bh), frame, 2)
        cv2.line(img, (x0 + bw // 2, y0), (x0 + bw // 2, y0 + bh), frame, 1)
    elif kind < 0.4:  # framed picture / poster with a noisy "image" inside
        h2 = max(4, bh // 2)
        pic = cv2.resize(rng.uniform(0, 1, (4, 4, 3)).astype(np.float32), (bw, h2), interpolation=cv2.INTER_CUBIC)
        img[y0 : y0 + h2, x0 : x0 + bw] = np.clip(pic, 0, 1)[: img.shape[0] - y0, : img.shape[1] - x0]
        cv2.rectangle(img, (x0, y0), (x0 + bw, y0 + h2), tuple(float(c) for c in rng.uniform(0, 0.6, 3)), 2)
    elif kind < 0.55:  # door / cabinet
        col = tuple(float(c) for c in jitter(rng, (0.3, 0.18, 0.1), 0.4))
        cv2.rectangle(img, (x0, height - bh), (x0 + bw, height - 1), col, -1)
        cv2.circle(img, (x0 + bw - 4, height - bh // 2), 2, (0.8, 0.7, 0.3), -1)
    elif kind < 0.68:  # shelf with bottles
        shelf_y = y0 + bh // 2
        cv2.rectangle(img, (x0, shelf_y), (x0 + bw, shelf_y + 3), (0.25, 0.15, 0.08), -1)
        x = x0 + 2
        while x < x0 + bw - 3:
            bh2 = int(rng.uniform(6, 14))
            col = tuple(float(c) for c in rng.uniform(0.05, 0.8, 3))
            cv2.rectangle(img, (x, shelf_y - bh2), (x + 3, shelf_y), col, -1)
            x += int(rng.uniform(4, 8))
    elif kind < 0.76:  # dartboard
        r = max(4, bw // 4)
        c = (x0 + bw // 2, y0 + r)
        for k, col in enumerate([(0.05, 0.05, 0.05), (0.8, 0.1, 0.1), (0.9, 0.85, 0.7), (0.1, 0.5, 0.2)]):
            cv2.circle(img, c, max(1, r - k * r // 4), col, -1)
    elif kind < 0.86:  # neon sign / TV
        if rng.random() < 0.5:
            col = tuple(float(c) for c in np.clip(rng.uniform(0.3, 1.0, 3) + 0.3, 0, 1))
            word = ["BAR", "POOL", "OPEN", "BEER", "8 BALL", "CUE"][int(rng.integers(6))]
            put_text(img, word, (x0, y0 + 20), FONTS[int(rng.integers(len(FONTS)))], 0.8, col, 2)
        else:
            cv2.rectangle(img, (x0, y0), (x0 + bw, y0 + bh // 2), (0.02, 0.02, 0.02), -1)
            inner = cv2.resize(rng.uniform(0.2, 1, (3, 3, 3)).astype(np.float32), (max(1, bw - 6), max(1, bh // 2 - 6)))
            img[y0 + 3 : y0 + 3 + inner.shape[0], x0 + 3 : x0 + 3 + inner.shape[1]] = inner[
                : img.shape[0] - y0 - 3, : img.shape[1] - x0 - 3
            ]
    else:  # dark furniture / person-like silhouette
        col = tuple(float(c) for c in rng.uniform(0.02, 0.25, 3))
        cv2.ellipse(img, (x0 + bw // 2, height - bh // 2), (bw // 2, bh // 2), 0, 0, 360, col, -1)


def wall_texture(rng: np.random.Generator, style: str, height: int = 192, width: int = 1536) -> np.ndarray:
    """The four room walls unrolled into one strip (RGB), rows from ceiling (0) to floor (height - 1).

    Args:
        style: ``"arena"`` (dark hall, crowd, ad boards), ``"pub"`` (warm walls, frames, shelves) or
            ``"home"`` (plain light walls, windows, doors, furniture).
    """
    noise = value_noise(rng, 256, (2, 4, 8))
    big = cv2.resize(noise, (width, height))[..., None]
    if style == "arena":
        base = jitter(rng, (0.08, 0.08, 0.10), 0.5)
        img = np.ones((height, width, 3), np.float32) * base * (1 + 0.4 * big)
        _draw_crowd(rng, img, int(height * 0.15), int(height * 0.75))
        _draw_ad_boards(rng, img, int(height * 0.78), int(height * 0.95))
    else:
        light = style == "home"
        base = jitter(rng, (0.80, 0.78, 0.72) if light else (0.45, 0.25, 0.15), 0.3)
        img = np.ones((height, width, 3), np.float32) * base * (1 + 0.15 * big)
        if rng.random() < 0.5:  # wainscot / lower panelling
            y = int(height * rng.uniform(0.55, 0.75))
            img[y:] = jitter(rng, (0.35, 0.2, 0.1), 0.4) * (1 + 0.1 * big[y:])
        for _ in range(int(rng.integers(6, 20))):
            _wall_item(rng, img, big)
        if style == "pub" and rng.random() < 0.5:
            _draw_ad_boards(rng, img, int(height * 0.2), int(height * 0.32))
    img[-3:] *= 0.4  # skirting shadow
    # fine detail: plaster/fabric grain and small clutter at texel scale
    detail = cv2.GaussianBlur(rng.normal(0.0, 1.0, (height, width)).astype(np.float32), (0, 0), 0.7)
    img *= (1.0 + rng.uniform(0.03, 0.1) * detail)[..., None]
    return np.clip(img, 0, 1).astype(np.float32)


@functools.lru_cache(maxsize=1)
def digit_bitmaps(size: int = 32) -> np.ndarray:
    """Ink masks of the numbers 0-15 as they sit in a ball's number circle, shape (16, size, size) in [0, 1].

    Index ``n`` holds the text ``str(n)`` (index 0 is blank). Ink is 1, paper 0; the circle has radius
    ``size / 2``.
    """
    out = np.zeros((16, size, size), np.float32)
    for n in range(1, 16):
        big = np.zeros((size * 4, size * 4), np.uint8)
        text = str(n)
        scale = 3.2 if n < 10 else 2.3
        thick = 6 if n < 10 else 5
        (tw, th), _ = cv2.getTextSize(text, cv2.FONT_HERSHEY_DUPLEX, scale, thick)
        org = ((size * 4 - tw) // 2, (size * 4 + th) // 2)
        cv2.putText(big, text, org, cv2.FONT_HERSHEY_DUPLEX, scale, 255, thick, cv2.LINE_AA)
        if n in (6, 9):  # underline marks 6 and 9 as on real balls
            cv2.line(big, (org[0], org[1] + 10), (org[0] + tw, org[1] + 10), 255, 5)
        out[n] = cv2.resize(big, (size, size), interpolation=cv2.INTER_AREA) / 255.0
    return out


TEXTURE_VARIANTS = 32
"""Distinct textures of each kind; scenes pick one by index and tint it (cached: building walls is slow)."""

_STYLE_CODE = {"arena": 1, "pub": 2, "home": 3}


@functools.cache
def cached_wall(style: str, key: int) -> np.ndarray:
    """Wall strip ``key`` of a room style as uint8 RGB (built once from its own seed)."""
    rng = np.random.default_rng([0x3A11, _STYLE_CODE[style], key])
    return np.round(wall_texture(rng, style, 160, 1280) * 255).astype(np.uint8)


@functools.cache
def cached_floor(key: int) -> np.ndarray:
    """Floor tile ``key`` as uint8 RGB."""
    return np.round(floor_texture(np.random.default_rng([0xF100, key])) * 255).astype(np.uint8)


@functools.cache
def cached_noise(key: int) -> np.ndarray:
    """Value-noise tile ``key`` (float32, [-1, 1])."""
    return value_noise(np.random.default_rng([0x2015E, key]), 256)


@functools.cache
def cached_grain(key: int) -> np.ndarray:
    """Wood-grain tile ``key`` (float32 around 1)."""
    return wood_grain(np.random.default_rng([0x6A1, key]), 256)

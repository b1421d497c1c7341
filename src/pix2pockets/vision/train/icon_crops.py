"""Flat ball icons, as broadcast graphics draw them, for "no ball" training crops (numpy and OpenCV only).

TV pool graphics show the balls left or pocketed as a row of small flat discs beside the score bar. A
detector trained on renders reads them as balls; these crops teach the ball classifier that a flat disc
with no shading is not a ball on the table. An icon fills the crop as a labelled ball does (the crop is
1.5 diameters wide, ``vision.stages.crops``), with the icon kinds of a set: solid colours, stripes (a band on
white) and the cue ball, with or without a white number disc, outlined or not, sometimes greyed out
(pocketed) and sometimes touching its neighbours in the row. The 8 is left out of the middle of a crop: a
real 8-ball shows hardly any shading, so it too reads as a flat black disc with a white number circle, and
a classifier taught that such a disc is no ball dropped real eights.
"""

from __future__ import annotations

import cv2
import numpy as np

from pix2pockets.vision.stages.crops import CROP_CONTEXT, CROP_SIZE

ICON_COLOURS_RGB: tuple[tuple[int, int, int], ...] = (
    (250, 200, 30),  # 1 yellow
    (30, 60, 200),  # 2 blue
    (220, 30, 30),  # 3 red
    (110, 40, 160),  # 4 purple
    (250, 120, 20),  # 5 orange
    (20, 130, 60),  # 6 green
    (130, 30, 30),  # 7 maroon
)
"""Ball colours of the standard set as flat graphics paint them."""

ICON_NUMBERS: tuple[int, ...] = tuple(n for n in range(16) if n != 8)
"""Balls drawn as the icon in the middle of a crop (neighbours may be any ball)."""

SUPERSAMPLE = 4


def _panel(rng: np.random.Generator, side: int) -> np.ndarray:
    """The graphic's background (side, side, 3) uint8: a flat or graded dark or light panel."""
    base = rng.uniform(0, 90, 3) if rng.random() < 0.7 else rng.uniform(120, 240, 3)
    grade = rng.uniform(-25, 25, 3)
    t = np.linspace(0, 1, side)[:, None, None] if rng.random() < 0.5 else np.linspace(0, 1, side)[None, :, None]
    return np.clip(np.broadcast_to(base + grade * t, (side, side, 3)), 0, 255).astype(np.uint8)


def _draw_icon(img: np.ndarray, centre: tuple[int, int], radius: int, number: int, rng: np.random.Generator) -> None:
    """One flat ball icon (in place, supersampled pixels)."""
    white = tuple(float(v) for v in rng.uniform(225, 255, 3))
    if number == 0:
        body = white
    elif number == 8:
        body = tuple(float(v) for v in rng.uniform(0, 30, 3))
    else:
        colour = np.array(ICON_COLOURS_RGB[(number - 1) % 7]) + rng.normal(0, 12, 3)
        body = tuple(float(v) for v in np.clip(colour, 0, 255))
    cx, cy = centre
    if number > 8:  # a stripe: a white disc with a colour band across
        cv2.circle(img, centre, radius, white, -1)
        disc = np.zeros(img.shape[:2], np.uint8)
        cv2.circle(disc, centre, radius, 1, -1)
        half = int(radius * rng.uniform(0.45, 0.65))
        band = np.zeros_like(disc)
        if rng.random() < 0.85:
            band[max(cy - half, 0) : cy + half + 1, :] = 1
        else:
            band[:, max(cx - half, 0) : cx + half + 1] = 1
        img[(disc & band) > 0] = body
    else:
        cv2.circle(img, centre, radius, body, -1)
    if number != 0 and rng.random() < 0.8:  # the number on a white disc
        r_num = int(radius * rng.uniform(0.4, 0.55))
        cv2.circle(img, centre, r_num, white, -1)
        scale = r_num / 16.0
        text = str(number)
        (tw, th), _ = cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, scale, max(1, int(scale * 2)))
        cv2.putText(img, text, (cx - tw // 2, cy + th // 2), cv2.FONT_HERSHEY_SIMPLEX, scale, (10.0, 10.0, 10.0),
                    max(1, int(scale * 2)))  # fmt: skip
    if rng.random() < 0.4:  # an outline
        shade = float(rng.uniform(0, 80)) if rng.random() < 0.6 else float(rng.uniform(180, 255))
        cv2.circle(img, centre, radius, (shade, shade, shade), max(1, int(radius * rng.uniform(0.04, 0.12))))


def ball_icon_crops(n: int, rng: np.random.Generator, crop_size: int = CROP_SIZE) -> np.ndarray:
    """``n`` crops (n, S, S, 3) uint8 of flat ball icons, each centred and sized as a ball crop (1.5 diameters
    wide, with the same small jitter), some between touching neighbours, some greyed out."""
    big = crop_size * SUPERSAMPLE
    out = np.empty((n, crop_size, crop_size, 3), np.uint8)
    for i in range(n):
        img = _panel(rng, big)
        radius = int(big / CROP_CONTEXT / 2 * rng.uniform(0.9, 1.1))
        shift = rng.uniform(-0.06, 0.06, 2) * 2 * radius
        centre = (int(big / 2 + shift[0]), int(big / 2 + shift[1]))
        if rng.random() < 0.5:  # neighbours in the row, touching or a little apart
            step = int(2 * radius * rng.uniform(1.0, 1.3))
            for side in (-1, 1):
                _draw_icon(img, (centre[0] + side * step, centre[1]), radius, int(rng.integers(0, 16)), rng)
        _draw_icon(img, centre, radius, ICON_NUMBERS[int(rng.integers(len(ICON_NUMBERS)))], rng)
        if rng.random() < 0.25:  # a pocketed ball, drawn faded into the panel
            img = cv2.addWeighted(img, 0.4, _panel(rng, big), 0.6, 0.0)
        out[i] = cv2.resize(img, (crop_size, crop_size), interpolation=cv2.INTER_AREA)
    return out

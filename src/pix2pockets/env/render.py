"""Top-view drawings of the table with numpy (no window), and a lazily created pygame window.

:func:`draw_table` returns an ``(H, W, 3)`` uint8 image: rails, cloth, pockets, cushion and jaw lines,
balls (solid colours by number, stripes with a white band, the cue ball white, the 8 black) and the last
shot as a line from the cue ball's starting point.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from pix2pockets.geometry.raster import TableRaster
from pix2pockets.state import BallClass, Shot, TableLayout

CLOTH = (24, 110, 60)
RAIL = (92, 54, 30)
POCKET = (15, 15, 15)
CUSHION = (16, 80, 42)
SHOT_LINE = (250, 250, 250)
GHOST = (200, 200, 200)
BALL_COLOURS = {
    1: (240, 200, 20),
    2: (20, 60, 200),
    3: (210, 30, 30),
    4: (110, 40, 150),
    5: (245, 120, 20),
    6: (20, 130, 60),
    7: (120, 20, 30),
    8: (10, 10, 10),
}
CLASS_COLOURS = {
    BallClass.CUE: (245, 245, 240),
    BallClass.BLACK: (10, 10, 10),
    BallClass.SOLID: (240, 200, 20),
    BallClass.STRIPE: (210, 30, 30),
}


def _disc(img: np.ndarray, centre: np.ndarray, radius: float, colour: tuple[int, int, int]) -> None:
    h, w, _ = img.shape
    u0, v0 = centre
    lo_u, hi_u = max(int(u0 - radius - 1), 0), min(int(u0 + radius + 2), w)
    lo_v, hi_v = max(int(v0 - radius - 1), 0), min(int(v0 + radius + 2), h)
    if lo_u >= hi_u or lo_v >= hi_v:
        return
    vv, uu = np.mgrid[lo_v:hi_v, lo_u:hi_u]
    inside = (uu + 0.5 - u0) ** 2 + (vv + 0.5 - v0) ** 2 <= radius**2
    img[lo_v:hi_v, lo_u:hi_u][inside] = colour


def _band(img: np.ndarray, centre: np.ndarray, radius: float, colour: tuple[int, int, int]) -> None:
    """A stripe ball: white disc with a coloured horizontal band."""
    h, w, _ = img.shape
    u0, v0 = centre
    lo_u, hi_u = max(int(u0 - radius - 1), 0), min(int(u0 + radius + 2), w)
    lo_v, hi_v = max(int(v0 - radius - 1), 0), min(int(v0 + radius + 2), h)
    if lo_u >= hi_u or lo_v >= hi_v:
        return
    vv, uu = np.mgrid[lo_v:hi_v, lo_u:hi_u]
    inside = (uu + 0.5 - u0) ** 2 + (vv + 0.5 - v0) ** 2 <= radius**2
    band = inside & (np.abs(vv + 0.5 - v0) <= 0.55 * radius)
    img[lo_v:hi_v, lo_u:hi_u][inside] = (245, 245, 240)
    img[lo_v:hi_v, lo_u:hi_u][band] = colour


def _line(img: np.ndarray, a: np.ndarray, b: np.ndarray, colour: tuple[int, int, int], thickness: float = 1.5) -> None:
    n = max(int(np.hypot(*(b - a)) * 2), 2)
    for t in np.linspace(0.0, 1.0, n):
        _disc(img, a + t * (b - a), thickness, colour)


def draw_table(
    layout: TableLayout,
    raster: TableRaster,
    shot: Shot | None = None,
    shot_start: np.ndarray | None = None,
) -> np.ndarray:
    """Draw ``layout`` (and the last ``shot`` from ``shot_start`` [m]) into a new RGB image."""
    spec = layout.spec
    w, h = raster.window_px
    img = np.empty((h, w, 3), dtype=np.uint8)
    img[:] = RAIL
    top_left = raster.table_to_pixels(np.array([0.0, spec.width]))
    bottom_right = raster.table_to_pixels(np.array([spec.length, 0.0]))
    u0, v0 = np.floor(top_left).astype(int)
    u1, v1 = np.ceil(bottom_right).astype(int)
    img[max(v0, 0) : v1, max(u0, 0) : u1] = CLOTH
    scale = raster.length_to_pixels(1.0)
    for pocket in spec.pockets:
        _disc(img, raster.table_to_pixels(pocket.centre), pocket.capture_radius * scale, POCKET)
    for a, b in np.concatenate([spec.cushion_segments, spec.jaw_segments]):
        _line(img, raster.table_to_pixels(a), raster.table_to_pixels(b), CUSHION, 1.0)
    r_px = max(spec.ball_radius * scale, 2.0)
    if shot is not None and shot_start is not None:
        start = raster.table_to_pixels(shot_start)
        length = min(0.15 + 0.1 * shot.speed, 1.0)  # [m] longer line for a harder shot
        end = raster.table_to_pixels(shot_start + length * np.array([math.cos(shot.angle), math.sin(shot.angle)]))
        _line(img, start, end, SHOT_LINE, 1.2)
        _disc(img, start, r_px, GHOST)
    for ball, xy in zip(layout.balls, layout.positions, strict=True):
        centre = raster.table_to_pixels(xy)
        if ball.number is not None and ball.number > 8:
            _band(img, centre, r_px, BALL_COLOURS[ball.number - 8])
        elif ball.number is not None and ball.number > 0:
            _disc(img, centre, r_px, BALL_COLOURS[ball.number])
        else:
            if ball.ball_class is BallClass.STRIPE:
                _band(img, centre, r_px, CLASS_COLOURS[BallClass.STRIPE])
            else:
                _disc(img, centre, r_px, CLASS_COLOURS[ball.ball_class])
    return img


class HumanWindow:
    """A pygame window showing RGB frames; pygame is imported when the first frame is shown."""

    def __init__(self, title: str = "pix2pockets") -> None:
        self.title = title
        self._pygame: Any = None
        self._screen: Any = None
        self._clock: Any = None

    def show(self, frame: np.ndarray, fps: int) -> None:
        """Display ``frame`` (H, W, 3) and keep the window responsive."""
        if self._pygame is None:
            try:
                import pygame
            except ImportError as err:
                raise ImportError('render_mode="human" needs pygame: pip install "pix2pockets[render]"') from err
            pygame.init()
            pygame.display.init()
            pygame.display.set_caption(self.title)
            self._pygame = pygame
            self._screen = pygame.display.set_mode((frame.shape[1], frame.shape[0]))
            self._clock = pygame.time.Clock()
        pygame = self._pygame
        pygame.event.pump()
        surface = pygame.surfarray.make_surface(np.ascontiguousarray(frame.transpose(1, 0, 2)))
        self._screen.blit(surface, (0, 0))
        pygame.display.flip()
        self._clock.tick(fps)

    def close(self) -> None:
        """Close the window (if one was opened)."""
        if self._pygame is not None:
            self._pygame.display.quit()
            self._pygame.quit()
            self._pygame = None

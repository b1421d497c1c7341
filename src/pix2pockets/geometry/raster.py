"""Conversions between table metres and raster pixels (environment windows, diagrams).

Pixels exist only at the edges. A :class:`TableRaster` maps the table frame (metres, ``+y`` up) to an
image raster (pixels, origin at the top-left pixel corner, ``+v`` down) by a scale per axis and a margin
for the rails.

The seed paper's environment is a pymunk world in pixels. :class:`PaperEnvLayout` holds its layout (window,
border, cushions, pockets, ball radius) as its code computes it at a zoom; :func:`paper_table` is that layout
in SI units (the ``physics="paper"`` table) and :func:`paper_env_raster` maps any table onto the paper's
nominal 735 x 410 window (the ``paper_pixels`` observations and ``env_xy_px``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np

from pix2pockets.geometry.table import TableSpec


@dataclass(frozen=True, slots=True)
class TableRaster:
    """A raster showing the playing surface plus rails.

    Attributes:
        spec: the table.
        surface_px: (width, height) of the playing surface in pixels (long axis horizontal).
        margin_px: (left/right, top/bottom) margin for the rails in pixels.
    """

    spec: TableSpec
    surface_px: tuple[float, float]
    margin_px: tuple[float, float]

    def __post_init__(self) -> None:
        if min(self.surface_px) <= 0 or min(self.margin_px) < 0:
            raise ValueError(f"bad raster size: surface {self.surface_px}, margin {self.margin_px}")

    @property
    def window_px(self) -> tuple[int, int]:
        """(width, height) of the whole window in pixels."""
        return (
            round(self.surface_px[0] + 2 * self.margin_px[0]),
            round(self.surface_px[1] + 2 * self.margin_px[1]),
        )

    @property
    def scale(self) -> np.ndarray:
        """Pixels per metre along (x, y)."""
        return np.array([self.surface_px[0] / self.spec.length, self.surface_px[1] / self.spec.width])

    def table_to_pixels(self, xy: np.ndarray) -> np.ndarray:
        """Table points [m] (..., 2) -> raster pixels (u right, v down) (..., 2)."""
        xy = np.asarray(xy, dtype=float)
        u = self.margin_px[0] + xy[..., 0] * self.scale[0]
        v = self.margin_px[1] + (self.spec.width - xy[..., 1]) * self.scale[1]
        return np.stack([u, v], axis=-1)

    def pixels_to_table(self, uv: np.ndarray) -> np.ndarray:
        """Raster pixels (..., 2) -> table points [m] (..., 2); inverse of :meth:`table_to_pixels`."""
        uv = np.asarray(uv, dtype=float)
        x = (uv[..., 0] - self.margin_px[0]) / self.scale[0]
        y = self.spec.width - (uv[..., 1] - self.margin_px[1]) / self.scale[1]
        return np.stack([x, y], axis=-1)

    def length_to_pixels(self, metres: float) -> float:
        """A length [m] in pixels, using the mean of the two axis scales."""
        return float(metres * self.scale.mean())

    @classmethod
    def fit(cls, spec: TableSpec, width_px: int, margin_fraction: float = 0.06) -> TableRaster:
        """A raster ``width_px`` wide with the table's true aspect ratio and rails of ``margin_fraction``."""
        margin = width_px * margin_fraction
        surface_w = width_px - 2 * margin
        surface_h = surface_w * spec.width / spec.length
        return cls(spec, (surface_w, surface_h), (margin, margin))


@dataclass(frozen=True, slots=True)
class PaperEnvLayout:
    """The seed paper's environment layout in its own pixels (``u`` right, ``v`` down).

    The paper's config gives every size at zoom 1 (a 735 x 410 window: a 29.5 px border, 11 px cushions,
    7 px balls, 15 px pockets) and its code builds the world at ``ZOOM = 2`` with ``int(size * zoom)``.
    All pixel values below are at ``zoom`` and truncated the same way, so at zoom 2 they are the exact
    coordinates of the world its physics runs in: cushion faces at u = 81 / 1389 and v = 81 / 739, ball
    radius 14, pocket circles of radius 30.

    Attributes:
        zoom: the paper's ``ZOOM`` (its environment runs at 2).
    """

    zoom: int = 2

    def __post_init__(self) -> None:
        if self.zoom < 1:
            raise ValueError(f"PaperEnvLayout.zoom must be >= 1, got {self.zoom}")

    def _px(self, size_at_zoom1: float) -> int:
        return int(size_at_zoom1 * self.zoom)

    @property
    def window(self) -> tuple[int, int]:
        """(width, height) of the window [px]."""
        return self._px(735), self._px(410)

    @property
    def border(self) -> int:
        """Border (rail top) outside the cushions [px]."""
        return self._px(29.5)

    @property
    def cushion(self) -> int:
        """Cushion depth from the border to the cushion face [px]."""
        return self._px(11)

    @property
    def ball_radius(self) -> int:
        """Ball radius [px]."""
        return self._px(7)

    @property
    def pocket_radius(self) -> int:
        """Pocket circle radius [px]; a ball drops as soon as it overlaps one."""
        return self._px(15)

    @property
    def faces(self) -> tuple[int, int, int, int]:
        """Cushion faces ``(u_left, u_right, v_top, v_bottom)`` [px]: the playing surface."""
        w, h = self.window
        inset = self.border + self.cushion
        return inset, w - inset, inset, h - inset

    @property
    def centre_box(self) -> tuple[int, int, int, int]:
        """Where ball centres may lie, ``(u_lo, u_hi, v_lo, v_hi)`` [px] (the faces minus a ball radius)."""
        u0, u1, v0, v1 = self.faces
        r = self.ball_radius
        return u0 + r, u1 - r, v0 + r, v1 - r

    @property
    def pocket_centres(self) -> np.ndarray:
        """Pocket circle centres [px], shape (6, 2), in ``TableSpec.pockets`` order.

        Corners sit ``int(5.88 * zoom)`` px inside the border corners, the side pockets on the border line.
        """
        w, h = self.window
        b, off = self.border, self._px(5.88)
        lo_u, hi_u, lo_v, hi_v = b + off, w - b - off, b + off, h - b - off
        return np.array(
            [[lo_u, hi_v], [w / 2, h - b], [hi_u, hi_v], [hi_u, lo_v], [w / 2, b], [lo_u, lo_v]], dtype=float
        )

    @property
    def cushion_polygons(self) -> np.ndarray:
        """The six cushions as convex quadrilaterals [px], shape (6, 4, 2), in ``TableSpec.cushion_segments``
        order. Vertices: back corner, jaw point, jaw point, back corner (the face runs between the two jaw
        points; the jaw faces slant back to the border line)."""
        w, h = self.window
        b, c = self.border, self.cushion
        hole, corner = self._px(19), self._px(33)  # jaw end on the border / jaw point, from the corner
        mid_hole, mid_off = self._px(16.17), self._px(3.675)  # side pocket: jaw end from the middle, slant
        mid = w / 2
        top, bot = b + c, h - b - c  # cushion faces along the long rails
        left, right = b + c, w - b - c
        return np.array(
            [
                [[b + hole, h - b], [b + corner, bot], [mid - mid_hole - mid_off, bot], [mid - mid_hole, h - b]],
                [
                    [mid + mid_hole, h - b],
                    [mid + mid_hole + mid_off, bot],
                    [w - b - corner, bot],
                    [w - b - hole, h - b],
                ],
                [[w - b, h - b - hole], [right, h - b - corner], [right, b + corner], [w - b, b + hole]],
                [[w - b - hole, b], [w - b - corner, top], [mid + mid_hole + mid_off, top], [mid + mid_hole, b]],
                [[mid - mid_hole, b], [mid - mid_hole - mid_off, top], [b + corner, top], [b + hole, b]],
                [[b, b + hole], [left, b + corner], [left, h - b - corner], [b, h - b - hole]],
            ],
            dtype=float,
        )

    @property
    def target_points(self) -> np.ndarray:
        """The paper Oracle's aiming points [px], shape (6, 2), in ``TableSpec.pockets`` order: where the
        ball-centre lines meet at the corners, and on the ball-centre line in the middle of the long rails."""
        u0, u1, v0, v1 = self.centre_box
        mid = self.window[0] / 2
        return np.array([[u0, v1], [mid, v1], [u1, v1], [u1, v0], [mid, v0], [u0, v0]], dtype=float)

    @property
    def jaw_points(self) -> np.ndarray:
        """The two jaw points of each pocket [px], shape (6, 2, 2), in ``TableSpec.pockets`` order (the
        Oracle's pocket window runs between them)."""
        q = self.cushion_polygons
        return np.array(
            [[q[5, 2], q[0, 1]], [q[0, 2], q[1, 1]], [q[1, 2], q[2, 1]], [q[2, 2], q[3, 1]], [q[3, 2], q[4, 1]],
             [q[4, 2], q[5, 1]]]
        )  # fmt: skip

    @property
    def metres_per_px(self) -> float:
        """Scale that makes the cushion-face length a 9-foot table's playing length (100 in) [m/px]."""
        u0, u1, _, _ = self.faces
        return 100 * 0.0254 / (u1 - u0)

    def to_table(self, uv: np.ndarray) -> np.ndarray:
        """Paper pixels (..., 2) -> the table frame [m] of :func:`paper_table` (origin at the cushion faces'
        lower-left corner, ``+y`` up)."""
        uv = np.asarray(uv, dtype=float)
        u0, _, _, v1 = self.faces
        s = self.metres_per_px
        return np.stack([(uv[..., 0] - u0) * s, (v1 - uv[..., 1]) * s], axis=-1)

    def from_table(self, xy: np.ndarray) -> np.ndarray:
        """The table frame [m] -> paper pixels (..., 2); inverse of :meth:`to_table`."""
        xy = np.asarray(xy, dtype=float)
        u0, _, _, v1 = self.faces
        s = self.metres_per_px
        return np.stack([u0 + xy[..., 0] / s, v1 - xy[..., 1] / s], axis=-1)


PAPER_LAYOUT = PaperEnvLayout()
"""The paper's environment as it runs (zoom 2, 1470 x 820 px)."""

PAPER_ENV_WINDOW_PX = (735, 410)
"""The paper's nominal window [px] (zoom 1), the frame of ``paper_pixels`` observations and ``env_xy_px``."""


@cache
def paper_table() -> TableSpec:
    """The paper's table in SI units: the ``physics="paper"`` table.

    Its cushion faces span 1308 x 658 px at zoom 2, scaled so that the length is a 9-foot table's 2.54 m
    (1.278 m wide, 1.942 mm per pixel); balls of 14 px are 54.4 mm across (5% smaller than 57.15 mm).
    Corner mouths are 44 px along each rail from the corner (a 62 px / 12.1 cm mouth), side mouths 78 px
    (15.1 cm); jaws slant at 141.8 degrees (corner) and 107.6 degrees (side) to the cushion face. A ball
    drops as soon as it overlaps a 30 px pocket circle: capture radius 44 px (8.5 cm), corner circles
    11 px outside each face line, side circles on the border line 22 px behind the face. The jaw depth is
    the corner jaws' 35.6 px (the side jaws are 23.1 px deep in the paper; ``physics.paper`` uses the exact
    cushion polygons of :class:`PaperEnvLayout`).
    """
    lay = PAPER_LAYOUT
    s = lay.metres_per_px
    u0, u1, v0, v1 = lay.faces
    q = lay.cushion_polygons
    corner_jaw = q[5, 1] - q[5, 0]  # head cushion: jaw point (81, 125) back to (59, 97)
    side_jaw = q[0, 3] - q[0, 2]  # bottom head-half cushion: jaw point to its border end
    corner_mouth = float(q[5, 1, 1] - v0) * math.sqrt(2.0)
    side_mouth = float(q[1, 1, 0] - q[0, 2, 0])
    pockets = lay.pocket_centres
    corner_setback = float(np.hypot(*(pockets[5] - [u0, v0])))
    side_setback = float(pockets[1, 1] - v1)
    capture = lay.pocket_radius + lay.ball_radius
    return TableSpec(
        name="paper",
        length=(u1 - u0) * s,
        width=(v1 - v0) * s,
        ball_radius=lay.ball_radius * s,
        corner_mouth=corner_mouth * s,
        side_mouth=side_mouth * s,
        corner_jaw_angle=math.acos(float(corner_jaw[1] / -np.hypot(*corner_jaw))),
        side_jaw_angle=math.acos(float(side_jaw[0] / -np.hypot(*side_jaw))),
        jaw_depth=float(np.hypot(*corner_jaw)) * s,
        corner_pocket_setback=corner_setback * s,
        corner_capture_radius=capture * s,
        side_pocket_setback=side_setback * s,
        side_capture_radius=capture * s,
        rail_width=u0 * s,
    )


def paper_env_raster(spec: TableSpec | None = None) -> TableRaster:
    """The paper's nominal 735 x 410 px window for ``spec`` (default 9-foot).

    The table's playing surface (between the cushion noses) fills the paper's cushion-face rectangle:
    u 40.5-694.5, v 40.5-369.5 (its zoom-2 world at half scale; ball centres of :func:`paper_table` lie in
    u 47.5-687.5, v 47.5-362.5).
    """
    spec = spec or TableSpec()
    lay = PAPER_LAYOUT
    u0, u1, v0, v1 = lay.faces
    half = 1.0 / lay.zoom
    return TableRaster(spec, ((u1 - u0) * half, (v1 - v0) * half), (u0 * half, v0 * half))


def table_to_env_pixels(xy: np.ndarray, spec: TableSpec | None = None) -> np.ndarray:
    """Table points [m] -> the paper's environment pixels (u right, v down, 735 x 410 window)."""
    return paper_env_raster(spec).table_to_pixels(xy)


def env_pixels_to_table(uv: np.ndarray, spec: TableSpec | None = None) -> np.ndarray:
    """The paper's environment pixels (735 x 410 window) -> table points [m]."""
    return paper_env_raster(spec).pixels_to_table(uv)

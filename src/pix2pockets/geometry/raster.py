"""Conversions between table metres and raster pixels (environment windows, diagrams).

Pixels exist only at the edges. A :class:`TableRaster` maps the table frame (metres, ``+y`` up) to an
image raster (pixels, origin at the top-left pixel corner, ``+v`` down) by a scale per axis and a margin
for the rails. The paper's environment window is :data:`PAPER_ENV_RASTER`.
"""

from __future__ import annotations

from dataclasses import dataclass

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


# The seed paper's environment: a 735 x 410 px window including 30 px rails; ball radius 7 px,
# pocket radius 15 px; ball centres keep 7 px from the cushions -> 662 x 337 valid centre positions.
PAPER_ENV_WINDOW_PX = (735, 410)
PAPER_ENV_RAIL_PX = 30
PAPER_ENV_BALL_RADIUS_PX = 7
PAPER_ENV_POCKET_RADIUS_PX = 15
PAPER_ENV_VALID_CENTRES = (662, 337)  # (along x, along y)


def paper_env_raster(spec: TableSpec | None = None) -> TableRaster:
    """The paper's environment raster (735 x 410 px, 30 px rails) for ``spec`` (default 9-foot)."""
    spec = spec or TableSpec()
    surface = (
        PAPER_ENV_WINDOW_PX[0] - 2 * PAPER_ENV_RAIL_PX,
        PAPER_ENV_WINDOW_PX[1] - 2 * PAPER_ENV_RAIL_PX,
    )
    return TableRaster(spec, surface, (PAPER_ENV_RAIL_PX, PAPER_ENV_RAIL_PX))


def table_to_env_pixels(xy: np.ndarray, spec: TableSpec | None = None) -> np.ndarray:
    """Table points [m] -> the paper's environment pixels (u right, v down)."""
    return paper_env_raster(spec).table_to_pixels(xy)


def env_pixels_to_table(uv: np.ndarray, spec: TableSpec | None = None) -> np.ndarray:
    """The paper's environment pixels -> table points [m]."""
    return paper_env_raster(spec).pixels_to_table(uv)

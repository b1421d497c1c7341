"""Table geometry: the table frame, pockets, cushions, diamonds, rasters and cameras."""

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.raster import (
    TableRaster,
    env_pixels_to_table,
    paper_env_raster,
    table_to_env_pixels,
)
from pix2pockets.geometry.table import (
    TABLE_PRESETS,
    Pocket,
    PocketKind,
    Rail,
    TableSpec,
    table_preset,
)

__all__ = [
    "TABLE_PRESETS",
    "PinholeCamera",
    "Pocket",
    "PocketKind",
    "Rail",
    "TableRaster",
    "TableSpec",
    "env_pixels_to_table",
    "paper_env_raster",
    "table_preset",
    "table_to_env_pixels",
]

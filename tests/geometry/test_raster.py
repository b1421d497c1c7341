import numpy as np
import pytest

from pix2pockets.geometry import TableRaster, TableSpec, env_pixels_to_table, paper_env_raster, table_to_env_pixels
from pix2pockets.geometry.raster import PAPER_ENV_BALL_RADIUS_PX, PAPER_ENV_VALID_CENTRES, PAPER_ENV_WINDOW_PX


def test_paper_window():
    raster = paper_env_raster()
    assert raster.window_px == PAPER_ENV_WINDOW_PX
    spec = raster.spec
    np.testing.assert_allclose(table_to_env_pixels([0.0, spec.width]), [30, 30])
    np.testing.assert_allclose(table_to_env_pixels([spec.length, 0.0]), [705, 380])


def test_paper_valid_centre_count():
    raster = paper_env_raster()
    w, h = raster.surface_px
    r = PAPER_ENV_BALL_RADIUS_PX
    assert (int(w - 2 * r + 1), int(h - 2 * r + 1)) == (PAPER_ENV_VALID_CENTRES[0] + 0, PAPER_ENV_VALID_CENTRES[1])


@pytest.mark.parametrize("raster", [paper_env_raster(), TableRaster.fit(TableSpec(), 1000)])
def test_round_trip(raster):
    rng = np.random.default_rng(0)
    xy = rng.random((100, 2)) * raster.spec.size
    np.testing.assert_allclose(raster.pixels_to_table(raster.table_to_pixels(xy)), xy, atol=1e-12)


def test_env_helpers_round_trip():
    xy = np.array([[0.3, 0.2], [2.0, 1.1]])
    np.testing.assert_allclose(env_pixels_to_table(table_to_env_pixels(xy)), xy)


def test_pixel_axes():
    raster = TableRaster.fit(TableSpec(), 800)
    a, b = raster.table_to_pixels(np.array([[0.5, 0.5], [0.6, 0.6]]))
    assert b[0] > a[0]  # +x right
    assert b[1] < a[1]  # +y up -> v decreases


def test_bad_raster():
    with pytest.raises(ValueError):
        TableRaster(TableSpec(), (0, 10), (1, 1))

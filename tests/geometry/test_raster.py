import numpy as np
import pytest

from pix2pockets.geometry import TableRaster, TableSpec, env_pixels_to_table, paper_env_raster, table_to_env_pixels
from pix2pockets.geometry.raster import PAPER_ENV_WINDOW_PX, PAPER_LAYOUT, PaperEnvLayout, paper_table


def test_paper_window():
    # the paper's layout: a 29.5 px border plus an 11 px cushion, cushion faces at 40.5 / 694.5 and 40.5 / 369.5
    raster = paper_env_raster()
    assert raster.window_px == PAPER_ENV_WINDOW_PX
    spec = raster.spec
    np.testing.assert_allclose(table_to_env_pixels([0.0, spec.width]), [40.5, 40.5])
    np.testing.assert_allclose(table_to_env_pixels([spec.length, 0.0]), [694.5, 369.5])


def test_paper_layout_at_zoom_2():
    lay = PAPER_LAYOUT
    assert lay.window == (1470, 820) and lay.faces == (81, 1389, 81, 739) and lay.centre_box == (95, 1375, 95, 725)
    assert (lay.ball_radius, lay.pocket_radius) == (14, 30)
    np.testing.assert_allclose(lay.pocket_centres[[0, 1, 5]], [[70, 750], [735, 761], [70, 70]])
    assert PaperEnvLayout(zoom=1).faces == (40, 695, 40, 370)  # its zoom-1 config truncates differently


def test_paper_table_matches_its_layout():
    spec = paper_table()
    assert spec.length == pytest.approx(2.54)
    assert spec.ball_radius * 2 == pytest.approx(28 * 2.54 / 1308)  # 54.4 mm balls
    np.testing.assert_allclose(PAPER_LAYOUT.from_table(spec.pocket_centres), PAPER_LAYOUT.pocket_centres, atol=1e-9)
    jaws = np.array([p.jaws for p in spec.pockets])
    np.testing.assert_allclose(np.sort(PAPER_LAYOUT.from_table(jaws), axis=1), np.sort(PAPER_LAYOUT.jaw_points, axis=1))
    # paper pixels at half the zoom-2 world
    np.testing.assert_allclose(table_to_env_pixels(spec.pocket_centres, spec), PAPER_LAYOUT.pocket_centres / 2)


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

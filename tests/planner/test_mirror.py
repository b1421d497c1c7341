"""Mirror-table geometry: reflections, bounce points, cushions, penalty multipliers."""

import numpy as np
import pytest

from pix2pockets.geometry.table import Rail, TableSpec
from pix2pockets.planner.mirror import (
    RAILS,
    PenaltyScheme,
    bounce_point,
    cushion_at,
    cushion_multiplier,
    rail_line,
    rail_of_cushion,
    rail_pockets,
    reflect,
)

SPEC = TableSpec()
R = SPEC.ball_radius


@pytest.mark.parametrize("rail", RAILS)
def test_reflect_twice_is_identity_and_fixes_the_line(rail):
    pts = np.array([[0.3, 0.2], [1.7, 1.1]])
    np.testing.assert_allclose(reflect(reflect(pts, SPEC, rail), SPEC, rail), pts)
    on_line = np.array([rail_line(SPEC, rail)] * 2)
    np.testing.assert_allclose(reflect(on_line, SPEC, rail)[rail is Rail.BOTTOM or rail is Rail.TOP], on_line[0])


def test_reflect_across_bottom_ball_centre_line():
    np.testing.assert_allclose(reflect(np.array([1.0, 0.5]), SPEC, Rail.BOTTOM), [1.0, 2 * R - 0.5])
    np.testing.assert_allclose(reflect(np.array([1.0, 0.5]), SPEC, Rail.FOOT), [2 * (SPEC.length - R) - 1.0, 0.5])


def test_bounce_point_equal_angles():
    start = np.array([0.5, 0.6])
    end = np.array([1.5, 0.9])
    hit = bounce_point(start, reflect(end, SPEC, Rail.BOTTOM), SPEC, Rail.BOTTOM)
    assert hit[1] == pytest.approx(R)
    a_in = np.arctan2(start[1] - hit[1], hit[0] - start[0])
    a_out = np.arctan2(end[1] - hit[1], end[0] - hit[0])
    assert a_in == pytest.approx(a_out)
    assert bounce_point(start, end, SPEC, Rail.BOTTOM) is None  # not through the mirror


def test_cushion_at_and_mouths():
    assert cushion_at(np.array([0.6, R]), SPEC, Rail.BOTTOM) == 0
    assert cushion_at(np.array([1.9, R]), SPEC, Rail.BOTTOM) == 1
    assert cushion_at(np.array([SPEC.length / 2, R]), SPEC, Rail.BOTTOM) is None  # side pocket mouth
    assert cushion_at(np.array([SPEC.length - R, 0.6]), SPEC, Rail.FOOT) == 2
    assert cushion_at(np.array([R, 0.01]), SPEC, Rail.HEAD) is None  # corner mouth
    assert rail_of_cushion(4) is Rail.TOP
    assert set(rail_pockets(Rail.TOP)) == {3, 4, 5}
    with pytest.raises(ValueError, match="cushion index"):
        rail_of_cushion(6)


def test_multipliers_text_and_code():
    assert cushion_multiplier("direct", 0) == 1.0
    assert cushion_multiplier("bank", 1) == pytest.approx(0.33)
    assert cushion_multiplier("kick", 2, penalty=0.5) == pytest.approx(0.25)
    assert cushion_multiplier("bank", 1, PenaltyScheme.PAPER_CODE) == 0.5
    assert cushion_multiplier("kick", 1, PenaltyScheme.PAPER_CODE) == 0.75
    with pytest.raises(ValueError, match="penalty"):
        cushion_multiplier("bank", 1, penalty=0.0)

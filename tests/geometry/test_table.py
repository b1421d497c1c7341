import dataclasses
import math

import numpy as np
import pytest

from pix2pockets.geometry import TABLE_PRESETS, PocketKind, TableSpec, table_preset
from pix2pockets.geometry.table import INCH


@pytest.fixture(params=sorted(TABLE_PRESETS))
def spec(request) -> TableSpec:
    return TABLE_PRESETS[request.param]


def test_nine_foot_is_default():
    spec = TableSpec()
    assert spec.name == "9ft"
    assert spec.length == pytest.approx(2.54)
    assert spec.width == pytest.approx(1.27)
    assert 2 * spec.ball_radius == pytest.approx(0.05715)


@pytest.mark.parametrize(("name", "length_in", "width_in"), [("9ft", 100, 50), ("8ft", 92, 46), ("7ft", 78, 39)])
def test_presets(name, length_in, width_in):
    spec = table_preset(name)
    assert spec.length == pytest.approx(length_in * INCH)
    assert spec.width == pytest.approx(width_in * INCH)


def test_unknown_preset():
    with pytest.raises(ValueError, match="unknown table preset"):
        table_preset("10ft")


@pytest.mark.parametrize(
    "changes", [{"length": -1.0}, {"width": 3.0}, {"ball_radius": 0.0}, {"side_jaw_angle": math.radians(10)}]
)
def test_bad_spec_rejected(changes):
    with pytest.raises(ValueError):
        dataclasses.replace(TableSpec(), **changes)


def test_diamonds_count_order_and_spacing(spec):
    d = spec.diamonds
    assert d.shape == (18, 2)
    b = spec.diamond_setback
    np.testing.assert_allclose(d[:6, 1], -b)
    np.testing.assert_allclose(d[6:9, 0], spec.length + b)
    np.testing.assert_allclose(d[9:15, 1], spec.width + b)
    np.testing.assert_allclose(d[15:, 0], -b)
    # long rails: eighths of the length, the 4/8 spot is the side pocket
    np.testing.assert_allclose(d[:6, 0] / spec.length * 8, [1, 2, 3, 5, 6, 7])
    np.testing.assert_allclose(d[9:15, 0] / spec.length * 8, [7, 6, 5, 3, 2, 1])
    np.testing.assert_allclose(d[6:9, 1] / spec.width * 4, [1, 2, 3])
    np.testing.assert_allclose(d[15:, 1] / spec.width * 4, [3, 2, 1])
    # one diamond spacing on both rails is the same distance (a quarter width == an eighth length)
    assert spec.length / 8 == pytest.approx(spec.width / 4)


def test_nine_foot_diamond_spacing_is_12_5_inches():
    assert np.diff(TableSpec().diamonds[:3, 0]) == pytest.approx([12.5 * INCH] * 2)


def test_diamonds_are_point_symmetric(spec):
    d = spec.diamonds
    rotated = spec.size - d  # 180 degree rotation about the table centre
    # rotation maps bottom rail to top rail etc.: every rotated point is some diamond
    dist = np.linalg.norm(rotated[:, None] - d[None], axis=-1).min(axis=1)
    np.testing.assert_allclose(dist, 0, atol=1e-12)
    mirrored = d * [1, -1] + [0, spec.width]
    dist = np.linalg.norm(mirrored[:, None] - d[None], axis=-1).min(axis=1)
    np.testing.assert_allclose(dist, 0, atol=1e-12)


def test_reference_points(spec):
    pts = spec.reference_points
    assert pts.shape == (22, 2)
    np.testing.assert_allclose(pts[18:], [[0, 0], [spec.length, 0], [spec.length, spec.width], [0, spec.width]])


def test_pockets(spec):
    pockets = spec.pockets
    assert [p.kind for p in pockets] == [PocketKind.CORNER, PocketKind.SIDE, PocketKind.CORNER] * 2
    for p in pockets:
        expected = spec.corner_mouth if p.kind is PocketKind.CORNER else spec.side_mouth
        assert p.mouth_width == pytest.approx(expected)
        assert not spec.contains(p.centre, margin=1e-9)  # capture centres lie outside the surface
    # side pockets sit at the middle of the long rails
    assert pockets[1].aim == pytest.approx([spec.length / 2, 0])
    assert pockets[4].aim == pytest.approx([spec.length / 2, spec.width])
    # point symmetry of the pocket set
    centres = spec.pocket_centres
    np.testing.assert_allclose(np.sort((spec.size - centres)[:, 0]), np.sort(centres[:, 0]))


def test_cushions_join_jaw_points(spec):
    segs = spec.cushion_segments
    assert segs.shape == (6, 2, 2)
    jaws = np.vstack([p.jaws for p in spec.pockets])
    ends = segs.reshape(-1, 2)
    dist = np.linalg.norm(ends[:, None] - jaws[None], axis=-1).min(axis=1)
    np.testing.assert_allclose(dist, 0, atol=1e-12)
    lengths = np.linalg.norm(segs[:, 1] - segs[:, 0], axis=1)
    assert np.all(lengths > 0.3)


@pytest.mark.parametrize("kind", [PocketKind.CORNER, PocketKind.SIDE])
def test_jaw_angles(kind):
    spec = TableSpec()
    expected = spec.corner_jaw_angle if kind is PocketKind.CORNER else spec.side_jaw_angle
    jaw_segs = spec.jaw_segments
    assert jaw_segs.shape == (12, 2, 2)
    for k, pocket in enumerate(spec.pockets):
        if pocket.kind is not kind:
            continue
        for i in range(2):
            start, end = jaw_segs[2 * k + i]
            jaw_dir = (end - start) / np.linalg.norm(end - start)
            # the cushion nose direction pointing away from the pocket, from the adjoining cushion segment
            seg = next(s for s in spec.cushion_segments if np.allclose(s[0], start) or np.allclose(s[1], start))
            other_end = seg[1] if np.allclose(seg[0], start) else seg[0]
            nose = (other_end - start) / np.linalg.norm(other_end - start)
            angle = math.acos(np.clip(jaw_dir @ nose, -1, 1))
            assert angle == pytest.approx(expected, abs=1e-9)
            assert not spec.contains(end, margin=1e-9)  # jaws go back into the rail


def test_contains():
    spec = TableSpec()
    assert spec.contains([1.0, 0.5])
    assert not spec.contains([-0.01, 0.5])
    assert not spec.contains([0.01, 0.5], margin=spec.ball_radius)


def test_uk_tables_follow_the_wepf_sizes():
    uk7, uk6 = table_preset("uk7"), table_preset("uk6")
    assert 2 * uk7.ball_radius == pytest.approx(0.0508) and uk7.ball_mass == pytest.approx(0.116)
    assert (uk7.length, uk7.width) == pytest.approx((84 * INCH, 42 * INCH))
    assert (uk6.length, uk6.width) == pytest.approx((72 * INCH, 36 * INCH))
    assert uk7.corner_mouth < TableSpec().corner_mouth  # small pockets for small balls


def test_the_baulk_line_lies_a_fifth_of_the_length_from_the_head_cushion():
    spec = table_preset("uk7")
    assert spec.baulk_line_x == pytest.approx(84 * INCH / 5)
    assert spec.contains(np.array([spec.baulk_line_x, spec.width / 2]))


def test_a_pocket_is_found_by_its_name():
    spec = TableSpec()
    assert [spec.pocket_index(p.name) for p in spec.pockets] == list(range(6))
    with pytest.raises(ValueError, match="no pocket named 'middle'"):
        spec.pocket_index("middle")

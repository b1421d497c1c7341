"""Hitpoints on known straight-in, cut, bank, kick and blocked cases."""

import math

import numpy as np
import pytest

from pix2pockets.geometry.table import TableSpec
from pix2pockets.planner import Hitpoint, ShotKind, find_hitpoints
from pix2pockets.planner.mirror import rail_axis, rail_line, rail_of_cushion
from pix2pockets.state import Ball, TableLayout, random_layout

SPEC = TableSpec()
R = SPEC.ball_radius
MID = SPEC.length / 2


def layout(*pos, numbers=None):
    numbers = numbers or list(range(len(pos)))
    return TableLayout(tuple(Ball.numbered(n) for n in numbers), np.array(pos, dtype=float))


def by(hps, kind, pocket=None):
    return [h for h in hps if h.kind is kind and (pocket is None or h.pocket == pocket)]


def test_straight_in_side_pocket():
    lay = layout([MID, 0.8], [MID, 0.3])
    (hp,) = by(find_hitpoints(lay, [1]), ShotKind.DIRECT, pocket=1)
    assert hp.cut_angle == pytest.approx(0.0, abs=1e-9)
    assert hp.cue_angle == pytest.approx(-math.pi / 2)
    np.testing.assert_allclose(hp.ghost, [MID, 0.3 + 2 * R], atol=1e-12)
    np.testing.assert_allclose(hp.aim_point, hp.ghost)
    assert hp.window == pytest.approx(2 * math.atan(SPEC.side_mouth / 2 / 0.3))
    assert hp.cushions == ()
    assert hp.object_distance == pytest.approx(0.3)
    assert hp.cue_distance == pytest.approx(0.5 - 2 * R)


def test_cut_shot_angle():
    cue = np.array([MID - 0.4, 0.8])
    lay = layout(cue, [MID, 0.3])
    (hp,) = by(find_hitpoints(lay, [1]), ShotKind.DIRECT, pocket=1)
    ghost = np.array([MID, 0.3 + 2 * R])
    d = ghost - cue
    expected = math.acos(-d[1] / np.linalg.norm(d))  # angle between cue path and straight down
    assert hp.cut_angle == pytest.approx(expected)
    assert hp.cue_angle == pytest.approx(math.atan2(d[1], d[0]))


def test_overcut_is_dropped_and_max_cut_respected():
    lay = layout([MID - 0.6, 0.3 + 2 * R], [MID, 0.3])  # cue level with the object ball: ~90 deg cut
    assert not by(find_hitpoints(lay, [1]), ShotKind.DIRECT, pocket=1)
    lay = layout([MID - 0.4, 0.8], [MID, 0.3])
    assert not by(find_hitpoints(lay, [1], max_cut=math.radians(20)), ShotKind.DIRECT, pocket=1)


def test_blocked_object_and_cue_paths():
    blocker_obj = layout([MID, 0.8], [MID, 0.3], [MID + 0.02, 0.12])
    assert not by(find_hitpoints(blocker_obj, [1]), ShotKind.DIRECT, pocket=1)
    blocker_cue = layout([MID, 0.8], [MID, 0.3], [MID - 0.03, 0.55])
    assert not by(find_hitpoints(blocker_cue, [1]), ShotKind.DIRECT, pocket=1)
    clear = layout([MID, 0.8], [MID, 0.3], [MID + 0.3, 0.55])
    assert by(find_hitpoints(clear, [1]), ShotKind.DIRECT, pocket=1)


def test_side_pocket_along_the_rail_does_not_fit():
    lay = layout([0.3, 0.6], [0.8, R + 0.001])
    assert not by(find_hitpoints(lay, [1]), ShotKind.DIRECT, pocket=1)


def _reflect_path(start, angle, rail, spec):
    """Follow a centre from ``start`` along ``angle`` to the rail line; return bounce point and new direction."""
    v = np.array([math.cos(angle), math.sin(angle)])
    ax = rail_axis(rail)
    t = (rail_line(spec, rail) - start[ax]) / v[ax]
    hit = start + t * v
    v2 = v.copy()
    v2[ax] = -v2[ax]
    return hit, v2


def _crosses_mouth(start, v, jaws, r):
    """The ray passes between the jaw points, clearing each by r."""
    for j in jaws:
        rel = j - start
        if abs(rel[0] * v[1] - rel[1] * v[0]) < r - 1e-9:
            return False
    a = jaws[0] - start
    b = jaws[1] - start
    return (a[0] * v[1] - a[1] * v[0]) * (b[0] * v[1] - b[1] * v[0]) < 0


def test_bank_paths_reflect_into_the_pocket():
    lay = layout([0.8, 0.9], [1.0, 0.45])
    banks = by(find_hitpoints(lay, [1], kinds=[ShotKind.BANK]), ShotKind.BANK)
    assert banks, "expected at least one bank"
    assert any(h.pocket == 4 and h.cushions in ((0,), (1,)) for h in banks)  # off the bottom rail, top side
    b = lay.positions[1]
    for h in banks:
        (cushion,) = h.cushions
        rail = rail_of_cushion(cushion)
        hit, v2 = _reflect_path(b, h.object_angle, rail, SPEC)
        assert SPEC.contains(hit, margin=R - 1e-9)
        assert _crosses_mouth(hit, v2, SPEC.pockets[h.pocket].jaws, R)
        u = np.array([math.cos(h.object_angle), math.sin(h.object_angle)])
        np.testing.assert_allclose(h.ghost, b - 2 * R * u)


def test_kick_paths_reach_the_ghost():
    lay = layout([0.5, 0.3], [1.7, 0.3], [1.1, 0.3])  # ball 2 blocks the direct path
    hps = find_hitpoints(lay, [1], kinds=list(ShotKind))
    assert not by(hps, ShotKind.DIRECT, pocket=2)
    kicks = by(hps, ShotKind.KICK)
    assert kicks
    c = lay.positions[0]
    for h in kicks:
        rail = rail_of_cushion(h.cushions[0])
        hit, v2 = _reflect_path(c, h.cue_angle, rail, SPEC)
        rel = h.ghost - hit
        assert abs(rel[0] * v2[1] - rel[1] * v2[0]) < 1e-9  # the rebound passes through the ghost
        assert rel @ v2 > 0
        assert not np.allclose(h.aim_point, h.ghost)


def test_order_determinism_and_shot():
    lay = random_layout(np.random.default_rng(3), list(range(16)))
    targets = [1, 2, 3, 4, 5, 6, 7]
    a = find_hitpoints(lay, targets, kinds=list(ShotKind))
    b = find_hitpoints(lay, targets, kinds=("direct", "bank", "kick"))
    assert a == b and len(a) > 0
    keys = [(targets.index(h.target), h.pocket) for h in a]
    assert keys == sorted(keys)
    for h in a:
        assert isinstance(h, Hitpoint) and 0 <= h.cut_angle <= math.radians(80)
        assert h.shot(2.0).angle == h.cue_angle
    direct_only = find_hitpoints(lay, targets)
    assert all(h.kind is ShotKind.DIRECT for h in direct_only)


@pytest.mark.parametrize(
    ("targets", "kw", "match"),
    [([0], {}, "cue ball"), ([9], {}, "out of range"), ([1], {"max_cut": 0.0}, "max_cut")],
)
def test_bad_input(targets, kw, match):
    lay = layout([0.5, 0.5], [1.0, 0.5])
    with pytest.raises(ValueError, match=match):
        find_hitpoints(lay, targets, **kw)


def test_no_cue_ball():
    lay = TableLayout((Ball.numbered(1),), [[1.0, 0.5]])
    with pytest.raises(ValueError, match="no cue ball"):
        find_hitpoints(lay, [0])

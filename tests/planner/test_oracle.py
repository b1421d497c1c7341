"""The paper's Oracle: score, variants, determinism, fallback."""

import math

import numpy as np
import pytest

from pix2pockets.planner import ShotKind, find_hitpoints
from pix2pockets.planner.mirror import PenaltyScheme
from pix2pockets.planner.oracle import OracleConfig, OracleMode, OraclePlanner, oracle_score
from pix2pockets.planner.registry import PLANNER_NAMES, make_planner
from pix2pockets.rules import GameState
from pix2pockets.state import Ball, Group, TableLayout, random_layout

SOLIDS = GameState(Group.SOLIDS)
MID = 1.27


def layout(*pos, numbers=None):
    numbers = numbers or list(range(len(pos)))
    return TableLayout(tuple(Ball.numbered(n) for n in numbers), np.array(pos, dtype=float))


def test_score_formula_and_penalties():
    lay = layout([MID, 0.8], [MID, 0.3])
    (hp,) = [h for h in find_hitpoints(lay, [1]) if h.pocket == 1]
    assert oracle_score(hp) == pytest.approx(hp.window / math.radians(60) + 1.0)
    lay = layout([0.8, 0.9], [1.0, 0.45])
    bank = next(h for h in find_hitpoints(lay, [1], kinds=[ShotKind.BANK]))
    base = bank.window / math.radians(60) + math.cos(bank.cut_angle)
    assert oracle_score(bank) == pytest.approx(0.33 * base)
    assert oracle_score(bank, PenaltyScheme.PAPER_CODE) == pytest.approx(0.5 * base)


def test_best_max_picks_the_top_score_at_max_speed():
    lay = random_layout(np.random.default_rng(5), list(range(16)))
    planner = OraclePlanner(OracleConfig(max_speed=4.0))
    sugg = planner.suggest(lay, SOLIDS)
    scores = [s.value for s in sugg]
    assert scores == sorted(scores, reverse=True)
    assert all(s.shot.speed == 4.0 and s.kind is ShotKind.DIRECT for s in sugg)
    assert all(lay.balls[s.target].group is Group.SOLIDS for s in sugg)


def test_mirror_adds_cushion_shots():
    lay = layout([0.5, 0.3], [1.7, 0.3], [1.1, 0.3])
    direct = OraclePlanner(OracleConfig(mirror=False)).scored_hitpoints(lay, SOLIDS)
    mirror = OraclePlanner(OracleConfig(mirror=True)).scored_hitpoints(lay, SOLIDS)
    assert len(mirror) > len(direct)
    assert {h.kind for _, h in mirror} >= {ShotKind.KICK}


@pytest.mark.parametrize("mode", list(OracleMode))
def test_random_modes_are_seeded(mode):
    lay = random_layout(np.random.default_rng(7), list(range(16)))
    planner = OraclePlanner(OracleConfig(mode=mode, mirror=True))
    a = planner.suggest(lay, SOLIDS, np.random.default_rng(3))[0]
    b = planner.suggest(lay, SOLIDS, np.random.default_rng(3))[0]
    assert a == b
    speeds = {planner.suggest(lay, SOLIDS, np.random.default_rng(s))[0].shot.speed for s in range(20)}
    if mode is OracleMode.RANDOM_RANDOM:
        assert len(speeds) > 1 and max(speeds) <= planner.config.max_speed
    else:
        assert speeds == {planner.config.max_speed}


def test_fallback_when_no_hitpoint():
    # the only solid is hidden behind a wall of stripes: no direct hitpoint; the Oracle still shoots
    lay = layout([1.0, 0.6], [0.2, 0.6], [0.7, 0.6], numbers=[0, 1, 9])
    assert not find_hitpoints(lay, [1])
    (sugg,) = OraclePlanner().suggest(lay, SOLIDS)
    assert sugg.safety and sugg.target == 1 and sugg.kind is None
    assert sugg.shot.angle == pytest.approx(math.pi)


def test_registry():
    assert {"oracle", "oracle-mirror", "search"} <= set(PLANNER_NAMES)
    assert make_planner("oracle-mirror").config.mirror
    with pytest.raises(ValueError, match="unknown planner"):
        make_planner("nope")
    with pytest.raises(ValueError, match="speed"):
        make_planner("oracle", oracle_speed=-1.0)

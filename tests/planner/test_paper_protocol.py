"""The paper's protocol (start layouts, judgement) and its Oracle."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.geometry.raster import PAPER_LAYOUT, paper_table
from pix2pockets.physics import make_simulator
from pix2pockets.planner.evaluation import evaluate_planner, paper_protocol
from pix2pockets.planner.paper_oracle import KickRule, PaperOracleConfig, PaperOraclePlanner
from pix2pockets.planner.paper_protocol import (
    PAPER_SEED_BASE,
    PAPER_SHOOTER,
    paper_continues,
    paper_shot_success,
    paper_start_layout,
    paper_turn_outcome,
)
from pix2pockets.planner.registry import make_planner
from pix2pockets.rules import GameState, Outcome
from pix2pockets.state import Ball, Event, EventType, Shot, ShotResult, TableLayout

STATE = GameState(PAPER_SHOOTER)


def test_start_layout_is_the_papers_draw():
    lay = paper_start_layout(PAPER_SEED_BASE)
    assert [b.number for b in lay.balls] == [*range(1, 16), 0]  # solids, the 8, stripes, then the cue ball
    assert lay.spec == paper_table()
    rs = np.random.RandomState(PAPER_SEED_BASE)  # the paper: np.random.seed(12345); np.random.randint(...)
    first = (rs.randint(95, 1375), rs.randint(95, 725))
    np.testing.assert_allclose(PAPER_LAYOUT.from_table(lay.positions[0]), first, atol=1e-9)
    uv = PAPER_LAYOUT.from_table(lay.positions)
    np.testing.assert_allclose(uv, np.round(uv), atol=1e-9)  # whole pixels
    assert paper_start_layout(PAPER_SEED_BASE) == lay


def _in_pocket(lay: TableLayout) -> bool:
    d = np.linalg.norm(lay.positions[:, None] - lay.spec.pocket_centres[None], axis=-1)
    return bool(np.any(d < lay.spec.corner_capture_radius))


def test_spawn_in_pocket_is_designed_out_unless_asked_for():
    seeds = [s for s in range(PAPER_SEED_BASE, PAPER_SEED_BASE + 300) if _in_pocket(paper_start_layout(s, 16, True))]
    assert seeds  # the paper's sampler puts a ball in a pocket circle now and then
    assert not any(_in_pocket(paper_start_layout(s, 16, False)) for s in seeds)


@pytest.mark.parametrize("balls", [1, 2])
def test_small_start_layouts(balls):
    lay = paper_start_layout(PAPER_SEED_BASE, balls)
    assert len(lay) == balls and lay.cue_index == balls - 1


def _result(lay: TableLayout, dropped: list[int]) -> ShotResult:
    events = [Event(0.0, EventType.CUE_STRIKE, lay.cue_index)]
    events += [Event(1.0 + k, EventType.POCKET, b, 0) for k, b in enumerate(dropped)]
    return ShotResult.from_events(lay, events, lay.positions, validate=False)


LAY = paper_start_layout(PAPER_SEED_BASE)
CUE, BLACK = LAY.cue_index, LAY.black_index
OWN = [i for i, b in enumerate(LAY.balls) if b.group is PAPER_SHOOTER]
OPP = [i for i, b in enumerate(LAY.balls) if b.group is PAPER_SHOOTER.other]


@pytest.mark.parametrize(
    ("dropped", "outcome", "success"),
    [
        ([], Outcome.END_TURN, False),
        ([OWN[0]], Outcome.CONTINUE, True),
        ([OWN[0], OWN[1]], Outcome.CONTINUE, True),
        ([OWN[0], OPP[0]], Outcome.END_TURN, True),  # an opponent's ball ends the turn; the pot still counts
        ([OPP[0]], Outcome.END_TURN, False),
        ([OWN[0], CUE], Outcome.END_TURN, True),
        ([BLACK], Outcome.LOSS, False),
        ([OWN[0], BLACK], Outcome.LOSS, True),
    ],
)
def test_judgement(dropped, outcome, success):
    turn = paper_turn_outcome(_result(LAY, dropped), STATE)
    assert turn.outcome is outcome
    assert paper_shot_success(turn) is success


def _endgame(extra: list[int]) -> TableLayout:
    keep = [CUE, BLACK, *extra]
    return TableLayout(tuple(LAY.balls[i] for i in keep), LAY.positions[keep], LAY.spec)


def test_the_8_after_the_group_wins():
    lay = _endgame([])
    assert paper_turn_outcome(_result(lay, [1]), STATE).outcome is Outcome.WIN
    assert paper_turn_outcome(_result(lay, [1, 0]), STATE).outcome is Outcome.LOSS  # with the cue ball


def test_the_early_8_loses_unless_the_defect_is_on():
    lay = _endgame([OWN[0]])  # cue, 8, last stripe
    early = _result(lay, [1, 2])  # the 8 drops before the last stripe, in the same shot
    assert paper_turn_outcome(early, STATE).outcome is Outcome.LOSS
    assert paper_turn_outcome(early, STATE, early_eight_wins=True).outcome is Outcome.WIN
    late = _result(lay, [2, 1])
    assert paper_turn_outcome(late, STATE).outcome is Outcome.WIN


def test_lean_judgement_matches_the_full_one():
    sim = make_simulator("paper")
    rng = np.random.default_rng(5)
    for i in range(4):
        lay = paper_start_layout(PAPER_SEED_BASE + i)
        rows = np.column_stack([rng.uniform(-math.pi, math.pi, 40), rng.uniform(0.2, 0.97, 40), np.zeros((40, 3))])
        lean = paper_continues(sim.simulate_arrays(lay, rows).pocket, lay, STATE)
        for k, row in enumerate(rows):
            turn = paper_turn_outcome(sim.simulate(lay, Shot(float(row[0]), float(row[1]))), STATE)
            assert lean[k] == (turn.outcome in (Outcome.CONTINUE, Outcome.WIN))


def _straight_layout() -> TableLayout:
    # a stripe 200 px from the bottom-right aiming point, the cue ball behind it on the line, solids far away
    aim = PAPER_LAYOUT.target_points[2]
    into = np.array([-1.0, -1.0]) / math.sqrt(2)
    uv = [(300.0, 200.0), tuple(aim + 200 * into), (300.0, 600.0), tuple(aim + 500 * into)]
    balls = (Ball.numbered(1), Ball.numbered(9), Ball.numbered(8), Ball.numbered(0))
    return TableLayout(balls, PAPER_LAYOUT.to_table(np.array(uv)), paper_table())


@pytest.mark.parametrize("mirror", [False, True])
def test_oracle_picks_the_straight_in_shot(mirror):
    lay = _straight_layout()
    best = PaperOraclePlanner(PaperOracleConfig(mirror=mirror)).suggest(lay, STATE)[0]
    assert (best.target, best.pocket, best.kind.value) == (1, 2, "direct")
    d = lay.positions[1] - lay.positions[3]
    assert best.shot.angle == pytest.approx(math.atan2(d[1], d[0]), abs=1e-9)
    res = make_simulator("paper").simulate(lay, best.shot)
    assert 1 in res.pocketed


def test_mirror_oracle_adds_banks_and_kicks():
    lay = paper_start_layout(PAPER_SEED_BASE + 3)
    direct = PaperOraclePlanner(PaperOracleConfig(mirror=False)).candidates(lay, STATE)
    mirror = PaperOraclePlanner(PaperOracleConfig(mirror=True)).candidates(lay, STATE)
    kinds = {c[2].kind.value for c in mirror}
    assert {c[2].kind.value for c in direct} == {"direct"}
    assert kinds == {"direct", "bank", "kick"}
    side = PaperOraclePlanner(PaperOracleConfig(mirror=True, kick_rule=KickRule.SIDE)).candidates(lay, STATE)
    assert [c[0] for c in side] != [c[0] for c in mirror]  # the code's multiplier quirk changes scores


def test_registry_gives_the_papers_oracle_on_paper_physics():
    planner = make_planner("oracle-mirror", physics="paper")
    assert isinstance(planner, PaperOraclePlanner) and planner.config.mirror
    with pytest.raises(ValueError, match="top power level"):
        make_planner("oracle", physics="paper", oracle_speed=2.0)


def test_oracle_evaluation_is_reproducible():
    # golden numbers for the first 30 reference layouts (the full 1,000 are in docs/benchmarks-planner.md)
    sim = make_simulator("paper")
    planner = make_planner("oracle", physics="paper")
    a = evaluate_planner(planner, sim.simulate, 16, 30, PAPER_SEED_BASE, physics="paper", protocol=paper_protocol())
    b = evaluate_planner(planner, sim.simulate, 16, 30, PAPER_SEED_BASE, physics="paper", protocol=paper_protocol())
    assert (a.shots, a.successes, a.clears) == (b.shots, b.successes, b.clears)
    assert a.protocol == "paper"
    assert 0.8 < a.per_shot_success < 0.97

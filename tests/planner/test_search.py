"""Search planner on the event physics: easy pots, determinism, rule consistency, fallback."""

import math

import numpy as np
import pytest

from pix2pockets.physics import make_simulator
from pix2pockets.planner import ShotKind, find_hitpoints
from pix2pockets.planner.position import direct_pot_probabilities, pot_probability
from pix2pockets.planner.search import SearchConfig, SearchPlanner, _runs
from pix2pockets.rules import GameState, turn_outcome
from pix2pockets.state import Ball, Group, Shot, TableLayout, random_layout

SOLIDS = GameState(Group.SOLIDS)
MID = 1.27
FAST = {"time_budget": None, "samples": 4, "max_candidates": 4, "speeds": (1.0, 2.0), "heights": (0.0, -0.3)}


def layout(*pos, numbers=None):
    numbers = numbers or list(range(len(pos)))
    return TableLayout(tuple(Ball.numbered(n) for n in numbers), np.array(pos, dtype=float))


@pytest.fixture(scope="module")
def planner():
    return SearchPlanner(SearchConfig(**FAST))


def test_pots_an_easy_straight_in(planner):
    lay = layout([MID, 0.8], [MID, 0.3], [2.0, 1.0], numbers=[0, 1, 9])
    best = planner.suggest(lay, SOLIDS, np.random.default_rng(0))[0]
    assert (best.target, best.pocket, best.kind) == (1, 1, ShotKind.DIRECT)
    assert best.success_probability >= 0.75
    assert best.shot.angle == pytest.approx(-math.pi / 2, abs=math.radians(2))
    res = planner.simulator.simulate(lay, best.shot)
    assert turn_outcome(res, SOLIDS).shot_succeeded


def test_deterministic_with_seed(planner):
    lay = random_layout(np.random.default_rng(11), list(range(16)))
    a = planner.suggest(lay, SOLIDS, np.random.default_rng(4))
    b = planner.suggest(lay, SOLIDS, np.random.default_rng(4))
    assert [(s.shot, s.target, s.pocket, s.success_probability) for s in a] == [
        (s.shot, s.target, s.pocket, s.success_probability) for s in b
    ]


def test_success_predicate_matches_rules(planner):
    sim = planner.simulator
    rng = np.random.default_rng(2)
    for seed in range(3):
        lay = random_layout(np.random.default_rng(seed), list(range(16)))
        cleared = GameState(Group.SOLIDS)
        rows = np.column_stack([rng.uniform(-math.pi, math.pi, 40), rng.uniform(0.5, 4.0, 40), np.zeros((40, 3))])
        first, pocket, _ = planner._run(lay, rows)
        ok = planner._success(first, pocket, lay, cleared)
        for row, flag in zip(rows, ok, strict=True):
            res = sim.simulate(lay, Shot(float(row[0]), float(row[1])))
            assert turn_outcome(res, cleared).shot_succeeded == bool(flag)


def test_eight_ball_when_group_cleared(planner):
    lay = layout([MID, 0.8], [MID, 0.3], [2.0, 1.0], numbers=[0, 8, 9])
    best = planner.suggest(lay, SOLIDS, np.random.default_rng(0))[0]
    assert best.target == 1
    assert turn_outcome(planner.simulator.simulate(lay, best.shot), SOLIDS).outcome.value == "win"


def test_never_empty_when_snookered(planner):
    lay = layout([1.0, 0.6], [0.2, 0.6], [0.7, 0.6], [0.7, 0.66], [0.7, 0.54], numbers=[0, 1, 9, 10, 11])
    sugg = planner.suggest(lay, SOLIDS, np.random.default_rng(0))
    assert sugg and isinstance(sugg[0].shot, Shot)


def test_vectorised_lookahead_matches_hitpoints():
    sigma = math.radians(0.125)
    for seed in range(5):
        lay = random_layout(np.random.default_rng(seed), list(range(16)))
        targets = [1, 2, 3, 4, 5, 6, 7]
        fast = direct_pot_probabilities(lay.positions, 0, targets, lay.spec, sigma)
        slow = np.zeros_like(fast)
        for h in find_hitpoints(lay, targets):
            slow[targets.index(h.target), h.pocket] = pot_probability(h, lay.spec.ball_radius, sigma)
        np.testing.assert_allclose(fast, slow, atol=1e-9)


def test_runs_circular():
    assert _runs(np.array([True, False, False, True, True])) == [(3, 3)]
    assert _runs(np.array([False, True, True, False])) == [(1, 2)]
    assert _runs(np.array([True, True])) == [(0, 2)]


def test_works_with_a_shot_by_shot_simulator():
    class Plain:  # no simulate_arrays: the planner falls back to simulate()
        name = "plain"

        def __init__(self):
            self.inner = make_simulator("event")

        def simulate(self, layout, shot, stop="rest"):
            return self.inner.simulate(layout, shot)

        def simulate_batch(self, layout, shots, stop="rest"):
            return [self.simulate(layout, s) for s in shots]

    p = SearchPlanner(SearchConfig(**{**FAST, "samples": 2}), simulator=Plain())
    lay = layout([MID, 0.8], [MID, 0.3], numbers=[0, 1])
    assert p.suggest(lay, SOLIDS)[0].target == 1


def test_blackball_success_predicate_matches_its_rules():
    from pix2pockets.rules import blackball_turn_outcome

    planner = SearchPlanner(SearchConfig(**FAST, rules="blackball"))
    sim = planner.simulator
    rng = np.random.default_rng(5)
    agree = opponent_fouls = 0
    for seed in range(3):
        lay = random_layout(np.random.default_rng(seed), list(range(16)))
        rows = np.column_stack([rng.uniform(-math.pi, math.pi, 40), rng.uniform(0.5, 4.0, 40), np.zeros((40, 3))])
        first, pocket, _ = planner._run(lay, rows)
        ok = planner._success(first, pocket, lay, SOLIDS)
        for row, flag in zip(rows, ok, strict=True):
            res = sim.simulate(lay, Shot(float(row[0]), float(row[1])))
            turn = blackball_turn_outcome(res, SOLIDS)
            agree += turn.shot_succeeded == bool(flag)
            opponent_fouls += "opponent_potted" in turn.fouls and turn_outcome(res, SOLIDS).shot_succeeded
    assert agree == 120
    assert opponent_fouls > 0  # strokes that 8-ball counts as pots and blackball as fouls were among them


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"fan": 4}, "fan"),
        ({"speeds": ()}, "speeds"),
        ({"heights": (0.7,)}, "heights"),
        ({"noise": "x"}, "noise"),
        ({"endgame": -1}, "endgame"),
        ({"endgame_speeds": (0.0,)}, "endgame_speeds"),
        ({"endgame_sides": (0.45,), "endgame_heights": (0.0, 0.4)}, "tip offsets"),
        ({"rules": "snooker"}, "rules"),
        ({"two_ply": -1}, "two_ply"),
        ({"two_ply_outcomes": 0}, "two_ply"),
        ({"two_ply_samples": -1}, "two_ply_samples"),
        ({"two_ply_verified": 0}, "two_ply_verified"),
        ({"two_ply_samples": 9, "samples": 4, "refine_samples": 4}, "two_ply_samples"),
        ({"two_ply_weight": -1.0}, "two_ply_weight"),
        ({"final_scale": 0}, "final_scale"),
        ({"stroke_budget": 0}, "stroke_budget"),
    ],
)
def test_bad_config(kw, match):
    with pytest.raises(ValueError, match=match):
        SearchConfig(**kw)


def test_potted_target_names_the_own_ball_that_dropped():
    lay = layout([MID, 0.8], [MID, 0.3], [2.0, 1.0], numbers=[0, 9, 1])
    row = np.array([-1, 3, 1])  # the stripe went into pocket 3, the solid (index 2) into pocket 1
    assert SearchPlanner._potted_target(row, lay, SOLIDS) == 2
    assert SearchPlanner._potted_target(np.array([-1, 3, -1]), lay, SOLIDS) is None


def test_endgame_adds_side_and_finer_strokes():
    # the last solid and the 8 among stripes: the endgame stroke set (english, more speeds) is searched
    lay = layout([MID, 0.8], [MID, 0.3], [2.0, 1.0], [0.6, 0.4], numbers=[0, 1, 8, 9])
    eg = {"endgame_speeds": (1.0, 2.0), "endgame_heights": (0.0, 0.3), "endgame_sides": (0.0, 0.3)}
    on = SearchPlanner(SearchConfig(**FAST, endgame=2, endgame_candidates=2, **eg))
    off = SearchPlanner(SearchConfig(**FAST, endgame=0, **eg))
    a = on.suggest(lay, SOLIDS, np.random.default_rng(0))
    b = off.suggest(lay, SOLIDS, np.random.default_rng(0))
    assert any(s.shot.side != 0 for s in a) and all(s.shot.side == 0 for s in b)
    assert a[0].target == 1 and a[0].success_probability >= 0.75
    assert turn_outcome(on.simulator.simulate(lay, a[0].shot), SOLIDS).shot_succeeded


def test_the_default_endgame_starts_with_five_balls_of_the_group_left():
    # five solids left: the default planner already plays for position with the finer stroke set (side spin)
    spots = ([0.4, 0.3], [MID, 0.9], [2.0, 0.3], [1.9, 1.0], [0.7, 1.0], [1.6, 0.5], [1.0, 0.6])
    lay = layout(*spots, numbers=[0, 1, 2, 3, 4, 5, 8])
    default = SearchPlanner(SearchConfig(**FAST, rescue_below=0.0))
    assert any(s.shot.side != 0 for s in default.suggest(lay, SOLIDS, np.random.default_rng(0)))
    with_two = SearchPlanner(SearchConfig(**FAST, rescue_below=0.0, endgame=2))
    assert all(s.shot.side == 0 for s in with_two.suggest(lay, SOLIDS, np.random.default_rng(0)))


def test_rescue_tries_the_finer_strokes_on_a_hard_shot():
    # three solids left (no endgame); rescue_below=1 treats every shot as hard, 0 never does
    lay = layout([0.4, 0.3], [MID, 0.9], [2.0, 0.3], [1.9, 1.0], [1.0, 0.6], numbers=[0, 1, 2, 3, 8])
    eg = {"endgame_speeds": (1.0, 2.0), "endgame_heights": (0.0,), "endgame_sides": (0.0, 0.3), "endgame": 2}
    on = SearchPlanner(SearchConfig(**FAST, rescue_below=1.0, endgame_candidates=2, **eg))
    off = SearchPlanner(SearchConfig(**FAST, rescue_below=0.0, **eg))
    a = on.suggest(lay, SOLIDS, np.random.default_rng(0))
    b = off.suggest(lay, SOLIDS, np.random.default_rng(0))
    assert any(s.shot.side != 0 for s in a) and all(s.shot.side == 0 for s in b)
    assert a[0].success_probability >= b[0].success_probability - 0.2  # the merged ranking keeps good shots


@pytest.mark.parametrize("two_ply_samples", [0, 8])
def test_next_value_reads_the_next_shot_by_simulation(monkeypatch, two_ply_samples):
    # solid 1 dropped; the last solid then lies straight in front of a corner pocket, or far off at a thin cut.
    # 0: the next shot is read off its aim fan; 8: its best two strokes are replayed under noise as well
    lay = layout([0.5, 0.5], [MID, 0.9], [2.2, 0.3], [1.0, 1.0], [0.3, 1.0], numbers=[0, 1, 2, 9, 8])
    plan = SearchPlanner(SearchConfig(**FAST, two_ply_samples=two_ply_samples, two_ply_verified=2))
    z = np.random.default_rng(0).standard_normal((8, 5))
    replays = []
    real = plan._replay
    monkeypatch.setattr(plan, "_replay", lambda st, *a, **k: replays.append(len(st)) or real(st, *a, **k))
    pocket = np.array([-1, 2, -1, -1, -1])
    easy = lay.positions.copy()
    easy[0], easy[2] = [2.0, 0.45], [2.25, 0.2]  # cue ball 0.28 m behind the solid, in line with the corner pocket
    hard = lay.positions.copy()
    hard[0], hard[2] = [0.2, 1.05], [2.4, 0.08]  # across the table, the solid near a rail
    v_easy = plan._next_value(lay, SOLIDS, pocket, easy, plan.noise.angle_sigma, z)
    v_hard = plan._next_value(lay, SOLIDS, pocket, hard, plan.noise.angle_sigma, z)
    assert bool(replays) is bool(two_ply_samples)
    assert all(n <= 2 for n in replays)  # at most two_ply_verified strokes replayed per position
    assert 0.0 <= v_hard < v_easy <= 1.0
    assert v_easy > 0.5


def test_next_value_is_a_win_when_the_8_dropped_legally():
    lay = layout([0.5, 0.5], [MID, 0.9], numbers=[0, 8])
    plan = SearchPlanner(SearchConfig(**FAST))
    assert plan._next_value(lay, GameState(Group.SOLIDS), np.array([-1, 4]), lay.positions, 0.002) == 1.0


@pytest.mark.parametrize(("two_ply", "called"), [(3, True), (0, False), (1, False)])
def test_two_ply_runs_only_with_few_balls_left(monkeypatch, two_ply, called):
    # two solids and the 8 left: two_ply=3 simulates the next shot, 0 (off) and 1 (one ball left) do not
    lay = layout([0.5, 0.5], [MID, 0.9], [2.0, 0.3], [1.0, 1.0], numbers=[0, 1, 2, 8])
    plan = SearchPlanner(SearchConfig(**FAST, two_ply=two_ply, two_ply_top=2, two_ply_outcomes=2))
    calls = []
    real = plan._next_value
    monkeypatch.setattr(plan, "_next_value", lambda *a: calls.append(1) or real(*a))
    best = plan.suggest(lay, SOLIDS, np.random.default_rng(0))[0]
    assert bool(calls) is called
    assert len(calls) <= 2 * 2
    assert best.target in (1, 2)


@pytest.mark.parametrize("final_scale", [1, 3])
def test_the_winning_shot_gets_more_replays(monkeypatch, final_scale):
    """With only the 8 left there is no position to play for: its strokes get ``final_scale`` times the replays."""
    counts = []
    original = SearchPlanner._replay

    def counting(self, strokes, layout, state, z, sigma, *args, **kwargs):
        counts.append(len(z))
        return original(self, strokes, layout, state, z, sigma, *args, **kwargs)

    monkeypatch.setattr(SearchPlanner, "_replay", counting)
    cfg = SearchConfig(**FAST, final_scale=final_scale, two_ply=0)
    planner = SearchPlanner(cfg)
    on_the_8 = layout([MID, 0.8], [MID, 0.3], [0.6, 0.4], numbers=[0, 8, 9])
    planner.suggest(on_the_8, SOLIDS, np.random.default_rng(0))
    assert counts[:2] == [final_scale * cfg.samples, final_scale * cfg.refine_samples]
    counts.clear()
    with_a_solid = layout([MID, 0.8], [MID, 0.3], [2.0, 1.0], [0.6, 0.4], numbers=[0, 1, 8, 9])
    planner.suggest(with_a_solid, SOLIDS, np.random.default_rng(0))
    assert counts[:2] == [cfg.samples, cfg.refine_samples]


def test_a_stroke_budget_caps_the_work_and_gives_the_same_decision_every_time():
    lay = random_layout(np.random.default_rng(11), list(range(16)))
    free = SearchPlanner(SearchConfig(**FAST))
    free.suggest(lay, SOLIDS, np.random.default_rng(4))
    unlimited = free._strokes
    cap = unlimited // 3
    capped = SearchPlanner(SearchConfig(**{**FAST, "stroke_budget": cap}))
    a = capped.suggest(lay, SOLIDS, np.random.default_rng(4))
    assert cap <= capped._strokes < unlimited  # stops after the batch that reaches the cap
    b = capped.suggest(lay, SOLIDS, np.random.default_rng(4))
    assert [(s.shot, s.target, s.success_probability) for s in a] == [
        (s.shot, s.target, s.success_probability) for s in b
    ]

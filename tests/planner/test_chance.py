"""Measured success chances: formatting, sample size, determinism, noise and position error."""

import math

import numpy as np
import pytest

from pix2pockets.planner.chance import Chance, format_chance, measure_chance
from pix2pockets.planner.noise import noise_model
from pix2pockets.planner.search import SearchConfig, SearchPlanner
from pix2pockets.rules import GameState
from pix2pockets.state import Ball, Group, Shot, TableLayout

POCKET = np.array([0.04041115, 0.04041115])  # bottom-left corner pocket's aim point [m]


@pytest.fixture(scope="module")
def planner():
    return SearchPlanner(SearchConfig(time_budget=None))


def straight_in(cue_distance: float = 0.61):
    """Object ball at the table centre straight in to a corner pocket, cue ball behind it on the line."""
    ob = np.array([1.27, 0.635])
    u = (POCKET - ob) / np.linalg.norm(POCKET - ob)
    layout = TableLayout((Ball.numbered(0), Ball.numbered(1)), [ob - cue_distance * u, ob])
    return layout, Shot(math.atan2(u[1], u[0]), 1.8), ob - 2 * layout.spec.ball_radius * u


@pytest.mark.parametrize(
    "p, text", [(1.0, ">99%"), (0.995, ">99%"), (0.99, "99%"), (0.5, "50%"), (0.004, "<1%"), (0.0, "<1%")]
)
def test_format_never_certain(p, text):
    assert format_chance(p) == text


def test_chance_fields():
    c = Chance(199, 200, "club")
    assert c.p == pytest.approx(0.995) and c.text == ">99%"
    lo, hi = c.ci95
    assert lo < 0.995 < hi <= 1.0
    d = c.to_dict()
    assert d["samples"] == 200 and d["successes"] == 199 and d["noise"] == "club" and d["text"] == ">99%"


@pytest.mark.parametrize("successes, samples", [(3, 2), (-1, 5), (0, 0)])
def test_bad_chance(successes, samples):
    with pytest.raises(ValueError):
        Chance(successes, samples)


def test_measured_chance_falls_with_skill_and_is_seeded(planner):
    layout, shot, _ = straight_in()
    state = GameState(Group.SOLIDS)
    rates = []
    for name in ("none", "pro", "club", "beginner"):
        c = measure_chance(planner, layout, state, shot, noise_model(name), 300, np.random.default_rng(1))
        assert c.samples == 300 and c.noise == name
        rates.append(c.p)
    assert rates[0] == 1.0
    assert rates[0] >= rates[1] > rates[2] > rates[3]
    again = measure_chance(planner, layout, state, shot, noise_model("club"), 300, np.random.default_rng(1))
    assert again.p == rates[2]


def test_position_error_costs_and_reaiming_helps(planner):
    layout, shot, ghost = straight_in()
    state = GameState(Group.SOLIDS)
    kw = dict(noise=noise_model("pro"), samples=300, position_sigma=0.004)
    exact = measure_chance(planner, layout, state, shot, noise_model("pro"), 300, np.random.default_rng(2))
    fixed = measure_chance(planner, layout, state, shot, rng=np.random.default_rng(2), **kw)
    aimed = measure_chance(planner, layout, state, shot, rng=np.random.default_rng(2), target=1, aim_point=ghost, **kw)
    assert fixed.position_sigma == 0.004
    assert fixed.p < exact.p
    assert fixed.p < aimed.p


def test_a_pocket_out_of_place_costs_the_more_the_further_it_may_lie(planner):
    layout, shot, ghost = straight_in()
    state = GameState(Group.SOLIDS)
    kw = dict(noise=noise_model("pro"), samples=300, target=1, aim_point=ghost)
    distance = float(np.linalg.norm(POCKET - layout.positions[1]))
    rates = []
    for sigma in (0.0, 0.01, 0.05, 0.2):
        c = measure_chance(
            planner,
            layout,
            state,
            shot,
            rng=np.random.default_rng(4),
            pocket_sigma=sigma,
            pocket_distance=distance,
            **kw,
        )
        assert c.pocket_sigma == sigma and c.to_dict()["pocket_sigma_m"] == sigma
        rates.append(c.p)
    assert rates[0] > 0.8
    assert rates[0] >= rates[1] > rates[2] > rates[3]
    # a 2-D Gaussian pocket error of 0.2 m leaves about the share that stays within the mouth's free half-width
    assert rates[3] < 0.3


@pytest.mark.parametrize(
    "kw", [{"target": None}, {"aim_point": None}, {"pocket_distance": 0.0}, {"pocket_sigma": -0.1}]
)
def test_a_pocket_error_needs_a_line_to_turn(planner, kw):
    layout, shot, ghost = straight_in()
    args = dict(target=1, aim_point=ghost, pocket_sigma=0.1, pocket_distance=1.0) | kw
    with pytest.raises(ValueError, match="pocket_sigma"):
        measure_chance(planner, layout, GameState(Group.SOLIDS), shot, **args)


@pytest.mark.parametrize("kw", [{"samples": 0}, {"position_sigma": -1.0}])
def test_bad_arguments(planner, kw):
    layout, shot, _ = straight_in()
    with pytest.raises(ValueError):
        measure_chance(planner, layout, GameState(Group.SOLIDS), shot, **kw)


def test_each_ball_can_carry_its_own_position_error(planner):
    layout, shot, _ = straight_in()
    state = GameState(Group.SOLIDS)
    kw = dict(noise=noise_model("pro"), samples=200)
    iso = measure_chance(planner, layout, state, shot, position_sigma=0.004, rng=np.random.default_rng(3), **kw)
    same = np.tile(np.eye(2) * 0.004**2, (2, 1, 1))
    as_cov = measure_chance(planner, layout, state, shot, position_sigma=same, rng=np.random.default_rng(3), **kw)
    assert as_cov.successes == iso.successes and as_cov.position_sigma == pytest.approx(0.004)
    # the object ball 1 cm off across the shot line turns a straight pot into a cut; along it, hardly matters
    u = np.array([np.cos(shot.angle), np.sin(shot.angle)])
    n = np.array([-u[1], u[0]])
    sure = np.eye(2) * 1e-8
    chances = {}
    for name, axis in (("across", n), ("along", u)):
        cov = np.stack([sure, np.outer(axis, axis) * 0.01**2 + sure])
        chances[name] = measure_chance(
            planner, layout, state, shot, position_sigma=cov, rng=np.random.default_rng(3), **kw
        ).p
    assert chances["across"] < chances["along"] - 0.2


@pytest.mark.parametrize("cov", [np.zeros((3, 2, 2)), np.full((2, 2, 2), np.nan), np.zeros((2, 2))])
def test_position_covariances_of_the_wrong_shape_are_refused(planner, cov):
    layout, shot, _ = straight_in()
    with pytest.raises(ValueError, match="position covariances"):
        measure_chance(planner, layout, GameState(Group.SOLIDS), shot, position_sigma=cov)

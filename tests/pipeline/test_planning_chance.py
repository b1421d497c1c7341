"""The pipeline's planning step: skill levels and measured chances with their sample size."""

import json

import numpy as np
import pytest

from pix2pockets.pipeline.planning import CHANCE_SAMPLES, default_planner, plan_shot
from pix2pockets.testing import NearestPocketPlanner, example_layout


@pytest.fixture(scope="module")
def layout():
    return example_layout()


@pytest.mark.parametrize("skill", ["pro", "beginner"])
def test_measured_chance_with_sample_size(layout, skill):
    planner = default_planner(skill=skill)
    advice = plan_shot(layout, "solids", planner, np.random.default_rng(0), chance_samples=100)
    assert planner.noise.name == skill
    assert advice.chance is not None and advice.chance.samples == 100 and advice.chance.noise == skill
    assert advice.success_probability == advice.chance.p
    assert advice.chance_exact_positions is not None and advice.chance_exact_positions.position_sigma == 0.0
    d = advice.to_dict()
    json.dumps(d)
    assert d["success_chance"]["samples"] == 100 and d["success_text"] == advice.chance.text
    assert d["success_text"] != "100%" and d["success_text"].endswith("%")
    assert d["success_chance"]["position_sigma_m"] > 0


def test_chance_is_deterministic(layout):
    a = plan_shot(layout, "solids", default_planner(skill="club"), np.random.default_rng(0), chance_samples=80)
    b = plan_shot(layout, "solids", default_planner(skill="club"), np.random.default_rng(0), chance_samples=80)
    assert a.chance == b.chance and a.stroke == b.stroke


def test_wrapped_planner_is_measured(layout):
    class Wrapper:  # like the CLI's AfterCompile
        def __init__(self, planner):
            self.planner = planner

        def suggest(self, *args, **kwargs):
            return self.planner.suggest(*args, **kwargs)

    advice = plan_shot(layout, "solids", Wrapper(default_planner()), np.random.default_rng(0), chance_samples=50)
    assert advice.chance is not None and advice.chance.samples == 50


def test_planner_without_simulator_keeps_its_estimate_rounded(layout):
    advice = plan_shot(layout, "solids", NearestPocketPlanner())
    assert advice.chance is None
    d = advice.to_dict()
    assert d["success_chance"] is None and d["success_text"] == advice.chance_text
    assert advice.chance_text in (">99%", "<1%") or 1 <= int(advice.chance_text[:-1]) <= 99


def test_default_samples_and_bad_skill():
    assert CHANCE_SAMPLES >= 200
    with pytest.raises(ValueError, match="unknown noise model"):
        default_planner(skill="wizard")


def test_a_pot_the_search_found_by_simulation_is_named_other(layout):
    from pix2pockets.pipeline.planning import advice_from_candidate
    from pix2pockets.planner.base import Suggestion
    from pix2pockets.state import Group, Shot

    target = layout.indices_of(Group.SOLIDS.ball_class)[0]
    candidate = Suggestion(Shot(0.3, 2.0), target=target, pocket=2, kind=None)
    advice = advice_from_candidate(candidate, layout, Group.SOLIDS)
    assert advice.kind == "other" and ", other," in advice.describe(tuple(_balls(layout)))


def _balls(layout):
    from pix2pockets.pipeline.result import LocatedBall

    for b, xy in zip(layout.balls, layout.positions, strict=True):
        yield LocatedBall(b.ball_class.value, 1.0, (0, 0, 1, 1), (0, 0), tuple(xy), (0, 0), None, None)


def test_a_blackball_set_plans_by_blackball_rules():
    from pix2pockets.pipeline.planning import default_planner, planner_for_set
    from pix2pockets.state.ball_set import BallSet

    planner = default_planner()
    assert planner_for_set(planner, BallSet.AMERICAN) is planner
    blackball = planner_for_set(planner, BallSet.BLACKBALL)
    assert blackball.config.rules == "blackball" and blackball.simulator is planner.simulator
    assert blackball.config.noise == planner.config.noise


def test_an_unsure_pocket_loses_its_shot_to_a_sure_one(layout):
    """NearestPocketPlanner ranks its shots by distance to the pocket; with that pocket's place unsure (out of the
    photo) the best shot to a pocket in view is played instead."""
    planner = NearestPocketPlanner()
    plain = plan_shot(layout, "solids", planner, np.random.default_rng(0))
    spec = layout.spec
    first = next(i for i, p in enumerate(spec.pockets) if p.name == plain.pocket)
    sigmas = np.zeros(len(spec.pockets))
    assert plan_shot(layout, "solids", planner, np.random.default_rng(0), pocket_sigma=sigmas).pocket == plain.pocket
    sigmas[first] = 0.2
    moved = plan_shot(layout, "solids", planner, np.random.default_rng(0), pocket_sigma=sigmas)
    assert moved.pocket != plain.pocket


def test_a_shot_to_an_unsure_pocket_is_measured_with_its_error(layout):
    planner = default_planner(skill="pro")
    sure = plan_shot(layout, "solids", planner, np.random.default_rng(0), chance_samples=200, position_sigma=0.0)
    assert sure.kind in ("direct", "bank") and sure.chance.pocket_sigma == 0.0
    spec = layout.spec
    sigmas = np.full(len(spec.pockets), 0.15)  # every pocket unsure: the same shot, a lower chance
    unsure = plan_shot(
        layout, "solids", planner, np.random.default_rng(0), chance_samples=200, position_sigma=0.0, pocket_sigma=sigmas
    )
    assert unsure.stroke == sure.stroke and unsure.chance.pocket_sigma == 0.15
    assert unsure.success_probability < sure.success_probability - 0.2
    assert unsure.chance_exact_positions.pocket_sigma == 0.0
    assert unsure.to_dict()["success_chance"]["pocket_sigma_m"] == 0.15


def test_the_advice_shows_where_the_cue_ball_goes_after_the_first_ball(layout):
    planner = default_planner()
    advice = plan_shot(layout, "solids", planner, np.random.default_rng(0), chance_samples=40)
    path = advice.cue_after
    assert path is not None and len(path) >= 2
    assert np.linalg.norm(path[0] - advice.ghost) < 0.02  # it meets the target where the ghost ball lies
    result = planner.simulator.simulate(layout, advice.stroke)
    assert advice.cue_pocketed == result.cue_pocketed
    if not result.cue_pocketed:
        assert np.allclose(path[-1], result.final.positions[result.final_ids.index(layout.cue_index)])
    d = json.loads(json.dumps(advice.to_dict()))["cue_ball_after"]
    assert np.allclose(d["path_m"], np.round(path, 4)) and d["pocketed"] == advice.cue_pocketed
    assert plan_shot(layout, "solids", NearestPocketPlanner()).cue_after is None  # no simulator, no path


def test_a_pot_the_photo_errors_ruin_gives_way_to_the_next_best(layout, monkeypatch):
    """A first candidate the planner rates highly but that pots nothing as played (a stroke off every ball, kind
    "other", so not re-aimed) measures near 0: the next best pot, measured the same way, is suggested instead."""
    from pix2pockets.pipeline import planning
    from pix2pockets.planner.base import Suggestion
    from pix2pockets.state import Group, Shot

    target = layout.indices_of(Group.SOLIDS.ball_class)[0]
    cue = layout.positions[layout.cue_index]
    away = float(np.arctan2(*(cue - layout.positions[target])[::-1]))  # straight away from the target
    fragile = Suggestion(Shot(away, 1.0), target=target, pocket=2, kind=None, success_probability=0.9, value=0.9)

    class FragileFirst:
        def __init__(self, planner):
            self.planner = planner

        def suggest(self, *args, **kwargs):
            return [fragile, *self.planner.suggest(*args, **kwargs)]

    planner = FragileFirst(default_planner())
    advice = plan_shot(layout, "solids", planner, np.random.default_rng(0), chance_samples=60)
    assert advice.stroke != fragile.shot and advice.success_probability > 0.3
    monkeypatch.setattr(planning, "RETRY_SHARE", 0.0)  # never fall back: the fragile pot stays
    kept = plan_shot(layout, "solids", planner, np.random.default_rng(0), chance_samples=60)
    assert kept.stroke == fragile.shot and kept.success_probability < 0.05

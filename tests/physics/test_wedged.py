"""Wedged balls: a ball pinned between another ball and a cushion (or jaw) must settle quickly.

Regression for the env soak's chatter shot (``tests/env/data/event_chatter_shot.json``): the first event
engine let a ball pinned between a rolling ball and the foot cushion bounce back and forth at one
instant (180 308 events). Pressing contacts and settle impacts (``docs/physics.md``, robustness rules)
end such chains; these tests hold the engine to a budget a hundred times smaller.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from pix2pockets.physics.event import EventSimulator
from pix2pockets.state import Ball, Shot, TableLayout

from .conftest import SPEC, R, layout_of

BUDGET = 2_000  # events; the chatter shot needed 180 308
CHATTER = Path(__file__).parents[1] / "env" / "data" / "event_chatter_shot.json"


@pytest.fixture(scope="module")
def tight() -> EventSimulator:
    return EventSimulator(max_events=BUDGET)


def _check(sim: EventSimulator, layout: TableLayout, shot: Shot) -> None:
    """Settles within the budget, energy never rises, no overlap, nothing through a cushion.

    A ball pushed past a cushion-nose line would end "pocketed" mid-rail (the end-of-shot drop rule),
    so every pocketed ball must have dropped at its pocket.
    """
    result, energy = sim.simulate_traced(layout, shot)
    assert np.all(np.diff(energy) <= 1e-12 * max(energy[0], 1e-9))
    pos = result.final.positions
    assert np.all(SPEC.contains(pos, margin=R - 1e-6))
    if len(pos) > 1:
        d = np.linalg.norm(pos[:, None] - pos[None], axis=-1) + 9 * np.eye(len(pos))
        assert d.min() >= 2 * R - 1e-6
    out = sim.simulate_arrays(layout, [shot])
    assert out.status[0] == 0
    assert np.allclose(out.final_positions[0][out.pocket[0] < 0], pos)
    for ball in np.nonzero(out.pocket[0] >= 0)[0]:  # dropped in a pocket, not pushed through a rail
        pocket = SPEC.pockets[out.pocket[0][ball]]
        assert np.linalg.norm(out.final_positions[0][ball] - pocket.centre) < pocket.capture_radius + 2 * R


def test_env_soak_pinned_ball_shot_settles(tight):
    d = json.loads(CHATTER.read_text())
    layout = TableLayout(tuple(Ball.numbered(n) for n in d["numbers"]), d["positions"], SPEC)
    shot = Shot(d["angle"], d["speed"])
    _check(tight, layout, shot)
    rng = np.random.default_rng(5)
    for _ in range(40):  # the neighbourhood of the recorded stroke, with spin
        r, ph = 0.5 * math.sqrt(rng.random()), rng.uniform(0, 2 * math.pi)
        near = Shot(
            d["angle"] + rng.normal(0, 0.03),
            d["speed"] * math.exp(rng.normal(0, 0.3)),
            r * math.cos(ph),
            r * math.sin(ph),
        )
        _check(tight, layout, near)


@pytest.mark.parametrize("speed", [0.002, 0.05, 0.5, 3.0, 11.0])
@pytest.mark.parametrize("height", [-0.4, 0.0, 0.4])
def test_cue_ball_frozen_to_a_ball_frozen_to_the_foot_cushion(tight, speed, height):
    y = 0.4 * SPEC.width
    layout = layout_of((SPEC.length - 3 * R, y), (SPEC.length - R, y))
    _check(tight, layout, Shot(0.0, speed, 0.0, height))
    _check(tight, layout, Shot(0.3, speed, 0.3, height * 0.5))


@pytest.mark.parametrize("speed", [0.05, 0.2, 0.8, 4.0])
@pytest.mark.parametrize("height", [0.0, 0.4])
def test_follow_into_a_ball_frozen_to_the_rail(tight, speed, height):
    """The soak's pattern: a rolling ball with topspin keeps driving into a ball pinned on the rail."""
    x = 0.3 * SPEC.length
    layout = layout_of((x, 0.35), (x, R))
    _check(tight, layout, Shot(-math.pi / 2, speed, 0.0, height))


@pytest.mark.parametrize("speed", [0.02, 0.3, 2.0, 9.0])
def test_three_ball_cluster_against_the_rail(tight, speed):
    x = 0.6 * SPEC.length
    top = (x + R, R + math.sqrt(3) * R)
    layout = layout_of((x + R, 0.5), (x, R), (x + 2 * R, R), top)
    for angle in (-math.pi / 2, -math.pi / 2 + 0.2):
        _check(tight, layout, Shot(angle, speed, 0.0, 0.3))


@pytest.mark.parametrize("speed", [0.02, 0.5, 5.0])
def test_ball_in_the_jaws_pressed_by_another(tight, speed):
    pocket = SPEC.pockets[1]
    centre = np.asarray(pocket.centre)
    inward = np.array([0.0, 1.0]) if centre[1] < SPEC.width / 2 else np.array([0.0, -1.0])
    jawed = np.clip(centre + inward * 0.06, R, SPEC.size - R)
    pusher = jawed + 2 * R * inward
    layout = layout_of(tuple(pusher + 0.3 * inward), tuple(jawed), tuple(pusher))
    angle = math.atan2(-inward[1], -inward[0])
    _check(tight, layout, Shot(angle, speed, 0.0, 0.4))


# Found by benchmarks/wedge_soak.py (seed 1): slow strokes into a ball frozen to a rail; repeated
# nudges of the pressing pair pushed the pinned ball through the cushion, which then "dropped" mid-rail.
THROUGH_THE_RAIL = [
    (
        (2.4544751921261265, 0.40784407051511423),
        (2.511425, 0.4030647522448052),
        (-1.7103, 0.0321, -0.4285, 0.0427, 0.7637),
    ),
    ((1.0099377844582613, 1.2060476495884949), (1.0548216966970756, 1.241425), (2.2070, 0.0140, -0.3112, -0.1921, 0.0)),
    ((0.07345394960150442, 0.7785644542501567), (0.028575, 0.813948099945105), (0.9276, 0.0344, 0.2100, -0.2416, 0.0)),
    ((1.630300154828819, 1.188969381729826), (1.6076168876061772, 1.241425), (0.4748, 0.0106, -0.1643, 0.2628, 0.0)),
]


@pytest.mark.parametrize(("cue", "pinned", "stroke"), THROUGH_THE_RAIL)
def test_pressing_nudges_never_push_a_pinned_ball_through_the_rail(tight, cue, pinned, stroke):
    _check(tight, layout_of(cue, pinned), Shot(*stroke))

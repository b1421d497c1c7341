"""The paper-style pymunk backend."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.physics import Simulator, StopAfter, make_simulator
from pix2pockets.physics.pymunk_backend import PymunkParams, PymunkSimulator
from pix2pockets.state import Ball, EventType, Shot, TableLayout, eight_ball_rack, random_layout


@pytest.fixture(scope="module")
def sim() -> PymunkSimulator:
    return make_simulator("pymunk")


def _layout(*balls: tuple[int, float, float]) -> TableLayout:
    return TableLayout(tuple(Ball.numbered(n) for n, _, _ in balls), [(x, y) for _, x, y in balls])


def test_registered_and_protocol(sim: PymunkSimulator) -> None:
    assert isinstance(sim, Simulator)
    assert sim.name == "pymunk"


def test_straight_in_shot_pockets_into_the_aimed_corner(sim: PymunkSimulator) -> None:
    layout = _layout((0, 0.6, 0.6), (1, 0.3, 0.3))
    result = sim.simulate(layout, Shot.toward((0.6, 0.6), (0.3, 0.3), 2.0))
    assert result.first_contact == 1
    assert 1 in result.pocketed
    assert result.pocketed_into[result.pocketed.index(1)] == 0  # bottom-left corner


def test_head_on_collision_transfers_momentum(sim: PymunkSimulator) -> None:
    layout = _layout((0, 0.5, 0.635), (1, 1.0, 0.635))
    result = sim.simulate(layout, Shot(0.0, 1.0), stop=StopAfter.FIRST_CONTACT)
    assert result.first_contact == 1
    contact = next(e for e in result.events if e.kind is EventType.BALL_BALL)
    assert {contact.ball, contact.other} == {0, 1}
    # full run: the object ball travels much farther than the cue ball (e = 0.95)
    full = sim.simulate(layout, Shot(0.0, 1.0))
    moved = np.abs(full.final.positions - layout.positions[list(full.final_ids)])
    cue_row, obj_row = full.final_ids.index(0), full.final_ids.index(1) if 1 in full.final_ids else None
    if obj_row is not None:
        assert moved[obj_row].sum() > moved[cue_row].sum()


def test_ball_along_rail_stays_on_table(sim: PymunkSimulator) -> None:
    spec = TableLayout((), np.zeros((0, 2))).spec
    r = spec.ball_radius
    layout = _layout((0, 0.5, r + 1e-4))
    result = sim.simulate(layout, Shot(0.0, 3.0))
    # either pocketed in a foot corner or still on the surface (TableLayout validates the bounds)
    assert result.pocketed in ((), (0,))
    if not result.pocketed:
        assert spec.contains(result.final.positions, margin=r - 1e-6).all()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_layouts_end_valid_and_at_rest(sim: PymunkSimulator, seed: int) -> None:
    rng = np.random.default_rng(seed)
    layout = random_layout(rng, list(range(16)))
    shot = Shot(angle=float(rng.uniform(-math.pi, math.pi)), speed=float(rng.uniform(0.5, 8.0)))
    result = sim.simulate(layout, shot)  # the final TableLayout validates overlap and bounds
    assert len(result.final) + len(result.pocketed) == 16
    assert np.all(np.isfinite(result.final.positions))
    assert result.duration > 0
    assert all(0 <= p < 6 for p in result.pocketed_into)


def test_break_shot_settles(sim: PymunkSimulator) -> None:
    result = sim.simulate(eight_ball_rack(), Shot(0.0, 8.0))
    assert result.first_contact is not None
    assert len(result.final) + len(result.pocketed) == 16


def test_deterministic(sim: PymunkSimulator) -> None:
    layout = random_layout(np.random.default_rng(5), list(range(16)))
    a = sim.simulate(layout, Shot(1.0, 4.0))
    b = PymunkSimulator().simulate(layout, Shot(1.0, 4.0))
    assert a.events == b.events
    assert a.final == b.final


def test_batch_matches_single(sim: PymunkSimulator) -> None:
    layout = _layout((0, 0.6, 0.6), (8, 1.5, 0.5))
    shots = [Shot(0.2, 1.0), Shot(-0.4, 2.5)]
    batch = sim.simulate_batch(layout, shots)
    assert [r.events for r in batch] == [sim.simulate(layout, s).events for s in shots]


def test_first_pocket_stops_early(sim: PymunkSimulator) -> None:
    layout = _layout((0, 0.6, 0.6), (1, 0.3, 0.3))
    shot = Shot.toward((0.6, 0.6), (0.3, 0.3), 2.0)
    early = sim.simulate(layout, shot, stop=StopAfter.FIRST_POCKET)
    full = sim.simulate(layout, shot)
    assert early.pocketed == (1,)
    assert early.duration < full.duration


def test_no_contact_shot(sim: PymunkSimulator) -> None:
    layout = _layout((0, 0.6, 0.6), (1, 2.0, 1.0))
    result = sim.simulate(layout, Shot(-math.pi / 2, 0.3), stop=StopAfter.FIRST_CONTACT)
    assert result.first_contact is None


def test_no_cue_ball_is_an_error(sim: PymunkSimulator) -> None:
    with pytest.raises(ValueError, match="no cue ball"):
        sim.simulate(_layout((1, 0.6, 0.6)), Shot(0.0, 1.0))


def test_time_cap_raises_clear_error() -> None:
    sim = PymunkSimulator(PymunkParams(max_time=0.5))
    with pytest.raises(RuntimeError, match="did not settle"):
        sim.simulate(_layout((0, 0.6, 0.6)), Shot(0.3, 3.0))


@pytest.mark.parametrize(
    "field,value",
    [("ball_restitution", 1.5), ("damping", 1.0), ("damping", 0.0), ("substep", 0.0), ("rest_check_every", 0)],
)
def test_bad_params(field: str, value: float) -> None:
    with pytest.raises(ValueError, match=field):
        PymunkParams(**{field: value})

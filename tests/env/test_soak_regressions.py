"""Shots the soak run found to fail, kept as regression cases for the physics backends."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pix2pockets.physics import make_simulator
from pix2pockets.state import Ball, Shot, TableLayout

DATA = Path(__file__).parent / "data"


def _case(name: str) -> tuple[TableLayout, Shot]:
    d = json.loads((DATA / name).read_text())
    layout = TableLayout(tuple(Ball.numbered(n) for n in d["numbers"]), d["positions"])
    return layout, Shot(d["angle"], d["speed"])


def test_pymunk_settles_the_pinned_ball_case() -> None:
    layout, shot = _case("event_chatter_shot.json")
    result = make_simulator("pymunk").simulate(layout, shot)
    assert len(result.final) + len(result.pocketed) == 16


@pytest.mark.xfail(reason="event backend: a ball pinned between a ball and a cushion chatters past max_events")
def test_event_settles_the_pinned_ball_case() -> None:
    layout, shot = _case("event_chatter_shot.json")
    result = make_simulator("event").simulate(layout, shot)
    assert len(result.final) + len(result.pocketed) == 16

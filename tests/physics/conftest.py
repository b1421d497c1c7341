"""Shared helpers for the physics tests."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.geometry.table import TableSpec
from pix2pockets.physics import available_simulators, make_simulator
from pix2pockets.state import Ball, TableLayout

SPEC = TableSpec()
R = SPEC.ball_radius


@pytest.fixture(params=available_simulators())
def sim(request):
    """Every registered backend."""
    return make_simulator(request.param)


def layout_of(*points: tuple[float, float]) -> TableLayout:
    """Cue ball at the first point, then balls 1, 2, ... at the others."""
    balls = (Ball.numbered(0), *(Ball.numbered(k) for k in range(1, len(points))))
    return TableLayout(balls, np.array(points, dtype=float), SPEC)


def straight_in_layout() -> tuple[TableLayout, float]:
    """Object ball 0.5 m out from the bottom-right corner pocket, cue 0.5 m behind it on the same line.

    Returns the layout and the shot angle [rad].
    """
    aim = SPEC.pockets[2].aim
    into_table = np.array([-1.0, 1.0]) / math.sqrt(2)
    obj = aim + 0.5 * into_table
    cue = obj + 0.5 * into_table
    angle = math.atan2(-into_table[1], -into_table[0])
    return layout_of(tuple(cue), tuple(obj)), angle

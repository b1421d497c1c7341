"""Soak test of the event backend: thousands of random shots, every outcome valid (``-m slow``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.physics.event import EventSimulator
from pix2pockets.state import Ball, TableLayout, eight_ball_rack, random_layout

from .conftest import SPEC, R


def _cluster(rng: np.random.Generator, n: int = 10) -> TableLayout:
    """Balls grown into a cluster of mutually touching balls (some frozen to a rail)."""
    pts = [(rng.uniform(0.3, SPEC.length - 0.3), rng.uniform(0.2, SPEC.width - 0.2))]
    while len(pts) < n:
        base = pts[rng.integers(len(pts))]
        a = rng.uniform(0, 2 * math.pi)
        p = (
            min(max(base[0] + 2 * R * math.cos(a), R), SPEC.length - R),
            min(max(base[1] + 2 * R * math.sin(a), R), SPEC.width - R),
        )
        if 0.2 < p[0] < SPEC.length - 0.2 and all(math.dist(p, q) >= 2 * R - 1e-9 for q in pts):
            pts.append(p)
    return TableLayout(tuple(Ball.numbered(k) for k in range(n)), np.array(pts), SPEC)


def _rail_row(n: int = 8) -> TableLayout:
    pts = [(0.15 + k * 0.28, R if k % 2 == 0 else SPEC.width - R) for k in range(n)]
    return TableLayout(tuple(Ball.numbered(k) for k in range(n)), np.array(pts), SPEC)


@pytest.mark.slow
def test_soak_random_shots_stay_valid():
    sim = EventSimulator()
    rng = np.random.default_rng(2024)
    for it in range(160):
        kind = it % 4
        if kind == 0:
            layout = random_layout(rng, list(range(int(rng.integers(2, 17)))))
        elif kind == 1:
            layout = eight_ball_rack(SPEC, rng)
        elif kind == 2:
            layout = _cluster(rng)
        else:
            layout = _rail_row()
        m = 40
        shots = np.zeros((m, 5))
        target = rng.integers(1, len(layout), m)
        d = layout.positions[target] - layout.positions[0]
        at_ball = np.arctan2(d[:, 1], d[:, 0]) + rng.normal(0, 0.05, m)
        shots[:, 0] = np.where(rng.random(m) < 0.6, at_ball, rng.uniform(-np.pi, np.pi, m))
        shots[:, 1] = np.exp(rng.uniform(np.log(0.01), np.log(11.5), m))
        radius, phase = np.sqrt(rng.random(m)) * 0.5, rng.uniform(0, 2 * np.pi, m)
        shots[:, 2], shots[:, 3] = radius * np.cos(phase), radius * np.sin(phase)
        shots[:, 4] = np.where(rng.random(m) < 0.2, rng.uniform(0, 1.2, m), 0.0)
        out = sim.simulate_arrays(layout, shots)
        assert np.all(out.status == 0), f"layout {it}: status {out.status}"
        for k in range(m):
            keep = out.pocket[k] < 0
            assert np.all(np.isfinite(out.final_positions[k]))
            balls = tuple(b for b, kept in zip(layout.balls, keep, strict=True) if kept)
            TableLayout(balls, out.final_positions[k][keep], SPEC)  # raises on overlap / off-table

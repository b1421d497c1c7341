"""Observation encoding: fixed slots, absent balls, units."""

from __future__ import annotations

import numpy as np

from pix2pockets.env.observation import (
    CLASS_CODE,
    ObsUnits,
    assign_slots,
    encode,
    observation_space,
)
from pix2pockets.geometry.raster import table_to_env_pixels
from pix2pockets.state import Ball, BallClass, Group, TableLayout, random_layout


def test_numbered_balls_take_their_slots() -> None:
    layout = random_layout(np.random.default_rng(0), list(range(16)))
    assert assign_slots(layout, Group.SOLIDS) == list(range(16))
    stripes = assign_slots(layout, Group.STRIPES)
    assert stripes[0] == 0 and stripes[8] == 8
    assert stripes[9] == 1 and stripes[1] == 9  # own stripes first


def test_encoding_positions_classes_and_absent() -> None:
    balls = (Ball.numbered(0), Ball.numbered(8), Ball.numbered(3), Ball.numbered(12))
    pos = [(0.5, 0.5), (2.0, 1.0), (1.0, 0.3), (1.5, 0.9)]
    layout = TableLayout(balls, pos)
    slots = assign_slots(layout, Group.SOLIDS)
    flat = encode(layout, slots)
    assert flat.shape == (48,) and flat.dtype == np.float32
    assert observation_space().contains(flat)
    obs = flat.reshape(16, 3)
    assert np.allclose(obs[0], [0.5 / layout.spec.length, 0.5 / layout.spec.width, CLASS_CODE["cue"]])
    assert obs[3, 2] == CLASS_CODE["own"] and obs[8, 2] == CLASS_CODE["black"]
    assert obs[12, 2] == CLASS_CODE["opponent"]
    absent = [s for s in range(16) if s not in slots]
    assert np.all(obs[absent] == [-1, -1, 0])


def test_unnumbered_balls_fill_slots_by_position() -> None:
    balls = (Ball(BallClass.CUE), Ball(BallClass.SOLID), Ball(BallClass.SOLID), Ball(BallClass.STRIPE))
    layout = TableLayout(balls, [(0.5, 0.5), (2.0, 1.0), (1.0, 0.3), (1.5, 0.9)])
    assert assign_slots(layout, Group.SOLIDS) == [0, 2, 1, 9]


def test_paper_pixels() -> None:
    layout = random_layout(np.random.default_rng(1), [0, 8])
    obs = encode(layout, assign_slots(layout, None), ObsUnits.PAPER_PIXELS)
    assert np.allclose(obs[:2], table_to_env_pixels(layout.positions[0]), atol=1e-3)
    assert observation_space(ObsUnits.PAPER_PIXELS).contains(obs)

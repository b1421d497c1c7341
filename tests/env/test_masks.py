"""Action masks from hitpoints (MaskablePPO)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from pix2pockets.env.masks import MaskKind, cue_pocket_angles, direction_mask
from pix2pockets.env.pool_env import PoolEnv
from pix2pockets.state import Ball, TableLayout
from tests.env.conftest import FAST_PHYSICS


def _two_ball() -> TableLayout:
    return TableLayout((Ball.numbered(0), Ball.numbered(8)), [(0.6, 0.6), (0.3, 0.3)])


def test_direction_mask_bins_and_width() -> None:
    mask = direction_mask(np.array([0.0]), 36000, width=2)
    assert mask.sum() == 5 and mask[18000] and mask[17998] and mask[18002]
    wrap = direction_mask(np.array([math.pi]), 36000)
    assert wrap[0] and wrap.sum() == 1
    assert direction_mask(np.zeros(0), 100).all()  # never empty


def test_two_ball_mask_points_at_the_straight_in_shot() -> None:
    env = PoolEnv(balls="two", **FAST_PHYSICS)
    env.reset(seed=0, options={"layout": _two_ball()})
    mask = env.action_masks()
    assert mask.shape == (36000 + 30,) and mask[36000:].all()
    allowed = np.flatnonzero(mask[:36000])
    straight = int(env.actions.bin_of_angle(math.atan2(-0.3, -0.3)))
    assert straight in allowed or any(abs(int(a) - straight) <= 1 for a in allowed)
    # every allowed direction of this layout pots the 8
    for a in allowed[:3]:
        env.reset(seed=0, options={"layout": _two_ball()})
        *_, info = env.step(np.array([a, 6]))
        assert info["outcome"] == "win"


def test_mirror_mask_adds_bank_and_kick_bins() -> None:
    layout = TableLayout((Ball.numbered(0), Ball.numbered(8)), [(1.0, 0.4), (1.6, 0.8)])
    direct = PoolEnv(balls="two", mask_kind="direct", **FAST_PHYSICS)
    mirror = PoolEnv(balls="two", mask_kind="mirror", **FAST_PHYSICS)
    direct.reset(seed=0, options={"layout": layout})
    mirror.reset(seed=0, options={"layout": layout})
    d, m = direct.action_masks(), mirror.action_masks()
    assert m[:36000].sum() > d[:36000].sum()
    assert np.all(m[d])  # mirror includes every direct bin


def test_one_ball_mask_pockets_the_cue_ball() -> None:
    env = PoolEnv(balls="one", **FAST_PHYSICS)
    env.reset(seed=0, options={"layout": TableLayout((Ball.numbered(0),), [(0.5, 0.4)])})
    allowed = np.flatnonzero(env.action_masks()[:36000])
    assert len(allowed) == 6
    wins = 0
    for a in allowed:
        env.reset(seed=0, options={"layout": TableLayout((Ball.numbered(0),), [(0.5, 0.4)])})
        *_, info = env.step(np.array([a, 20]))
        wins += info["is_success"]
    assert wins >= 5  # a long shot at the far side pocket may rattle the jaws
    layout = TableLayout((Ball.numbered(0),), [(0.5, 0.4)])
    assert len(cue_pocket_angles(layout, MaskKind.MIRROR)) == 30


@dataclass(frozen=True)
class _FakeHitpoint:
    target: int
    pocket: int
    kind: str
    cue_angle: float


def test_custom_hitpoint_finder() -> None:
    calls = []

    def finder(layout, targets, kinds):
        calls.append((list(targets), tuple(kinds)))
        return [_FakeHitpoint(targets[0], 0, "direct", 0.0)]

    env = PoolEnv(balls="all", hitpoint_finder=finder, mask_kind="mirror", **FAST_PHYSICS)
    env.reset(seed=0)
    mask = env.action_masks()
    assert np.flatnonzero(mask[:36000]).tolist() == [18000]
    assert calls and calls[0][1] == ("direct", "bank", "kick")
    assert sorted(calls[0][0]) == sorted(env.targets())


def test_masks_need_discrete_actions() -> None:
    env = PoolEnv(balls="two", action_type="continuous", **FAST_PHYSICS)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="discrete"):
        env.action_masks()

"""The paper's reward terms on hand-made shot results."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.env.reward import BallSetup, PaperReward, RewardFn, ShotContext, contact_departure
from pix2pockets.state import Ball, Event, EventType, Shot, ShotResult, TableLayout


def _result(events: list[Event], final: list[tuple[float, float]]) -> ShotResult:
    layout = TableLayout((Ball.numbered(0), Ball.numbered(8)), [(0.6, 0.6), (0.3, 0.3)])
    return ShotResult.from_events(layout, events, np.array(final))


def _ctx(result: ShotResult, shot: Shot, **kw) -> ShotContext:
    base = {"won": False, "lost": False, "succeeded": False, "turn": None, "targets": (1,)}
    base.update(kw)
    return ShotContext(
        BallSetup.TWO,
        shot,
        result,
        base["targets"],
        base["turn"],
        base["won"],
        base["lost"],
        base["succeeded"],
        contact_departure(result, shot),
    )


def test_paper_reward_is_a_reward_fn() -> None:
    assert isinstance(PaperReward(), RewardFn)


def test_no_hit_penalty_scales_with_distance() -> None:
    res = _result([Event(1.0, EventType.BALL_CUSHION, 0, 2)], [(1.6, 0.3), (0.3, 0.3)])
    terms = PaperReward().terms(_ctx(res, Shot(0.0, 1.0)))
    assert terms == {"no_hit": pytest.approx(-50 * 1.3 / res.initial.spec.diagonal)}


def test_angle_term_for_a_cut() -> None:
    # cue from (0.6, 0.6) aimed a little off the line of centres: the 8 leaves along the contact normal
    shot = Shot(math.atan2(-0.3, -0.3) + 0.05, 1.0)
    res = _result([Event(0.3, EventType.BALL_BALL, 0, 1)], [(0.5, 0.5), (1.0, 1.0)])
    departure = contact_departure(res, shot)
    assert departure is not None and abs(np.hypot(*departure) - 1) < 1e-12
    terms = PaperReward().terms(_ctx(res, shot))
    assert terms["hit"] == 10
    assert -50 < terms["angle"] < 50


def test_clip_and_normalise() -> None:
    res = _result([Event(0.3, EventType.BALL_BALL, 0, 1), Event(1.0, EventType.POCKET, 1, 0)], [(0.5, 0.5), (0, 0)])
    ctx = _ctx(res, Shot.toward((0.6, 0.6), (0.3, 0.3), 1.0), won=True, succeeded=True)
    assert sum(PaperReward().terms(ctx).values()) == pytest.approx(210.0)  # the best possible shot
    assert PaperReward()(ctx) == pytest.approx(1.0)
    assert PaperReward(clip=150.0)(ctx) == 1.0
    assert PaperReward(clip=150.0, normalize=False)(ctx) == 150.0


def test_scratch_is_a_loss_with_cue_penalty() -> None:
    res = _result([Event(0.5, EventType.BALL_BALL, 0, 1), Event(1.0, EventType.POCKET, 0, 3)], [(0, 0), (0.4, 0.2)])
    terms = PaperReward().terms(_ctx(res, Shot.toward((0.6, 0.6), (0.3, 0.3), 1.0), lost=True))
    assert terms["loss"] == -100 and terms["cue_pocketed"] == -80


def test_kick_has_no_departure() -> None:
    res = _result(
        [Event(0.2, EventType.BALL_CUSHION, 0, 1), Event(0.5, EventType.BALL_BALL, 0, 1)], [(0.5, 0.5), (1, 1)]
    )
    assert contact_departure(res, Shot(-math.pi / 2, 1.0)) is None

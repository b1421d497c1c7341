import math

import pytest

from pix2pockets.state import Ball, Event, EventType, Shot, ShotResult, TableLayout


def test_shot_validation():
    Shot(0.0, 2.0, side=0.3, height=-0.3)
    with pytest.raises(ValueError, match="speed"):
        Shot(0.0, -1.0)
    with pytest.raises(ValueError, match="miscue"):
        Shot(0.0, 1.0, side=0.5, height=0.5)
    with pytest.raises(ValueError, match="finite"):
        Shot(math.nan, 1.0)


def test_shot_toward():
    s = Shot.toward((0.0, 0.0), (1.0, 1.0), 2.0)
    assert s.angle_deg == pytest.approx(45.0)


def test_result_from_events():
    lay = TableLayout((Ball.numbered(0), Ball.numbered(1), Ball.numbered(2)), [[0.5, 0.5], [1.0, 0.5], [2.0, 1.0]])
    events = [
        Event(0.0, EventType.CUE_STRIKE, 0),
        Event(0.3, EventType.BALL_BALL, 0, 1),
        Event(0.9, EventType.BALL_CUSHION, 1, 2),
        Event(1.2, EventType.POCKET, 1, 3),
    ]
    res = ShotResult.from_events(lay, events, [[0.8, 0.5], [2.5, 1.2], [2.0, 1.0]])
    assert res.first_contact == 1
    assert res.pocketed == (1,)
    assert res.pocketed_into == (3,)
    assert res.rail_after_contact
    assert res.final_ids == (0, 2)
    assert len(res.final) == 2
    assert not res.cue_pocketed
    assert res.rails_touched == (1,)
    assert res.duration == pytest.approx(1.2)


def test_result_without_revalidation_matches_and_user_layouts_are_still_checked():
    lay = TableLayout((Ball.numbered(0), Ball.numbered(1), Ball.numbered(2)), [[0.5, 0.5], [1.0, 0.5], [2.0, 1.0]])
    events = [Event(0.0, EventType.CUE_STRIKE, 0), Event(0.5, EventType.POCKET, 2, 3)]
    final = [[0.6, 0.5], [1.2, 0.6], [9.0, 9.0]]
    checked = ShotResult.from_events(lay, events, final)
    fast = ShotResult.from_events(lay, events, final, validate=False)
    assert fast.final == checked.final and fast.final_ids == checked.final_ids == (0, 1)
    assert not fast.final.positions.flags.writeable
    with pytest.raises(ValueError, match="overlap"):  # the validating path still rejects bad layouts
        ShotResult.from_events(lay, events, [[0.6, 0.5], [0.61, 0.5], [9.0, 9.0]])
    with pytest.raises(ValueError, match="off the playing surface"):
        TableLayout((Ball.numbered(0),), [[-1.0, 0.5]])

"""Blackball (WEPF) rules on hand-made shot results: where they differ from 8-ball, and where they agree."""

import numpy as np
import pytest

from pix2pockets.rules import (
    PENALTY_VISITS,
    Foul,
    GameState,
    InHand,
    Outcome,
    blackball_turn_outcome,
    judge_for,
    turn_outcome,
)
from pix2pockets.state import Ball, Event, EventType, Group, ShotResult, TableLayout

# index: 0 cue, 1 black, 2 red (solid slot), 3 red, 4 yellow (stripe slot)
FULL = (Ball.numbered(0), Ball.numbered(8), Ball.numbered(1), Ball.numbered(2), Ball.numbered(9))
POS = np.array([[0.5, 0.5], [1.0, 0.5], [1.5, 0.5], [2.0, 0.5], [1.5, 1.0]])
REDS_CLEARED = (Ball.numbered(0), Ball.numbered(8), Ball.numbered(9))
POS_CLEARED = POS[[0, 1, 4]]
R, Y = Group.SOLIDS, Group.STRIPES


def shot(balls, pos, first=None, rail=False, pocketed=()):
    lay = TableLayout(balls, pos)
    events = [Event(0.0, EventType.CUE_STRIKE, 0)]
    if first is not None:
        events.append(Event(0.1, EventType.BALL_BALL, 0, first))
    if rail:
        events.append(Event(0.2, EventType.BALL_CUSHION, first if first is not None else 0, 0))
    for k, i in enumerate(pocketed):
        events.append(Event(0.3 + 0.1 * k, EventType.POCKET, i, 0))
    return ShotResult.from_events(lay, events, pos)


CASES = [
    # name, balls, pos, group, first, rail, pocketed, outcome, fouls, group_after
    ("legal pot continues", FULL, POS, R, 2, False, (2,), Outcome.CONTINUE, (), R),
    ("legal miss with rail ends turn", FULL, POS, R, 2, True, (), Outcome.END_TURN, (), R),
    ("no rail after contact", FULL, POS, R, 2, False, (), Outcome.FOUL, (Foul.NO_RAIL_AFTER_CONTACT,), R),
    ("opponent ball only is a foul", FULL, POS, R, 2, True, (4,), Outcome.FOUL, (Foul.OPPONENT_POTTED,), R),
    ("own and opponent ball is a foul", FULL, POS, R, 2, True, (2, 4), Outcome.FOUL, (Foul.OPPONENT_POTTED,), R),
    ("wrong first contact", FULL, POS, R, 4, True, (), Outcome.FOUL, (Foul.WRONG_FIRST_CONTACT,), R),
    ("scratch", FULL, POS, R, 2, True, (0,), Outcome.FOUL, (Foul.SCRATCH,), R),
    ("open table: both colours drop", FULL, POS, None, 2, True, (4, 2), Outcome.CONTINUE, (), Y),
    ("early black loses", FULL, POS, R, 2, True, (1,), Outcome.LOSS, (), R),
    ("legal black wins", REDS_CLEARED, POS_CLEARED, R, 1, True, (1,), Outcome.WIN, (), R),
    (
        "black with opponent ball loses",
        REDS_CLEARED,
        POS_CLEARED,
        R,
        1,
        True,
        (1, 2),
        Outcome.LOSS,
        (Foul.OPPONENT_POTTED,),
        R,
    ),
]


@pytest.mark.parametrize(
    ("name", "balls", "pos", "group", "first", "rail", "pocketed", "outcome", "fouls", "group_after"),
    CASES,
    ids=[c[0] for c in CASES],
)
def test_blackball_turn_outcome(name, balls, pos, group, first, rail, pocketed, outcome, fouls, group_after) -> None:
    turn = blackball_turn_outcome(shot(balls, pos, first, rail, pocketed), GameState(group))
    assert turn.outcome is outcome
    assert turn.fouls == fouls
    assert turn.group is group_after
    assert turn.penalty_visits == (PENALTY_VISITS if outcome is Outcome.FOUL else 0)


def test_a_foul_gives_two_visits_in_blackball_and_ball_in_hand_in_eight_ball() -> None:
    res = shot(FULL, POS, 2, True, (0,))
    assert blackball_turn_outcome(res, GameState(R)).penalty_visits == 2
    assert turn_outcome(res, GameState(R)).penalty_visits == 1
    assert turn_outcome(res, GameState(R)).ball_in_hand


def test_after_a_foul_the_cue_ball_is_in_hand_in_baulk_only_when_it_dropped() -> None:
    """WEPF: a foul leaves the cue ball where it lies; a dropped cue ball is played from baulk. 8-ball: in hand."""
    dropped = shot(FULL, POS, 2, True, (0,))
    lies = shot(FULL, POS, 4, True, ())
    assert blackball_turn_outcome(dropped, GameState(R)).in_hand is InHand.BAULK
    assert blackball_turn_outcome(dropped, GameState(R)).ball_in_hand
    assert blackball_turn_outcome(lies, GameState(R)).in_hand is InHand.NONE
    assert not blackball_turn_outcome(lies, GameState(R)).ball_in_hand
    assert turn_outcome(lies, GameState(R)).in_hand is InHand.TABLE
    assert not blackball_turn_outcome(shot(FULL, POS, 2, True, (2,)), GameState(R)).ball_in_hand  # no foul


def test_the_ball_set_picks_the_rules() -> None:
    res = shot(FULL, POS, 2, True, (4,))
    assert judge_for("american")(res, GameState(R)).outcome is Outcome.END_TURN
    assert judge_for("blackball")(res, GameState(R)).outcome is Outcome.FOUL
    with pytest.raises(ValueError, match="unknown ball set"):
        judge_for("snooker")

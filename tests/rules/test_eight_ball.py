"""Table-driven tests of the 8-ball rules on hand-made shot results."""

import numpy as np
import pytest

from pix2pockets.rules import Foul, GameState, Outcome, turn_outcome
from pix2pockets.state import Ball, Event, EventType, Group, ShotResult, TableLayout

# index: 0 cue, 1 black, 2 solid(1), 3 solid(2), 4 stripe(9)
FULL = (Ball.numbered(0), Ball.numbered(8), Ball.numbered(1), Ball.numbered(2), Ball.numbered(9))
POS = np.array([[0.5, 0.5], [1.0, 0.5], [1.5, 0.5], [2.0, 0.5], [1.5, 1.0]])
# only cue, black and one stripe: solids cleared
SOLIDS_CLEARED = (Ball.numbered(0), Ball.numbered(8), Ball.numbered(9))
POS_CLEARED = POS[[0, 1, 4]]
# cue, black, one solid: last own ball for solids
LAST_SOLID = (Ball.numbered(0), Ball.numbered(8), Ball.numbered(1))
POS_LAST = POS[[0, 1, 2]]


def shot(balls, pos, first=None, rail=False, pocketed=()):
    lay = TableLayout(balls, pos)
    events = [Event(0.0, EventType.CUE_STRIKE, 0)]
    t = 0.1
    if first is not None:
        events.append(Event(t, EventType.BALL_BALL, 0, first))
    if rail:
        events.append(Event(t + 0.1, EventType.BALL_CUSHION, first if first is not None else 0, 0))
    for k, i in enumerate(pocketed):
        events.append(Event(t + 0.2 + 0.1 * k, EventType.POCKET, i, 0))
    return ShotResult.from_events(lay, events, pos)


S, T = Group.SOLIDS, Group.STRIPES
CASES = [
    # name, balls, pos, group, first, rail, pocketed, outcome, fouls, group_after
    ("legal pot continues", FULL, POS, S, 2, False, (2,), Outcome.CONTINUE, (), S),
    ("legal miss with rail ends turn", FULL, POS, S, 2, True, (), Outcome.END_TURN, (), S),
    ("no rail after contact", FULL, POS, S, 2, False, (), Outcome.FOUL, (Foul.NO_RAIL_AFTER_CONTACT,), S),
    ("no contact", FULL, POS, S, None, True, (), Outcome.FOUL, (Foul.NO_CONTACT,), S),
    ("wrong first contact", FULL, POS, S, 4, True, (), Outcome.FOUL, (Foul.WRONG_FIRST_CONTACT,), S),
    ("pot after wrong contact is foul", FULL, POS, S, 4, True, (2,), Outcome.FOUL, (Foul.WRONG_FIRST_CONTACT,), S),
    ("scratch", FULL, POS, S, 2, True, (0,), Outcome.FOUL, (Foul.SCRATCH,), S),
    ("pot and scratch", FULL, POS, S, 2, True, (2, 0), Outcome.FOUL, (Foul.SCRATCH,), S),
    ("opponent ball only ends turn", FULL, POS, S, 2, True, (4,), Outcome.END_TURN, (), S),
    ("own and opponent ball continue", FULL, POS, S, 2, True, (4, 2), Outcome.CONTINUE, (), S),
    ("early 8 loses", FULL, POS, S, 2, True, (1,), Outcome.LOSS, (), S),
    ("8 with last own ball loses", LAST_SOLID, POS_LAST, S, 2, True, (2, 1), Outcome.LOSS, (), S),
    ("8 first hit before clear", FULL, POS, S, 1, True, (), Outcome.FOUL, (Foul.WRONG_FIRST_CONTACT,), S),
    ("legal 8 wins", SOLIDS_CLEARED, POS_CLEARED, S, 1, True, (1,), Outcome.WIN, (), S),
    ("8 with scratch loses", SOLIDS_CLEARED, POS_CLEARED, S, 1, True, (1, 0), Outcome.LOSS, (Foul.SCRATCH,), S),
    (
        "8 after wrong contact loses",
        SOLIDS_CLEARED,
        POS_CLEARED,
        S,
        2,
        True,
        (1,),
        Outcome.LOSS,
        (Foul.WRONG_FIRST_CONTACT,),
        S,
    ),
    (
        "cleared group must hit 8",
        SOLIDS_CLEARED,
        POS_CLEARED,
        S,
        2,
        True,
        (),
        Outcome.FOUL,
        (Foul.WRONG_FIRST_CONTACT,),
        S,
    ),
    ("open table: pot assigns stripes", FULL, POS, None, 4, False, (4,), Outcome.CONTINUE, (), T),
    ("open table: first drop decides", FULL, POS, None, 2, False, (3, 4), Outcome.CONTINUE, (), S),
    ("open table: 8 first is a foul", FULL, POS, None, 1, True, (), Outcome.FOUL, (Foul.WRONG_FIRST_CONTACT,), None),
    ("open table: 8 drops loses", FULL, POS, None, 2, True, (1,), Outcome.LOSS, (), None),
    ("open table: miss keeps it open", FULL, POS, None, 4, True, (), Outcome.END_TURN, (), None),
    ("open table: foul pot no group", FULL, POS, None, 4, True, (4, 0), Outcome.FOUL, (Foul.SCRATCH,), None),
]


@pytest.mark.parametrize(
    ("balls", "pos", "group", "first", "rail", "pocketed", "outcome", "fouls", "group_after"),
    [c[1:] for c in CASES],
    ids=[c[0] for c in CASES],
)
def test_turn_outcome(balls, pos, group, first, rail, pocketed, outcome, fouls, group_after):
    res = turn_outcome(shot(balls, pos, first, rail, pocketed), GameState(group))
    assert res.outcome is outcome
    assert res.fouls == fouls
    assert res.group == group_after
    assert res.ball_in_hand == (outcome is Outcome.FOUL)


def test_legal_pots_listed():
    res = turn_outcome(shot(FULL, POS, 2, True, (4, 2, 3)), GameState(S))
    assert res.legal_pots == (2, 3)
    assert res.shot_succeeded

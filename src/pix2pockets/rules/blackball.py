"""Blackball (UK 8-ball) rules, as played under the World Eightball Pool Federation (WEPF) rules.

Reds and yellows play as the two groups (:mod:`pix2pockets.state.ball_set`: reds in the solids' slot, yellows in
the stripes'). A shot is judged as under :mod:`pix2pockets.rules.eight_ball`, with the WEPF differences that
matter to one shot:

* with the groups decided, potting an opponent's ball is a foul (:attr:`Foul.OPPONENT_POTTED`), even when an own
  ball drops too;
* a foul gives the opponent **two visits** (``penalty_visits=2``); the cue ball is played from where it lies, or,
  when it dropped, from anywhere behind the baulk line (``in_hand=InHand.BAULK``; WEPF rules, "Playing from
  Baulk");
* an open table is decided by the first colour potted on a legal shot; both colours may drop on it.

The rest is common to both games: the cue ball must first hit a ball on (any colour on an open table, the black
once the group is cleared), a ball must be potted or reach a cushion after contact, the cue ball must not drop,
and the black wins only on a legal shot after the group was cleared (else the frame is lost).
"""

from __future__ import annotations

from pix2pockets.rules.eight_ball import Foul, GameState, InHand, TurnResult, judge_turn, shot_fouls
from pix2pockets.state.result import ShotResult

PENALTY_VISITS = 2
"""Visits the opponent gets after a foul (WEPF)."""


def opponent_potted(result: ShotResult, state: GameState) -> bool:
    """With the groups decided, a ball of the opponent's group dropped."""
    if state.group is None:
        return False
    other = state.group.other
    return any(result.initial.balls[i].group is other for i in result.pocketed)


def blackball_shot_fouls(result: ShotResult, state: GameState) -> tuple[Foul, ...]:
    """All fouls of a shot under blackball rules, in a fixed order."""
    fouls = shot_fouls(result, state)
    return (*fouls, Foul.OPPONENT_POTTED) if opponent_potted(result, state) else fouls


def blackball_turn_outcome(result: ShotResult, state: GameState) -> TurnResult:
    """Judge one shot under blackball rules: win, loss, foul (two visits), continue or end of turn."""
    fouls = blackball_shot_fouls(result, state)
    in_hand = InHand.BAULK if Foul.SCRATCH in fouls else InHand.NONE
    return judge_turn(result, state, fouls, PENALTY_VISITS, in_hand)

"""8-ball rules as small pure predicates over a finished shot.

A turn is judged from the :class:`~pix2pockets.state.ShotResult` and the shooter's
:class:`GameState` before the shot. Conventions (WPA-style, no called pockets, no break rules):

* open table (no group yet): the first ball contacted must be a solid or a stripe (not the 8);
  the first object ball pocketed on a legal shot assigns the group;
* group assigned: the first contact must be an own ball, or the 8 once the group is cleared;
* after contact a ball must be pocketed or some ball must touch a cushion;
* the cue ball must not drop (scratch); any foul gives the opponent ball in hand anywhere on the table;
* pocketing the 8 wins only when the group was cleared **before** the shot and the shot is foul-free;
  otherwise (early 8, or 8 on a foul) the shooter loses - even if the last own ball drops on the same
  shot;
* the turn continues after a legal shot that pockets at least one own ball (any object ball on an open
  table).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from pix2pockets.state.ball import BallClass, Group
from pix2pockets.state.layout import TableLayout
from pix2pockets.state.result import ShotResult


class Foul(StrEnum):
    NO_CONTACT = "no_contact"
    WRONG_FIRST_CONTACT = "wrong_first_contact"
    NO_RAIL_AFTER_CONTACT = "no_rail_after_contact"
    SCRATCH = "scratch"
    OPPONENT_POTTED = "opponent_potted"  # blackball rules only


class InHand(StrEnum):
    """Where the incoming player may place the cue ball after a foul."""

    NONE = "none"  # nowhere: the cue ball is played from where it lies
    TABLE = "table"  # anywhere free on the table
    BAULK = "baulk"  # anywhere free behind the baulk line (blackball, after the cue ball dropped)


class Outcome(StrEnum):
    CONTINUE = "continue"  # legal pot: shoot again
    END_TURN = "end_turn"  # legal miss: opponent shoots from where the cue ball lies
    FOUL = "foul"  # opponent gets ball in hand
    WIN = "win"
    LOSS = "loss"


@dataclass(frozen=True, slots=True)
class GameState:
    """The shooter's state before a shot.

    Attributes:
        group: the shooter's group, or ``None`` while the table is open.
    """

    group: Group | None = None


@dataclass(frozen=True, slots=True)
class TurnResult:
    """How a shot ends.

    Attributes:
        outcome: what happens next.
        group: the shooter's group after the shot (assigned on an open table by a legal pot).
        fouls: the fouls committed, empty for a legal shot.
        legal_pots: indices (into the initial layout) of own balls legally pocketed.
        penalty_visits: after a foul, the visits the opponent gets (1: ball in hand under 8-ball rules; 2 under
            blackball rules); 0 otherwise.
        in_hand: after a foul, where the opponent may place the cue ball (anywhere under 8-ball rules; under
            blackball rules behind the baulk line when the cue ball dropped, else nowhere).
    """

    outcome: Outcome
    group: Group | None
    fouls: tuple[Foul, ...]
    legal_pots: tuple[int, ...]
    penalty_visits: int = 0
    in_hand: InHand = InHand.NONE

    @property
    def ball_in_hand(self) -> bool:
        """Whether the opponent places the cue ball (:attr:`in_hand` names where)."""
        return self.outcome is Outcome.FOUL and self.in_hand is not InHand.NONE

    @property
    def shot_succeeded(self) -> bool:
        """A legal pot of an own ball (or the winning 8)."""
        return self.outcome in (Outcome.CONTINUE, Outcome.WIN)


def own_balls(layout: TableLayout, group: Group | None) -> list[int]:
    """Indices of the group's balls on the table (all object balls but the 8 when open)."""
    if group is None:
        return layout.indices_of(BallClass.SOLID) + layout.indices_of(BallClass.STRIPE)
    return layout.indices_of(group.ball_class)


def group_cleared(layout: TableLayout, group: Group | None) -> bool:
    """Whether the shooter has an assigned group with no balls left on ``layout``."""
    return group is not None and not own_balls(layout, group)


def is_scratch(result: ShotResult) -> bool:
    """The cue ball dropped."""
    return result.cue_pocketed


def black_pocketed(result: ShotResult) -> bool:
    """The 8-ball dropped."""
    black = result.initial.black_index
    return black is not None and black in result.pocketed


def legal_first_contact(result: ShotResult, state: GameState) -> bool:
    """The cue ball's first contact is a ball the shooter may hit first."""
    if result.first_contact is None:
        return False
    hit = result.initial.balls[result.first_contact].ball_class
    if state.group is None:
        return hit in (BallClass.SOLID, BallClass.STRIPE)
    if group_cleared(result.initial, state.group):
        return hit is BallClass.BLACK
    return hit is state.group.ball_class


def missing_rail_after_contact(result: ShotResult) -> bool:
    """After contact, nothing was pocketed and no ball reached a cushion."""
    return result.first_contact is not None and not result.pocketed and not result.rail_after_contact


def shot_fouls(result: ShotResult, state: GameState) -> tuple[Foul, ...]:
    """All fouls of a shot, in a fixed order."""
    fouls: list[Foul] = []
    if result.first_contact is None:
        fouls.append(Foul.NO_CONTACT)
    elif not legal_first_contact(result, state):
        fouls.append(Foul.WRONG_FIRST_CONTACT)
    if missing_rail_after_contact(result):
        fouls.append(Foul.NO_RAIL_AFTER_CONTACT)
    if is_scratch(result):
        fouls.append(Foul.SCRATCH)
    return tuple(fouls)


def assigned_group(result: ShotResult, state: GameState) -> Group | None:
    """The group after a foul-free shot: unchanged, or set by the first object ball dropped when open."""
    if state.group is not None:
        return state.group
    for i in result.pocketed:
        group = result.initial.balls[i].group
        if group is not None:
            return group
    return None


def judge_turn(
    result: ShotResult,
    state: GameState,
    fouls: tuple[Foul, ...],
    penalty_visits: int,
    in_hand: InHand = InHand.TABLE,
) -> TurnResult:
    """Win, loss, foul, continue or end of turn, given the shot's ``fouls`` under a game's rules, the visits a foul
    gives the opponent and where they may place the cue ball."""
    if black_pocketed(result):
        won = not fouls and group_cleared(result.initial, state.group)
        return TurnResult(Outcome.WIN if won else Outcome.LOSS, state.group, fouls, ())
    if fouls:
        return TurnResult(Outcome.FOUL, state.group, fouls, (), penalty_visits=penalty_visits, in_hand=in_hand)
    group = assigned_group(result, state)
    pots = tuple(i for i in result.pocketed if group is not None and result.initial.balls[i].group is group)
    outcome = Outcome.CONTINUE if pots else Outcome.END_TURN
    return TurnResult(outcome, group, (), pots)


def turn_outcome(result: ShotResult, state: GameState) -> TurnResult:
    """Judge one shot by the 8-ball rules: win, loss, foul (ball in hand), continue or end of turn."""
    return judge_turn(result, state, shot_fouls(result, state), penalty_visits=1)

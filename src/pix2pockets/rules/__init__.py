"""8-ball rules, and blackball's where they differ (:func:`judge_for` picks by ball set)."""

from collections.abc import Callable

from pix2pockets.rules.blackball import PENALTY_VISITS, blackball_shot_fouls, blackball_turn_outcome, opponent_potted
from pix2pockets.rules.eight_ball import (
    Foul,
    GameState,
    InHand,
    Outcome,
    TurnResult,
    assigned_group,
    black_pocketed,
    group_cleared,
    is_scratch,
    legal_first_contact,
    missing_rail_after_contact,
    own_balls,
    shot_fouls,
    turn_outcome,
)
from pix2pockets.state.ball_set import BallSet, parse_ball_set
from pix2pockets.state.result import ShotResult

Judge = Callable[[ShotResult, GameState], TurnResult]
"""Judges a shot: :func:`turn_outcome`, :func:`blackball_turn_outcome` or the paper's judgement."""


def judge_for(ball_set: BallSet | str) -> Judge:
    """The rules a ball set is played by: 8-ball for ``american``, WEPF blackball for ``blackball``."""
    return blackball_turn_outcome if parse_ball_set(ball_set) is BallSet.BLACKBALL else turn_outcome


__all__ = [
    "PENALTY_VISITS",
    "Foul",
    "GameState",
    "InHand",
    "Judge",
    "Outcome",
    "TurnResult",
    "assigned_group",
    "black_pocketed",
    "blackball_shot_fouls",
    "blackball_turn_outcome",
    "group_cleared",
    "is_scratch",
    "judge_for",
    "legal_first_contact",
    "missing_rail_after_contact",
    "opponent_potted",
    "own_balls",
    "shot_fouls",
    "turn_outcome",
]

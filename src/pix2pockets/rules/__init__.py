"""8-ball rules."""

from pix2pockets.rules.eight_ball import (
    Foul,
    GameState,
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

__all__ = [
    "Foul",
    "GameState",
    "Outcome",
    "TurnResult",
    "assigned_group",
    "black_pocketed",
    "group_cleared",
    "is_scratch",
    "legal_first_contact",
    "missing_rail_after_contact",
    "own_balls",
    "shot_fouls",
    "turn_outcome",
]

"""The seed paper's evaluation protocol: its start layouts and its judgement of a shot.

**Start layouts** (:func:`paper_start_layout`): the paper's environment places the balls one by one at
uniformly random integer pixels of its zoom-2 world (ball centres ``u`` in 95-1374, ``v`` in 95-724), from
numpy's global generator, redrawing a ball that would touch or overlap one already placed (centres 28 px
apart or less). The order is its creation order: seven solids, the 8, seven stripes, the cue ball. Layout
``i`` of the reference figures was drawn right after ``np.random.seed(12345 + i)``; here the same stream
comes from ``np.random.RandomState(seed)``, without touching numpy's global state.

Its sampler does not keep balls out of the pockets: about 1.5% of its all-ball layouts have a ball inside
a pocket circle, which drops at the first step of the first shot (a free pot when it is the shooter's).
``spawn_in_pocket=False`` redraws such a ball instead (then the stream, and so that layout, differs from
the paper's).

**Judgement** (:func:`paper_turn_outcome`), its code's rules for the shooter (the paper plays the
stripes; once they are gone the 8 counts as one of them): a shot that leaves none of the shooter's balls
and not the 8 on the table wins unless the cue ball dropped; otherwise the 8 dropping loses, the cue ball
dropping ends the turn (and loses once the group is gone), an opponent's ball dropping ends the turn,
and only the shooter's balls dropping earns another shot. The first ball hit is not judged (hitting an
opponent's ball first is no foul) and there is no rail-after-contact rule. Its per-shot success rate
counts the shots that pot at least one of the shooter's balls (:func:`paper_shot_success`), whether or
not the turn goes on: the paper's "pocket at least one ball".

One defect of that judgement is designed out unless ``early_eight_wins=True``: the 8 dropping *before*
the group's last ball in the same shot counted as a win (a loss here, as in 8-ball).
"""

from __future__ import annotations

import numpy as np

from pix2pockets.geometry.raster import PAPER_LAYOUT, paper_table
from pix2pockets.rules import GameState, Outcome, TurnResult
from pix2pockets.state import Ball, Group, ShotResult, TableLayout

PAPER_SHOOTER = Group.STRIPES
"""The group the paper's environment plays (its ``suit=2``)."""

PAPER_SEED_BASE = 12345
"""Layout ``i`` of the reference figures: ``np.random.seed(12345 + i)``."""

_CREATION_ORDER: dict[int, tuple[int, ...]] = {
    1: (0,),
    2: (8, 0),
    16: (1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 0),
}


def paper_start_layout(seed: int, balls: int = 16, spawn_in_pocket: bool = True) -> TableLayout:
    """The paper environment's start layout drawn after ``np.random.seed(seed)``, on :func:`paper_table`.

    Args:
        seed: the legacy numpy seed (``PAPER_SEED_BASE + i`` for layout ``i``).
        balls: 16 (all-ball), 2 (cue and 8) or 1 (the cue ball).
        spawn_in_pocket: keep the paper's draws that put a ball inside a pocket circle.

    Returns:
        The layout with balls in the paper's creation order (solids 1-7, the 8, stripes 9-15, then the cue).

    Raises:
        ValueError: ``balls`` is not 1, 2 or 16.
    """
    if balls not in _CREATION_ORDER:
        raise ValueError(f"balls must be 1, 2 or 16, got {balls}")
    numbers = _CREATION_ORDER[balls]
    lay = PAPER_LAYOUT
    u_lo, u_hi, v_lo, v_hi = lay.centre_box
    touch2 = (2 * lay.ball_radius) ** 2
    capture2 = (lay.pocket_radius + lay.ball_radius) ** 2
    pockets = lay.pocket_centres
    rs = np.random.RandomState(seed)
    placed: list[tuple[int, int]] = []

    def bad(u: int, v: int) -> bool:
        if any((u - a) ** 2 + (v - b) ** 2 <= touch2 for a, b in placed):
            return True
        return not spawn_in_pocket and bool(np.any(np.sum((pockets - (u, v)) ** 2, axis=1) < capture2))

    for _ in numbers:
        u, v = int(rs.randint(u_lo, u_hi)), int(rs.randint(v_lo, v_hi))
        while bad(u, v):
            u, v = int(rs.randint(u_lo, u_hi)), int(rs.randint(v_lo, v_hi))
        placed.append((u, v))
    xy = lay.to_table(np.array(placed, dtype=float))
    return TableLayout(tuple(Ball.numbered(n) for n in numbers), xy, paper_table())


def paper_turn_outcome(result: ShotResult, state: GameState, early_eight_wins: bool = False) -> TurnResult:
    """Judge a shot as the paper's environment does (see the module docstring).

    Args:
        result: the simulated shot.
        state: the shooter's group (required; the paper has no open table).
        early_eight_wins: the paper's defect: the 8 dropping before the group's last ball, in the shot that
            clears the group, wins.

    Raises:
        ValueError: ``state.group`` is ``None``.
    """
    if state.group is None:
        raise ValueError("the paper's judgement needs the shooter's group")
    initial = result.initial
    own_class = state.group.ball_class
    own = {i for i, b in enumerate(initial.balls) if b.ball_class is own_class}
    black = initial.black_index
    cleared = not own
    if cleared and black is not None:  # the paper turns the 8 into one of the shooter's balls
        own = {black}
    dropped = set(result.pocketed)
    cue_in = result.cue_pocketed
    own_pots = tuple(i for i in result.pocketed if i in own)
    left = own - dropped
    black_left = black is not None and black not in dropped
    if not left and not black_left:
        if cue_in:
            return TurnResult(Outcome.LOSS, state.group, (), own_pots)
        if black is not None and black in dropped and not cleared and not early_eight_wins:
            last_own = max(result.pocketed.index(i) for i in own)
            if result.pocketed.index(black) < last_own:
                return TurnResult(Outcome.LOSS, state.group, (), own_pots)
        return TurnResult(Outcome.WIN, state.group, (), own_pots)
    if not dropped:
        return TurnResult(Outcome.END_TURN, state.group, (), ())
    if black is not None and black in dropped and not cleared:  # the 8 before the group is gone
        return TurnResult(Outcome.LOSS, state.group, (), own_pots)
    if cue_in or dropped - own:  # the cue ball, or an opponent's ball, ends the turn
        return TurnResult(Outcome.END_TURN, state.group, (), own_pots)
    return TurnResult(Outcome.CONTINUE, state.group, (), own_pots)


def paper_shot_success(turn: TurnResult) -> bool:
    """The paper's per-shot success: the shot potted at least one of the shooter's balls (or won)."""
    return bool(turn.legal_pots) or turn.outcome is Outcome.WIN


def paper_continues(pocket: np.ndarray, layout: TableLayout, state: GameState) -> np.ndarray:
    """The paper's judgement of many strokes from their pocket arrays (m, n) (-1 = on the table): whether
    each one continues the turn (only the shooter's balls dropped) or wins (the 8 once the group is gone;
    an 8 in the same shot as the group's last ball counts as early). ``state.group`` must be set."""
    cue, black = layout.cue_index, layout.black_index
    classes = [b.ball_class for b in layout.balls]
    potted = pocket >= 0
    own = np.array([c is state.group.ball_class for c in classes])
    cue_ok = ~potted[:, cue]
    if not own.any():  # the group is gone: only the 8 is left to pot
        return cue_ok & (potted[:, black] if black is not None else np.zeros(len(pocket), dtype=bool))
    others = ~own
    others[cue] = False
    return cue_ok & np.any(potted & own[None, :], axis=1) & ~np.any(potted & others[None, :], axis=1)


PAPER_SEARCH_EFFORT: dict = {"samples": 8, "refine_samples": 16, "endgame": 4, "two_ply": 0}
"""The search effort on the paper's environment: it clears every rack there without the two-ply look-ahead (which
reads our rules' legal balls, not the paper's judgement) and with half the noisy replays."""


def paper_search_config() -> dict:
    """:class:`~pix2pockets.planner.search.SearchConfig` overrides for the ``paper`` physics: the paper's
    power levels (its strokes have no spin) and its judgement. Speeds are levels 8, 15, 22 and 30
    (0.27-0.97 m/s), the endgame's every fourth level from 6 up (0.20-0.97 m/s)."""
    from pix2pockets.physics.paper import paper_level_speed

    return {
        "speeds": tuple(float(paper_level_speed(lv)) for lv in (8, 15, 22, 30)),
        "heights": (0.0,),
        "endgame_speeds": tuple(float(paper_level_speed(lv)) for lv in (6, 10, 14, 18, 22, 26, 30)),
        "endgame_heights": (0.0,),
        "endgame_sides": (0.0,),
        "rules": "paper",
        **PAPER_SEARCH_EFFORT,
    }

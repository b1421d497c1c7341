"""Whole games between two players: visits, fouls and their penalty, ball in hand, until one of them wins.

The rules judge one shot at a time (:mod:`pix2pockets.rules`); a game strings the shots together:

- a legal pot lets the shooter go on in the same visit;
- a legal miss ends the visit: the opponent comes to the table, unless the shooter still has a visit owed;
- a foul hands the opponent ``TurnResult.penalty_visits`` visits (one under 8-ball rules, two under blackball rules)
  and the cue ball where ``TurnResult.in_hand`` says: under 8-ball rules in hand anywhere free on the table
  (:func:`~pix2pockets.planner.ball_in_hand.best_placement`); under blackball rules where it lies, or in hand behind
  the baulk line when it dropped;
- the black potted legally wins, a loss (the black early, or with a foul) hands the game to the opponent.

An open table stays open until a legal pot gives the shooter a group; the opponent then has the other. The game
starts from the given layout (e.g. a rack already broken), the first player at the table with an open table.

Example:
    >>> record = play_game(layout, (search, oracle), make_simulator("event"), "blackball", noise, rng)  # doctest: +SKIP
    >>> record.winner, record.shots, record.fouls  # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from pix2pockets.physics.base import Simulator
from pix2pockets.planner.ball_in_hand import best_placement
from pix2pockets.planner.base import Planner
from pix2pockets.planner.noise import NoiseModel
from pix2pockets.rules import GameState, InHand, Judge, Outcome, judge_for
from pix2pockets.state import TableLayout
from pix2pockets.state.ball import Group
from pix2pockets.state.ball_set import BallSet

MAX_SHOTS = 200
"""A game still going after this many shots is called unfinished."""


@dataclass(frozen=True, slots=True)
class GameRecord:
    """How a game went.

    Attributes:
        winner: 0 or 1, the player who won; ``None`` when the game reached the shot limit.
        shots: shots played.
        visits: visits to the table.
        fouls: fouls committed, per player (2,).
        pots: own balls legally potted, per player (2,).
        final: the layout when the game ended.
    """

    winner: int | None
    shots: int
    visits: int
    fouls: tuple[int, int]
    pots: tuple[int, int]
    final: TableLayout


def play_game(
    layout: TableLayout,
    players: Sequence[Planner],
    simulator: Simulator,
    ball_set: BallSet | str,
    noise: NoiseModel,
    rng: np.random.Generator,
    max_shots: int = MAX_SHOTS,
    judge: Judge | None = None,
) -> GameRecord:
    """Play one game from ``layout`` between two planners, each stroke executed with ``noise``.

    Args:
        layout: the table when the first player comes to it (with its cue ball, or without: ball in hand).
        players: the two planners; ``players[0]`` shoots first.
        simulator: the physics.
        ball_set: the rules: 8-ball for ``american``, WEPF blackball for ``blackball``
            (:func:`~pix2pockets.rules.judge_for`).
        noise: how each player's strokes stray.
        rng: all randomness (planning, noise, placement).
        max_shots: the game is called unfinished after this many shots.
        judge: judges each shot instead of the set's rules (e.g. a variant of them).

    Returns:
        The :class:`GameRecord`.
    """
    if len(players) != 2:
        raise ValueError(f"a game needs two players, got {len(players)}")
    judge = judge or judge_for(ball_set)
    groups: list[Group | None] = [None, None]
    fouls, pots = [0, 0], [0, 0]
    player, owed, visits, shots = 0, 1, 1, 0
    in_hand = InHand.TABLE  # a layout without its cue ball: placed anywhere
    while shots < max_shots:
        state = GameState(groups[player])
        if layout.cue_index is None:
            layout, _ = best_placement(layout, players[player], state, rng, in_hand)
        suggestion = players[player].suggest(layout, state, rng)[0]
        result = simulator.simulate(layout, noise.perturb(suggestion.shot, rng))
        judged = judge(result, state)
        shots += 1
        pots[player] += len(judged.legal_pots)
        if judged.group is not None and groups[player] is None:
            groups[player], groups[1 - player] = judged.group, judged.group.other
        if judged.outcome is Outcome.WIN:
            return GameRecord(player, shots, visits, (fouls[0], fouls[1]), (pots[0], pots[1]), result.final)
        if judged.outcome is Outcome.LOSS:
            return GameRecord(1 - player, shots, visits, (fouls[0], fouls[1]), (pots[0], pots[1]), result.final)
        layout = result.final
        if judged.outcome is Outcome.CONTINUE:
            continue
        visits += 1
        if judged.outcome is Outcome.FOUL:
            fouls[player] += 1
            player, owed = 1 - player, judged.penalty_visits
            cue = layout.cue_index
            in_hand = judged.in_hand
            if cue is None and in_hand is InHand.NONE:  # dropped, on a judge that names no area: anywhere
                in_hand = InHand.TABLE
            if cue is not None and judged.ball_in_hand:  # the incoming player picks it up to place it
                layout = layout.without([cue])
            continue
        owed -= 1
        if owed <= 0:
            player, owed = 1 - player, 1
    return GameRecord(None, shots, visits, (fouls[0], fouls[1]), (pots[0], pots[1]), layout)

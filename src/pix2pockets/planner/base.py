"""The planner slot: a protocol, the suggestion type and helpers shared by all planners."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from pix2pockets.planner.hitpoints import Hitpoint, ShotKind, path_blocked, pocket_window
from pix2pockets.rules import GameState, group_cleared, own_balls
from pix2pockets.state import Shot, TableLayout


@dataclass(frozen=True, slots=True)
class Suggestion:
    """One suggested shot.

    Attributes:
        shot: the stroke to play.
        target: object ball index the shot pots (``None`` for a safety / no-pot shot; the cue ball itself
            in the 1-ball task, see :func:`lone_cue`).
        pocket: pocket index (``TableSpec.pockets`` order), or ``None``.
        kind: direct, bank or kick; ``None`` for a safety or for a pot found by the search planner's
            full-circle sweep (a combination or multi-cushion shot; ``target`` and ``pocket`` are then
            the ball that dropped and where).
        success_probability: estimated probability of a legal pot of an own ball, in [0, 1]; ``None``
            when the planner does not estimate it (the paper's Oracle).
        value: the planner's ranking value (higher is better; its meaning depends on the planner).
        hitpoint: the hitpoint the shot was built from, if any.
        safety: the planner found no pot worth trying and plays for a legal contact instead.
    """

    shot: Shot
    target: int | None = None
    pocket: int | None = None
    kind: ShotKind | None = None
    success_probability: float | None = None
    value: float = 0.0
    hitpoint: Hitpoint | None = None
    safety: bool = False

    def __post_init__(self) -> None:
        p = self.success_probability
        if p is not None and not 0.0 <= p <= 1.0:
            raise ValueError(f"success_probability must be in [0, 1], got {p}")


@runtime_checkable
class Planner(Protocol):
    """Layout + game state -> ranked shot suggestions (best first, never empty while a cue ball is on)."""

    name: str

    def suggest(
        self, layout: TableLayout, state: GameState, rng: np.random.Generator | None = None
    ) -> list[Suggestion]:
        """Rank shots for the shooter; randomness only from ``rng`` (a fixed seed when ``None``)."""
        ...


def legal_targets(layout: TableLayout, state: GameState) -> list[int]:
    """Balls the shooter may pot now: own group, the 8 once the group is cleared, any but the 8 when open."""
    if group_cleared(layout, state.group):
        black = layout.black_index
        return [] if black is None else [black]
    return own_balls(layout, state.group)


def lone_cue(layout: TableLayout) -> bool:
    """Whether ``layout`` is the paper's 1-ball task: only the cue ball is on the table, the goal is to pot it."""
    return len(layout) == 1 and layout.cue_index is not None


def cue_pot_suggestions(layout: TableLayout, speed: float) -> list[Suggestion]:
    """1-ball task: strokes sending the lone cue ball at the middle of each pocket's clear window.

    ``target`` is the cue ball itself; ``value`` is the clear window [rad]; the widest window comes first.
    Empty when the layout is not a lone cue ball.
    """
    if not lone_cue(layout):
        return []
    c = layout.positions[layout.cue_index]
    r = layout.spec.ball_radius
    out = []
    for k, p in enumerate(layout.spec.pockets):
        w = pocket_window(c, p.jaws, r)
        if w is not None:
            out.append(Suggestion(Shot(angle=w[1], speed=speed), layout.cue_index, k, ShotKind.DIRECT, value=w[2]))
    return sorted(out, key=lambda s: -s.value)


def fallback_shot(layout: TableLayout, state: GameState, speed: float) -> Suggestion:
    """A shot straight at the nearest legal ball, preferring an unblocked one (a legal contact at least).

    Raises:
        ValueError: the layout has no cue ball.
    """
    cue = layout.cue_index
    if cue is None:
        raise ValueError("cannot plan a shot: the layout has no cue ball")
    pos = layout.positions
    c = pos[cue]
    targets = legal_targets(layout, state) or [i for i in range(len(layout)) if i != cue]
    if not targets:
        return Suggestion(Shot(angle=0.0, speed=speed), safety=True)
    r = layout.spec.ball_radius
    best, best_key = targets[0], (True, math.inf)
    for t in targets:
        others = np.delete(pos, [cue, t], axis=0)
        d = pos[t] - c
        dist = float(np.hypot(*d))
        stop = c + d * max(0.0, (dist - 2 * r) / dist)
        key = (path_blocked(c, stop, others, 2 * r), dist)
        if key < best_key:
            best, best_key = t, key
    return Suggestion(Shot.toward(tuple(c), tuple(pos[best]), speed), target=best, safety=True)

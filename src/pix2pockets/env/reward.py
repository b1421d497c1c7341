"""Rewards: a pluggable reward function and the paper's reward.

The environment judges every shot into a :class:`ShotContext` and hands it to a :class:`RewardFn`; pass
your own callable as ``reward_fn=`` to the environment to change the reward.

The paper's reward (:class:`PaperReward`, section 6.2), summed per shot, clipped to ``[-210, 210]`` and
divided by 210:

=================================================  =====================================================
term                                               value
=================================================  =====================================================
win                                                +100
loss                                               -100
each target ball hit                               +10
each target ball pocketed                          +50
a target ball hit: best pocket direction           ``1000 / (v + 10) - 50``, ``v`` [deg] the smallest
                                                   angle between its departure direction and the
                                                   direction from it to a pocket (+50 at 0 deg, 0 at
                                                   10 deg, -44.4 at 180 deg)
nothing hit                                        ``-50 d / D``: ``d`` the distance from the cue ball
                                                   at rest to the nearest target ball, ``D`` the table
                                                   diagonal
cue ball pocketed                                  -80
=================================================  =====================================================

"Target" balls are the paper's "blue" balls: the shooter's own group while any is left, else the 8-ball
(so in the 2-ball variant the 8 is the target). Win and loss follow our 8-ball rules
(:func:`pix2pockets.rules.turn_outcome`); as in the paper, pocketing the cue ball also counts as a loss.

Defects of the paper's code fixed here (documented in ``docs/env.md``):
    * the 1-ball variant's goal *is* to pocket the cue ball, so a successful 1-ball shot does not carry
      the -80 cue-ball penalty nor the loss; its "nothing hit" distance is to the nearest pocket;
    * the 8 dropped before the last own ball in the same shot is a loss, not a win (our rules);
    * the departure direction is only known for the ball the cue ball hits first: the angle term uses
      that ball (when it is a target); balls hit later still earn +10 each.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum
from typing import Protocol, runtime_checkable

import numpy as np

from pix2pockets.rules import TurnResult
from pix2pockets.state import EventType, Shot, ShotResult


class BallSetup(StrEnum):
    """Which balls are on the table and what the goal is."""

    ONE = "one"  # cue ball only: pocket the cue ball
    TWO = "two"  # cue + 8: pocket the 8 with the cue ball, keep the cue on the table
    ALL = "all"  # cue + 15: pocket your group, then the 8, without a foul


@dataclass(frozen=True, slots=True, eq=False)
class ShotContext:
    """Everything a reward function may look at for one shot.

    Attributes:
        setup: the environment variant.
        shot: the stroke actually played (after execution noise).
        result: the simulated shot; ``result.initial`` is the layout before it.
        targets: indices (into ``result.initial``) of the target ("blue") balls before the shot.
        turn: the 8-ball rules' judgement (``None`` in the 1-ball variant).
        won: the shot won the episode's game (1-ball: the cue ball dropped; else the 8 dropped legally).
        lost: the shot lost the game (the 8 dropped illegally, or the cue ball dropped outside 1-ball).
        succeeded: the shot earns another shot or wins.
        departure: unit direction in which the first ball the cue ball hit left (table frame), or ``None``.
    """

    setup: BallSetup
    shot: Shot
    result: ShotResult
    targets: tuple[int, ...]
    turn: TurnResult | None
    won: bool
    lost: bool
    succeeded: bool
    departure: np.ndarray | None


@runtime_checkable
class RewardFn(Protocol):
    """A reward function: one shot's context -> a float reward."""

    def __call__(self, ctx: ShotContext) -> float:
        """The reward of the shot."""
        ...


@dataclass(frozen=True, slots=True)
class PaperReward:
    """The paper's reward (see the module docstring); the constants are the paper's.

    Attributes:
        win, loss, per_hit, per_pocket, cue_pocketed, no_hit_scale: reward terms.
        angle_numerator, angle_offset, angle_shift: the angle term ``n / (v + o) - s`` (v in degrees).
        clip: rewards are clipped to ``[-clip, clip]``.
        normalize: divide by ``clip`` so rewards lie in ``[-1, 1]``.
    """

    win: float = 100.0
    loss: float = -100.0
    per_hit: float = 10.0
    per_pocket: float = 50.0
    cue_pocketed: float = -80.0
    no_hit_scale: float = -50.0
    angle_numerator: float = 1000.0
    angle_offset: float = 10.0
    angle_shift: float = 50.0
    clip: float = 210.0
    normalize: bool = True

    def terms(self, ctx: ShotContext) -> dict[str, float]:
        """The unclipped reward terms by name (for logging and tests)."""
        res = ctx.result
        spec = res.initial.spec
        out: dict[str, float] = {}
        if ctx.won:
            out["win"] = self.win
        if ctx.lost:
            out["loss"] = self.loss
        targets = set(ctx.targets)
        hit = {b for e in res.events if e.kind is EventType.BALL_BALL for b in (e.ball, e.other)} & targets
        if hit:
            out["hit"] = self.per_hit * len(hit)
        pots = targets & set(res.pocketed)
        if pots:
            out["pocket"] = self.per_pocket * len(pots)
        if res.first_contact in targets and ctx.departure is not None:
            v = _best_pocket_angle_deg(res.initial.positions[res.first_contact], ctx.departure, spec.pocket_aims)
            out["angle"] = self.angle_numerator / (v + self.angle_offset) - self.angle_shift
        if res.first_contact is None and not (ctx.setup is BallSetup.ONE and ctx.won):
            d = _no_hit_distance(ctx)
            out["no_hit"] = self.no_hit_scale * d / spec.diagonal
        if res.cue_pocketed and ctx.setup is not BallSetup.ONE:
            out["cue_pocketed"] = self.cue_pocketed
        return out

    def total(self, terms: dict[str, float]) -> float:
        """The reward from :meth:`terms`: summed, clipped and (optionally) normalised."""
        total = float(np.clip(sum(terms.values()), -self.clip, self.clip))
        return total / self.clip if self.normalize else total

    def __call__(self, ctx: ShotContext) -> float:
        return self.total(self.terms(ctx))


def _best_pocket_angle_deg(ball: np.ndarray, direction: np.ndarray, pockets: np.ndarray) -> float:
    """Smallest angle [deg] between ``direction`` and the directions from ``ball`` to the pockets."""
    to_pockets = pockets - ball
    cos = to_pockets @ direction / (np.linalg.norm(to_pockets, axis=1) * np.linalg.norm(direction))
    return float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))).min())


def _no_hit_distance(ctx: ShotContext) -> float:
    """Distance [m] from the cue ball at rest to the nearest target (1-ball: to the nearest pocket)."""
    res = ctx.result
    spec = res.initial.spec
    cue = res.initial.cue_index
    if cue is None:
        return 0.0
    if cue in res.pocketed:  # it rests in its pocket
        where = spec.pocket_centres[res.pocketed_into[res.pocketed.index(cue)]]
    else:
        where = res.final.positions[res.final_ids.index(cue)]
    if ctx.setup is BallSetup.ONE:
        points = spec.pocket_centres
    else:
        left = [i for i in ctx.targets if i in res.final_ids]
        if not left:
            return 0.0
        points = res.final.positions[[res.final_ids.index(i) for i in left]]
    return float(np.min(np.linalg.norm(points - where, axis=1)))


def contact_departure(result: ShotResult, shot: Shot) -> np.ndarray | None:
    """Direction [unit vector] in which the cue ball's first object ball leaves, for smooth balls.

    Without spin the impulse acts along the line of centres at contact. When the cue ball travels
    straight to its first contact (no cushion before it), the contact point follows from the stroke
    direction (ghost-ball geometry); otherwise ``None``.
    """
    target = result.first_contact
    cue = result.initial.cue_index
    if target is None or cue is None:
        return None
    t_contact = next(e.time for e in result.events if e.kind is EventType.BALL_BALL and cue in (e.ball, e.other))
    for e in result.events:
        if e.time > t_contact:
            break
        if e.ball == cue and e.kind in (EventType.BALL_CUSHION, EventType.BALL_JAW):
            return None
    c = result.initial.positions[cue]
    b = result.initial.positions[target]
    u = np.array([math.cos(shot.angle), math.sin(shot.angle)])
    rel = b - c
    along = float(rel @ u)
    perp2 = float(rel @ rel) - along * along
    reach2 = (2.0 * result.initial.spec.ball_radius) ** 2
    if along <= 0 or perp2 > reach2 * (1 + 1e-9):
        return None
    ghost = c + (along - math.sqrt(max(reach2 - perp2, 0.0))) * u
    n = b - ghost
    norm = float(np.hypot(*n))
    return n / norm if norm > 0 else None

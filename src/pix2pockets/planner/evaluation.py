"""Planner evaluation: the paper's Table 3 protocol over seeded random layouts.

Environments (``balls``):
    * ``1``: the cue ball alone; the goal is to pot it (the paper's 1-ball, ``pix2pockets/OneBall-v0``);
    * ``2``: the cue ball and the 8, the shooter's group already cleared; the goal is to pot the 8 with the
      cue ball and keep the cue ball on the table (the paper's 2-ball, ``pix2pockets/TwoBall-v0``);
    * ``16``: a full table at random spots, the shooter on solids (the paper's all-ball,
      ``pix2pockets/AllBall-v0``).

Each layout is one turn: the planner shoots until a shot fails or the table is cleared. A shot succeeds on
a legal pot of an own ball (or the winning 8); fouls count as failures. In the 1-ball environment the one
shot succeeds when the cue ball drops. Per-shot success is successes over all shots played; full-turn
clear is the fraction of turns that pot the whole group and then the 8 (or the single target) without a
miss or foul.

Two protocols (:class:`Protocol`): ``ours`` (layout ``i`` from ``default_rng([seed, i, 0])`` on the chosen
table, the shooter on solids, our 8-ball rules) and ``paper`` (the paper environment's own start layouts
``np.random.seed(seed + i)`` on its table, the shooter on stripes, its judgement of a shot; see
:mod:`pix2pockets.planner.paper_protocol`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from pix2pockets.geometry.table import TableSpec
from pix2pockets.planner.base import Planner, legal_targets, lone_cue
from pix2pockets.planner.noise import NO_NOISE, NoiseModel
from pix2pockets.rules import GameState, Judge, Outcome, TurnResult, turn_outcome
from pix2pockets.state import Group, Shot, ShotResult, TableLayout, random_layout

BALL_SETS: dict[int, tuple[int, ...]] = {1: (0,), 2: (0, 8), 16: tuple(range(16))}
"""Ball numbers per environment (as in ``pix2pockets/OneBall-v0``, ``TwoBall-v0``, ``AllBall-v0``)."""

Z95 = 1.959963984540054


def wilson_interval(successes: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval for a binomial proportion (default 95%)."""
    if n <= 0:
        return (0.0, 1.0)
    p = successes / n
    den = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return (max(0.0, centre - half), min(1.0, centre + half))


def sample_environment(balls: int, rng: np.random.Generator, spec: TableSpec | None = None) -> TableLayout:
    """A random layout for the ``balls`` environment (1, 2 or 16), ball 0 of the layout the cue ball."""
    if balls not in BALL_SETS:
        raise ValueError(f"balls must be one of {sorted(BALL_SETS)}, got {balls}")
    return random_layout(rng, list(BALL_SETS[balls]), spec)


def environment_state(balls: int) -> GameState:
    """The shooter's state at the start of a turn: solids (cleared already in the 2-ball case)."""
    return GameState(Group.SOLIDS)


def continues_or_wins(turn: TurnResult) -> bool:
    """Our per-shot success: a legal pot of an own ball (the turn goes on) or the winning 8."""
    return turn.shot_succeeded


@dataclass(frozen=True, slots=True)
class Protocol:
    """Where turns start, who shoots and how a shot is judged.

    Attributes:
        name: ``ours`` or ``paper``.
        layout: ``(balls, seed, i) -> TableLayout``, the start of turn ``i``.
        state: the shooter's group.
        judge: judges each shot.
        success: whether a judged shot counts as a success per shot.
    """

    name: str
    layout: Callable[[int, int, int], TableLayout]
    state: GameState
    judge: Judge
    success: Callable[[TurnResult], bool] = continues_or_wins


def ours_protocol(spec: TableSpec | None = None, judge: Judge = turn_outcome) -> Protocol:
    """Our protocol: layout ``i`` from ``default_rng([seed, i, 0])`` on ``spec``, solids (reds in a blackball
    set), 8-ball rules or another ``judge`` (:func:`pix2pockets.rules.judge_for`)."""

    def layout(balls: int, seed: int, i: int) -> TableLayout:
        return sample_environment(balls, np.random.default_rng([seed, i, 0]), spec)

    return Protocol("ours", layout, GameState(Group.SOLIDS), judge)


def paper_protocol(spawn_in_pocket: bool = False, early_eight_wins: bool = False) -> Protocol:
    """The paper environment's protocol: its start layout after ``np.random.seed(seed + i)``, the stripes,
    its judgement. The two flags switch its defects back on (see :mod:`pix2pockets.planner.paper_protocol`)."""
    from pix2pockets.planner.paper_protocol import (
        PAPER_SHOOTER,
        paper_shot_success,
        paper_start_layout,
        paper_turn_outcome,
    )

    def layout(balls: int, seed: int, i: int) -> TableLayout:
        return paper_start_layout(seed + i, balls, spawn_in_pocket)

    def judge(result: ShotResult, state: GameState) -> TurnResult:
        return paper_turn_outcome(result, state, early_eight_wins)

    name = "paper" + "".join(
        f"+{flag}" for flag, on in (("spawn-in-pocket", spawn_in_pocket), ("early-eight-wins", early_eight_wins)) if on
    )
    return Protocol(name, layout, GameState(PAPER_SHOOTER), judge, paper_shot_success)


@dataclass(frozen=True, slots=True)
class TurnRecord:
    """One turn.

    Attributes:
        shots: shots played.
        successes: shots that legally potted an own ball (or won).
        cleared: the turn cleared the table.
        last_outcome: how the last shot ended.
        decision_times: planner wall-clock time per shot [s].
    """

    shots: int
    successes: int
    cleared: bool
    last_outcome: Outcome | None
    decision_times: tuple[float, ...] = ()


def play_turn(
    layout: TableLayout,
    state: GameState,
    planner: Planner,
    simulate: Callable[[TableLayout, Shot], ShotResult],
    noise: NoiseModel = NO_NOISE,
    rng: np.random.Generator | None = None,
    max_shots: int = 30,
    judge: Judge = turn_outcome,
    success: Callable[[TurnResult], bool] | None = None,
) -> TurnRecord:
    """Shoot until a miss, a foul or a cleared table.

    Args:
        layout: the starting table.
        state: the shooter's group.
        planner: picks each shot (its first suggestion is played).
        simulate: runs one executed shot.
        noise: turns the planned shot into the executed one.
        rng: randomness for the planner and the noise.
        max_shots: safety cap on the turn length.
        judge: judges each shot (default: our 8-ball rules).
        success: whether a judged shot counts as a success (default: it continues the turn or wins).
    """
    success = success or continues_or_wins
    rng = rng if rng is not None else np.random.default_rng(0)
    plan_rng, noise_rng = (np.random.default_rng(s) for s in rng.bit_generator.seed_seq.spawn(2))
    shots = successes = 0
    times: list[float] = []
    outcome: Outcome | None = None
    if lone_cue(layout):  # the 1-ball task: one shot, won when the cue ball drops
        t0 = time.perf_counter()
        suggestion = planner.suggest(layout, state, plan_rng)[0]
        times.append(time.perf_counter() - t0)
        try:
            won = simulate(layout, noise.perturb(suggestion.shot, noise_rng)).cue_pocketed
        except RuntimeError:
            won = False
        return TurnRecord(1, int(won), won, Outcome.WIN if won else Outcome.END_TURN, tuple(times))
    while shots < max_shots:
        if not legal_targets(layout, state):
            return TurnRecord(shots, successes, True, outcome, tuple(times))
        t0 = time.perf_counter()
        suggestion = planner.suggest(layout, state, plan_rng)[0]
        times.append(time.perf_counter() - t0)
        shot = noise.perturb(suggestion.shot, noise_rng)
        shots += 1
        try:
            result = simulate(layout, shot)
        except RuntimeError:  # a simulator time-out counts as a failed shot
            return TurnRecord(shots, successes, False, None, tuple(times))
        turn = judge(result, state)
        outcome = turn.outcome
        successes += bool(success(turn))
        if outcome is Outcome.WIN:
            return TurnRecord(shots, successes, True, outcome, tuple(times))
        if outcome is not Outcome.CONTINUE:
            return TurnRecord(shots, successes, False, outcome, tuple(times))
        layout, state = result.final, GameState(turn.group)
        if layout.cue_index is None:  # cannot happen on a legal shot; guard anyway
            return TurnRecord(shots, successes, False, outcome, tuple(times))
    return TurnRecord(shots, successes, False, outcome, tuple(times))


@dataclass(frozen=True, slots=True)
class EvaluationSummary:
    """Results over many turns."""

    planner: str
    physics: str
    noise: str
    balls: int
    seed: int
    turns: int
    shots: int
    successes: int
    clears: int
    decision_times: tuple[float, ...] = field(default=(), repr=False)
    protocol: str = "ours"

    @property
    def per_shot_success(self) -> float:
        return self.successes / self.shots if self.shots else 0.0

    @property
    def full_turn_clear(self) -> float:
        return self.clears / self.turns if self.turns else 0.0

    def to_dict(self) -> dict:
        """A JSON-ready dict with the paper's two metrics, 95% Wilson intervals and decision times."""
        times = np.array(self.decision_times) if self.decision_times else np.zeros(1)
        return {
            "planner": self.planner,
            "physics": self.physics,
            "noise": self.noise,
            "balls": self.balls,
            "seed": self.seed,
            "protocol": self.protocol,
            "layouts": self.turns,
            "shots": self.shots,
            "per_shot_success": self.per_shot_success,
            "per_shot_success_ci95": list(wilson_interval(self.successes, self.shots)),
            "full_turn_clear": self.full_turn_clear,
            "full_turn_clear_ci95": list(wilson_interval(self.clears, self.turns)),
            "decision_time_mean_s": float(times.mean()),
            "decision_time_p95_s": float(np.percentile(times, 95)),
            "decision_time_max_s": float(times.max()),
        }


def evaluate_planner(
    planner: Planner,
    simulate: Callable[[TableLayout, Shot], ShotResult],
    balls: int = 16,
    layouts: int = 100,
    seed: int = 0,
    noise: NoiseModel = NO_NOISE,
    physics: str = "",
    progress: bool = False,
    protocol: Protocol | None = None,
    first: int = 0,
) -> EvaluationSummary:
    """Run ``layouts`` seeded turns; layout ``i`` depends only on ``(seed, i)`` (not on the planner).

    ``protocol`` (default :func:`ours_protocol`) gives the layouts, the shooter and the judgement. ``first``
    starts at layout ``first`` (turns ``first .. first + layouts - 1``): pieces of one evaluation run anywhere
    and :func:`merge_summaries` joins them into the summary of the whole.
    """
    if layouts < 1:
        raise ValueError(f"layouts must be >= 1, got {layouts}")
    if first < 0:
        raise ValueError(f"first must be >= 0, got {first}")
    protocol = protocol or ours_protocol()
    state = protocol.state
    shots = successes = clears = 0
    times: list[float] = []
    it = range(first, first + layouts)
    if progress:
        from tqdm import tqdm

        it = tqdm(it, desc=f"{planner.name} {balls}-ball", unit="turn")
    for i in it:
        layout = protocol.layout(balls, seed, i)
        rng = np.random.default_rng([seed, i, 1])
        rec = play_turn(layout, state, planner, simulate, noise, rng, judge=protocol.judge, success=protocol.success)
        shots += rec.shots
        successes += rec.successes
        clears += rec.cleared
        times.extend(rec.decision_times)
        if progress:
            it.set_postfix(shot=f"{successes / max(shots, 1):.3f}", clear=f"{clears / (i - first + 1):.3f}")
    return EvaluationSummary(
        planner.name, physics, noise.name, balls, seed, layouts, shots, successes, clears, tuple(times), protocol.name
    )


def merge_summaries(parts: Sequence[EvaluationSummary]) -> EvaluationSummary:
    """One summary from the summaries of consecutive layout ranges of one evaluation (in layout order).

    Counts add up and decision times are concatenated, so the result equals a single run over all layouts
    (decision times are wall-clock, so only their count matches).

    Raises:
        ValueError: no parts, or parts of different evaluations (planner, physics, noise, balls, seed, protocol).
    """
    if not parts:
        raise ValueError("nothing to merge")
    head = parts[0]
    key = (head.planner, head.physics, head.noise, head.balls, head.seed, head.protocol)
    for part in parts[1:]:
        other = (part.planner, part.physics, part.noise, part.balls, part.seed, part.protocol)
        if other != key:
            raise ValueError(f"cannot merge evaluations of different settings: {key} and {other}")
    return replace(
        head,
        turns=sum(p.turns for p in parts),
        shots=sum(p.shots for p in parts),
        successes=sum(p.successes for p in parts),
        clears=sum(p.clears for p in parts),
        decision_times=tuple(t for p in parts for t in p.decision_times),
    )


__all__ = [
    "BALL_SETS",
    "EvaluationSummary",
    "Judge",
    "Protocol",
    "TurnRecord",
    "environment_state",
    "evaluate_planner",
    "merge_summaries",
    "ours_protocol",
    "paper_protocol",
    "play_turn",
    "sample_environment",
    "wilson_interval",
]

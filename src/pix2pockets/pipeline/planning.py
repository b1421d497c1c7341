"""The planning step of the photo pipeline: a planner slot and the shot's paths for drawing.

Any object with the shape of :class:`pix2pockets.planner.Planner` fits (``suggest(layout, state, rng)``
returning ranked candidates that carry ``shot``, ``target``, ``pocket``, ``kind``,
``success_probability``, ``value``, ``hitpoint`` and ``safety``).

With the search planner the chance shown is measured (:func:`pix2pockets.planner.chance.measure_chance`):
the chosen stroke replayed :data:`CHANCE_SAMPLES` times under the player's skill noise, with the balls
moved by the photo's location error (each ball's own, from the fitted camera and the fit's error,
:mod:`pix2pockets.vision.locate.position_error`; :data:`PHOTO_POSITION_SIGMA` per axis for a layout without a
photo), and reported with its sample size. A pot whose chance so measured falls far below the planner's own estimate
gives way to the next best pot that the photo's errors spare more (:data:`RETRY_SHARE`).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, Protocol, runtime_checkable

import numpy as np

from pix2pockets.geometry.table import TableSpec
from pix2pockets.physics.event.simulator import shots_to_array
from pix2pockets.pipeline.break_shot import break_advice, break_spot, hand_racked, racked_balls, tight_rack
from pix2pockets.pipeline.result import ShotAdvice
from pix2pockets.pipeline.unseen_pockets import pocket_hit_share
from pix2pockets.planner.ball_in_hand import best_placement
from pix2pockets.planner.chance import Chance, measure_chance
from pix2pockets.rules import GameState, InHand
from pix2pockets.state import Ball, BallClass, Group, Shot, TableLayout
from pix2pockets.state.ball_set import BallSet


@runtime_checkable
class ShotPlanner(Protocol):
    """Layout + game state -> ranked shot candidates, best first."""

    def suggest(self, layout: TableLayout, state: GameState, rng: np.random.Generator | None = None) -> list: ...


CHANCE_SAMPLES = 400
"""Sampled executions behind a shown chance (a 95% interval of about +-5 points at 50%)."""
BREAK_RACKS = 20
"""Triangles racked by hand behind a break's chance (the samples are split among them)."""
RERANKED_CANDIDATES = 8
"""Candidates ranked again when a pocket's place is unsure: the search planner's strokes valued by noisy replays
(``SearchConfig.max_verified``); those after them carry only their clean value."""
RETRIED_CANDIDATES = 4
"""Pots of each group kept to fall back on ..."""
RETRY_SHARE = 0.5
"""... when the chosen pot's chance under the photo's errors is less than this share of the planner's own estimate
(the balls exactly where the photo puts them): a combination or a thin cut that needs the balls to the millimetre
may lose to a plainer pot there. The pot with the best chance so measured is suggested."""
PHOTO_POSITION_SIGMA = 0.003
"""Ball-position error per axis [m] of a layout whose photo is not at hand: the shipped detector's median ball error
on renders is 1.4-4.2 mm (docs/benchmarks-vision.md); a 2-D Gaussian with 3 mm per axis has a median error of
3.5 mm."""
DEFAULT_SKILL = "pro"
"""The skill level the pipeline plans for unless told (FastFiz noise; see ``docs/planner.md``)."""


def default_planner(time_budget: float | None = None, skill: str = DEFAULT_SKILL) -> ShotPlanner:
    """The project's default planner: :class:`pix2pockets.planner.search.SearchPlanner` (event physics,
    planning for the player's skill level: ``pro``, ``club``, ``beginner`` or a noise ``FILE.json``).

    Without ``time_budget`` the search runs to completion, so the same photo always gets the same answer
    (typically 0.1-0.4 s per group on one core). A wall-clock budget [s] per group caps the time but makes
    the answer depend on machine load (and on a first run's JIT compile).

    Raises:
        ValueError: an unknown skill level, or the planner cannot be built in this installation.
    """
    try:
        from pix2pockets.planner.search import SearchConfig, SearchPlanner
    except ImportError as err:  # pragma: no cover - depends on the build
        raise ValueError(f"no shot planner available: {err}") from None
    return SearchPlanner(SearchConfig(time_budget=time_budget, noise=skill))


def planner_for_set(planner: ShotPlanner, ball_set: BallSet) -> ShotPlanner:
    """``planner`` playing by the rules of ``ball_set``: a search planner on 8-ball rules is copied onto WEPF
    blackball rules (an opponent's ball down is a foul) for a blackball set; other planners are returned as given."""
    from pix2pockets.planner.search import SearchPlanner

    if ball_set is not BallSet.BLACKBALL or not isinstance(planner, SearchPlanner) or planner.config.rules != "8ball":
        return planner
    copy = SearchPlanner(replace(planner.config, rules="blackball"), simulator=planner.simulator)
    copy.name = planner.name
    return copy


def _search_planner(planner: Any) -> Any | None:
    """The search planner inside ``planner`` (wrappers keep it as ``.planner``), or ``None``."""
    for _ in range(3):
        if hasattr(planner, "_run") and hasattr(planner, "_success") and hasattr(planner, "noise"):
            return planner
        planner = getattr(planner, "planner", None)
        if planner is None:
            return None
    return None


def break_chance(
    planner: Any, layout: TableLayout, samples: int = CHANCE_SAMPLES, seed: int = 0, racks: int = BREAK_RACKS
) -> Chance | None:
    """The chance of the break on a racked ``layout``: of ``samples`` executions under the planner's noise, each on
    one of ``racks`` triangles racked by hand where the photo shows the rack
    (:func:`~pix2pockets.pipeline.break_shot.tight_rack`, :func:`~pix2pockets.pipeline.break_shot.hand_racked`) and
    struck as :func:`break_advice` strikes it, the share that pocket an object ball and keep the cue ball on the
    table. None for planners without a simulator, or a rack that cannot be made tight where it lies.
    """
    search = _search_planner(planner)
    tight = tight_rack(layout)
    if search is None or tight is None or samples < 1:
        return None
    stroke = break_advice(tight).stroke
    rng = np.random.default_rng([seed, 11])
    z = rng.standard_normal((samples, 5))
    objects = np.array([b.ball_class is not BallClass.CUE for b in tight.balls])
    made = 0
    for draws in np.array_split(np.arange(samples), max(1, min(racks, samples))):
        racked = hand_racked(tight, rng)
        rows = shots_to_array([search.noise.apply(stroke, z[k]) for k in draws])
        _, pocket, _ = search._run(racked, rows)
        made += int(np.count_nonzero((pocket[:, objects] >= 0).any(axis=1) & (pocket[:, racked.cue_index] < 0)))
    return Chance(made, samples, search.noise.name)


def shot_chance(
    planner: Any,
    layout: TableLayout,
    group: Group,
    shot: Shot,
    samples: int = CHANCE_SAMPLES,
    position_sigma: float | np.ndarray = PHOTO_POSITION_SIGMA,
    seed: int = 0,
    target: int | None = None,
    aim_point: np.ndarray | None = None,
    pocket_sigma: float = 0.0,
    pocket_distance: float | None = None,
) -> Chance | None:
    """The measured chance of ``shot`` under the planner's noise (``None`` for planners without a simulator).

    With ``target`` and ``aim_point`` (the ghost-ball centre [m]) the stroke is re-aimed on each layout drawn
    with the position error, as a player aiming at the real balls would; ``pocket_sigma`` [m] and
    ``pocket_distance`` [m] add the pocket's position error (:func:`~pix2pockets.planner.chance.measure_chance`).
    """
    search = _search_planner(planner)
    if search is None or samples < 1:
        return None
    rng = np.random.default_rng([seed, 7])
    return measure_chance(
        search,
        layout,
        GameState(group=group),
        shot,
        samples=samples,
        rng=rng,
        position_sigma=position_sigma,
        target=target,
        aim_point=aim_point,
        pocket_sigma=pocket_sigma,
        pocket_distance=pocket_distance,
    )


def _rail_hit(start: np.ndarray, angle: float, spec: TableSpec) -> np.ndarray:
    """Where a ball centre leaving ``start`` in direction ``angle`` first reaches a cushion [m]."""
    R = spec.ball_radius
    d = np.array([math.cos(angle), math.sin(angle)])
    ts = []
    for axis, lo, hi in ((0, R, spec.length - R), (1, R, spec.width - R)):
        if abs(d[axis]) > 1e-12:
            for bound in (lo, hi):
                t = (bound - start[axis]) / d[axis]
                if t > 1e-9:
                    ts.append(t)
    t = min(ts) if ts else 0.0
    return start + t * d


def _is_safety(candidate: Any) -> bool:
    """A candidate that pots nothing: the planner's safety, or one without a target ball or pocket."""
    return (
        bool(getattr(candidate, "safety", False))
        or getattr(candidate, "target", None) is None
        or getattr(candidate, "pocket", None) is None
    )


def _value_of(candidate: Any) -> float:
    p = getattr(candidate, "success_probability", None)
    return float(p) if p is not None else float(getattr(candidate, "value", 0.0))


OTHER_KIND = "other"
"""The kind of a pot the search found by simulation that is none of direct, bank or kick (a combination, a carom,
a path off several cushions)."""


def advice_from_candidate(candidate: Any, layout: TableLayout, group: Group) -> ShotAdvice:
    """Turn a planner candidate into a :class:`ShotAdvice` with drawable paths."""
    spec = layout.spec
    R = spec.ball_radius
    cue = layout.cue_index
    if cue is None:
        raise ValueError("no cue ball found on the table")
    start = layout.positions[cue]
    shot = candidate.shot
    target = getattr(candidate, "target", None)
    pocket = getattr(candidate, "pocket", None)
    kind = getattr(candidate, "kind", None)
    kind = None if kind is None else str(getattr(kind, "value", kind))
    safety = _is_safety(candidate)
    hp = getattr(candidate, "hitpoint", None)
    ghost = None
    if not safety:
        ball = layout.positions[target]
        aim = spec.pockets[pocket].aim
        if hp is not None:
            ghost = np.asarray(hp.ghost, dtype=float)
            object_angle = float(hp.object_angle)
        else:
            u = (aim - ball) / np.linalg.norm(aim - ball)
            ghost = ball - 2 * R * u
            object_angle = math.atan2(u[1], u[0])
        if kind == "kick":
            cue_path = np.array([start, _rail_hit(start, shot.angle, spec), ghost])
        else:
            cue_path = np.array([start, ghost])
        if kind == "bank":
            object_path = np.array([ball, _rail_hit(ball, object_angle, spec), aim])
        else:
            object_path = np.array([ball, aim])
    else:
        end = _rail_hit(start, shot.angle, spec)
        length = min(float(np.linalg.norm(end - start)), 1.0)
        cue_path = np.array([start, start + length * np.array([math.cos(shot.angle), math.sin(shot.angle)])])
        object_path = np.zeros((0, 2))
    p = getattr(candidate, "success_probability", None)
    return ShotAdvice(
        target_ball=None if safety else int(target),
        pocket=None if safety else spec.pockets[pocket].name,
        kind=None if safety else (kind or OTHER_KIND),
        cue_angle=float(shot.angle),
        speed=float(shot.speed),
        success_probability=None if p is None else float(p),
        group=group.value,
        cue_path=cue_path,
        object_path=object_path,
        ghost=ghost,
        safety=safety,
        stroke=shot if isinstance(shot, Shot) else None,
    )


def groups_to_plan(layout: TableLayout, group: str | Group) -> list[Group]:
    """The groups to plan for: ``group``, or for ``auto`` each group with balls on the table (solids when only the 8
    is left).

    Raises:
        ValueError: an unknown group, or no ball of the group (and no 8-ball) on the table.
    """
    have = {g: bool(layout.indices_of(g.ball_class)) for g in Group}
    black = bool(layout.indices_of(BallClass.BLACK))
    if str(group) == "auto":
        groups = [g for g in Group if have[g]] or ([Group.SOLIDS] if black else [])
        if not groups:
            raise ValueError("no object balls found on the table (no solids, stripes or 8-ball)")
        return groups
    try:
        g = Group(str(group))
    except ValueError:
        raise ValueError(f"unknown group {group!r}; choose solids, stripes or auto") from None
    if not have[g] and not black:
        raise ValueError(f"no {g.value} (and no 8-ball) found on the table")
    return [g]


def place_in_hand(
    layout: TableLayout,
    group: str | Group,
    planner: ShotPlanner,
    area: InHand,
    rng: np.random.Generator | None = None,
) -> tuple[TableLayout, Group]:
    """Ball in hand: ``layout`` without its cue ball (the player picks it up), the cue ball put back where
    ``planner`` likes the best shot for ``group`` most (``auto``: for the group with the better shot;
    :func:`~pix2pockets.planner.ball_in_hand.best_placement`), anywhere free on the table or behind the baulk line
    (``area``). Returns the layout, its placed cue ball last, and the group it was placed for.

    A racked table gets the cue ball where the break is played from
    (:func:`~pix2pockets.pipeline.break_shot.break_spot`) when that spot is free.

    Raises:
        ValueError: as :func:`groups_to_plan`, or no free spot in ``area``.
    """
    base = layout if layout.cue_index is None else layout.without([layout.cue_index])
    if len(racked_balls(base)):
        spot = break_spot(base, area)
        clear = np.linalg.norm(base.positions - spot, axis=1).min() > base.spec.ball_radius + base.spec.cue_radius
        if clear:
            placed = TableLayout((*base.balls, Ball.numbered(0)), np.vstack([base.positions, spot]), base.spec)
            return placed, groups_to_plan(base, group)[0]
    best: tuple[float, TableLayout, Group] | None = None
    for g in groups_to_plan(base, group):
        placed, top = best_placement(base, planner, GameState(group=g), rng, area)
        score = _value_of(top) - (1e3 if top.safety else 0.0)
        if best is None or score > best[0]:
            best = (score, placed, g)
    return best[1], best[2]


def plan_shot(
    layout: TableLayout,
    group: str | Group,
    planner: ShotPlanner,
    rng: np.random.Generator | None = None,
    chance_samples: int = CHANCE_SAMPLES,
    position_sigma: float | np.ndarray = PHOTO_POSITION_SIGMA,
    pocket_sigma: np.ndarray | None = None,
) -> ShotAdvice:
    """Best shot for ``group`` (``solids``, ``stripes`` or ``auto``: the group with the better shot).

    The advice's ``success_probability`` is the measured chance of the chosen stroke (``chance_samples``
    executions under the planner's noise, balls moved by ``position_sigma`` [m] per axis, or by each ball's position
    covariance (n, 2, 2) [m^2]) when the planner simulates; otherwise the planner's own estimate.

    ``pocket_sigma`` gives each pocket's position error per axis [m] (``spec.pockets`` order; a pocket out of the
    photo, :mod:`pix2pockets.pipeline.unseen_pockets`): the planner's candidates are then ranked by their value times
    the share of those errors their pocket still takes, and the chosen direct or bank shot's chance is measured with its
    pocket's error.

    The advice carries where the cue ball goes after the first ball, played exactly as planned
    (:func:`with_cue_after`; not for a break, which scatters each rack its own way). A racked table gets the break
    (:mod:`pix2pockets.pipeline.break_shot`, its chance from :func:`break_chance`), whatever the group.

    Raises:
        ValueError: no cue ball, or no ball of the group (and no 8-ball) on the table.
    """
    advice = _plan(layout, group, planner, rng, chance_samples, position_sigma, pocket_sigma)
    if advice.kind == "break":  # no one way: a break scatters the rack differently each time it is racked
        return advice
    return with_cue_after(advice, planner, layout)


def _plan(
    layout: TableLayout,
    group: str | Group,
    planner: ShotPlanner,
    rng: np.random.Generator | None,
    chance_samples: int,
    position_sigma: float | np.ndarray,
    pocket_sigma: np.ndarray | None,
) -> ShotAdvice:
    """:func:`plan_shot` without the cue ball's path after the first ball."""
    if layout.cue_index is None:
        raise ValueError("no cue ball found on the table")
    if len(racked_balls(layout)):
        advice = break_advice(layout)
        chance = break_chance(planner, layout, chance_samples)
        return advice if chance is None else replace(advice, success_probability=chance.p, chance=chance)
    spec = layout.spec
    sigmas = np.zeros(len(spec.pockets)) if pocket_sigma is None else np.asarray(pocket_sigma, dtype=float)

    def share(candidate: Any) -> float:  # the pocket position errors the candidate's pocket still takes
        pocket = getattr(candidate, "pocket", None)
        return 1.0 if pocket is None else pocket_hit_share(spec, pocket, float(sigmas[pocket]))

    firsts: list[tuple[float, ShotAdvice, Any]] = []  # each group's best: (score, advice, candidate)
    others: list[ShotAdvice] = []  # the next pots of each group, to fall back on
    for g in groups_to_plan(layout, group):
        candidates = planner.suggest(layout, GameState(group=g), rng)
        if not candidates:
            continue
        if np.any(sigmas > 0):  # a pocket out of the photo: the best strokes ranked again by the errors they survive
            candidates = sorted(
                candidates[:RERANKED_CANDIDATES],
                key=lambda c: float(getattr(c, "value", 0.0)) * share(c) - 1e3 * _is_safety(c),
                reverse=True,
            )
        advices = [advice_from_candidate(c, layout, g) for c in candidates[:RETRIED_CANDIDATES]]
        score = _value_of(candidates[0]) * share(candidates[0]) - (1e3 if advices[0].safety else 0.0)
        firsts.append((score, advices[0], candidates[0]))
        others.extend(advices[1:])
    if not firsts:
        raise ValueError("the planner found no shot")
    _, advice, cand = max(firsts, key=lambda item: item[0])
    others = [a for _, a, _ in firsts if a is not advice] + others
    if advice.safety or advice.stroke is None:
        return advice
    chance = _photo_chance(planner, layout, advice, chance_samples, position_sigma, sigmas)
    if chance is None:
        return advice
    planned = getattr(cand, "success_probability", None)
    if planned is not None and chance.p < RETRY_SHARE * float(planned):
        # the photo's errors take most of the chosen shot's chance: the next best pots are measured the same way
        for other in others:
            if other.safety or other.stroke is None:
                continue
            measured = _photo_chance(planner, layout, other, chance_samples, position_sigma, sigmas)
            if measured is not None and measured.p > chance.p:
                advice, chance = other, measured
    exact = chance
    if chance.position_sigma > 0 or chance.pocket_sigma > 0:
        exact = shot_chance(planner, layout, Group(advice.group), advice.stroke, chance_samples, 0.0)
    return replace(advice, success_probability=chance.p, chance=chance, chance_exact_positions=exact)


def _photo_chance(
    planner: ShotPlanner,
    layout: TableLayout,
    advice: ShotAdvice,
    samples: int,
    position_sigma: float | np.ndarray,
    pocket_sigmas: np.ndarray,
) -> Chance | None:
    """The measured chance of a pot ``advice`` under the planner's noise and the photo's errors (the balls'
    ``position_sigma``, each pocket's ``pocket_sigmas``), re-aimed on each drawn layout as a player aiming at the
    real balls would: direct and bank strokes at the ghost ball, kicks at their angle. None without a simulator."""
    aim = advice.ghost if advice.kind != "kick" else None
    pocket = layout.spec.pocket_index(advice.pocket)
    # a kick or a combination is not re-aimed along a line to its pocket: measured with the pocket where it was fitted
    unsure = float(pocket_sigmas[pocket]) if advice.kind in ("direct", "bank") else 0.0
    distance = float(np.linalg.norm(np.diff(advice.object_path, axis=0), axis=1).sum())
    return shot_chance(
        planner,
        layout,
        Group(advice.group),
        advice.stroke,
        samples,
        position_sigma,
        0,
        advice.target_ball,
        aim,
        unsure,
        distance,
    )


def with_cue_after(advice: ShotAdvice, planner: Any, layout: TableLayout) -> ShotAdvice:
    """``advice`` with where its cue ball goes once it meets the first ball (``cue_after``, ``cue_pocketed``), from the
    planner's own simulator, played exactly as planned; unchanged for planners without an event simulator or advice
    without a stroke."""
    search = _search_planner(planner)
    simulator = getattr(search, "simulator", None)
    if advice.stroke is None or not hasattr(simulator, "ball_path"):
        return advice
    cue = layout.cue_index
    path = simulator.ball_path(layout, advice.stroke, cue, from_first_contact=True)
    dropped = bool(simulator.simulate(layout, advice.stroke).cue_pocketed)
    return replace(advice, cue_after=path, cue_pocketed=dropped)

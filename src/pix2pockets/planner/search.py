"""Our search planner: hitpoint candidates verified by the physics engine under execution noise.

1. **Candidates**: hitpoints (direct, bank, kick) for the shooter's legal balls, ranked by a geometric
   pot probability (:func:`~pix2pockets.planner.position.pot_probability`); the best ``max_candidates``
   are expanded over ``speeds`` and tip ``heights`` (follow / draw; direct shots only).
2. **Verify**: each stroke is simulated once without noise; strokes whose clean execution does not
   legally pot an own ball are dropped. A missed pot is retried once with the aim corrected by the
   observed miss (engines with throw or real cushions deviate from ideal ghost-ball geometry).
3. **Robustness and position**: the surviving strokes are replayed with ``samples`` noisy executions
   (common random numbers: the same draws for every stroke). Each execution scores
   ``success x (1 + lookahead x V)``, ``V`` the best next-shot pot probability from where the balls stop.
   The expected score ranks the suggestions; the success fraction is their success probability.
4. **Fallback**: with no pot, a legal safety (contact an own ball, no foul) or a plain shot at the nearest
   own ball.

Budgets: ``max_simulations`` is deterministic; ``time_budget`` [s] additionally stops early on slow
machines (results then depend on timing, so evaluations set it to ``None``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from pix2pockets.physics import Simulator, make_simulator
from pix2pockets.planner.base import Suggestion, fallback_shot, legal_targets
from pix2pockets.planner.hitpoints import Hitpoint, ShotKind, find_hitpoints
from pix2pockets.planner.noise import GaussianNoise, noise_model
from pix2pockets.planner.position import position_value, pot_probability
from pix2pockets.rules import GameState, Outcome, TurnResult, turn_outcome
from pix2pockets.state import Shot, ShotResult, TableLayout

_MIN_SIGMA = math.radians(0.05)  # planning never assumes perfect aim


@dataclass(frozen=True, slots=True)
class SearchConfig:
    """Search planner settings.

    Attributes:
        physics: simulator backend name (``make_simulator``).
        noise: planning noise model name (``noise_model``); the planner prefers strokes that survive it.
        samples: noisy executions per surviving stroke.
        speeds: candidate cue-ball speeds [m/s].
        heights: candidate vertical tip offsets (fraction of the radius; + follow, - draw) for direct shots.
        kinds: hitpoint kinds to consider.
        max_candidates: hitpoints expanded per decision.
        max_verified: strokes that get noisy replays.
        max_cut: largest cut angle [rad].
        lookahead: weight of the next-shot value.
        time_budget: wall-clock limit per decision [s], ``None`` for none.
        max_simulations: simulation limit per decision (deterministic).
        correct_aim: retry a missed pot once with the aim corrected by the observed miss.
    """

    physics: str = "event"
    noise: str = "fastfiz"
    samples: int = 6
    speeds: tuple[float, ...] = (1.2, 2.0, 3.2)
    heights: tuple[float, ...] = (0.0, 0.3, -0.3)
    kinds: tuple[ShotKind, ...] = (ShotKind.DIRECT, ShotKind.BANK, ShotKind.KICK)
    max_candidates: int = 10
    max_verified: int = 6
    max_cut: float = math.radians(80.0)
    lookahead: float = 1.0
    time_budget: float | None = 0.5
    max_simulations: int = 200
    correct_aim: bool = True
    simulator_params: dict = field(default_factory=dict, hash=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "kinds", tuple(ShotKind(k) for k in self.kinds))
        if self.samples < 0 or self.max_candidates < 1 or self.max_verified < 1 or self.max_simulations < 1:
            raise ValueError("SearchConfig: samples >= 0, max_candidates, max_verified, max_simulations >= 1")
        if not self.speeds or any(not s > 0 for s in self.speeds):
            raise ValueError(f"SearchConfig.speeds must be positive, got {self.speeds}")
        if any(abs(h) > 0.5 for h in self.heights) or not self.heights:
            raise ValueError(f"SearchConfig.heights must lie in [-0.5, 0.5], got {self.heights}")
        if self.time_budget is not None and not self.time_budget > 0:
            raise ValueError(f"SearchConfig.time_budget must be positive or None, got {self.time_budget}")
        if self.lookahead < 0:
            raise ValueError(f"SearchConfig.lookahead must be >= 0, got {self.lookahead}")
        noise_model(self.noise)  # validate the name early


@dataclass(slots=True)
class _Stroke:
    hp: Hitpoint
    shot: Shot
    prior: float
    result: ShotResult | None = None
    turn: TurnResult | None = None
    successes: int = 0
    runs: int = 0
    score: float = 0.0

    @property
    def ev(self) -> float:
        return self.score / self.runs if self.runs else 0.0

    @property
    def p(self) -> float:
        return self.successes / self.runs if self.runs else 0.0


class _Budget:
    def __init__(self, cfg: SearchConfig) -> None:
        self.start = time.perf_counter()
        self.cfg = cfg
        self.sims = 0

    def left(self) -> bool:
        if self.sims >= self.cfg.max_simulations:
            return False
        tb = self.cfg.time_budget
        return tb is None or time.perf_counter() - self.start < tb


class SearchPlanner:
    """Physics-verified search planner (a :class:`~pix2pockets.planner.base.Planner`).

    Example:
        >>> planner = SearchPlanner(SearchConfig(physics="pymunk", heights=(0.0,)))  # doctest: +SKIP
        >>> best = planner.suggest(layout, GameState(Group.SOLIDS))[0]                  # doctest: +SKIP
    """

    def __init__(self, config: SearchConfig | None = None, simulator: Simulator | None = None) -> None:
        self.config = config or SearchConfig()
        self.noise: GaussianNoise = noise_model(self.config.noise)
        self.simulator = simulator or make_simulator(self.config.physics, **self.config.simulator_params)
        self.name = "search"

    # ------------------------------------------------------------------ api
    def suggest(
        self, layout: TableLayout, state: GameState, rng: np.random.Generator | None = None
    ) -> list[Suggestion]:
        """Ranked suggestions, best expected value first (never empty while a cue ball is on the table)."""
        cfg = self.config
        rng = rng if rng is not None else np.random.default_rng(0)
        budget = _Budget(cfg)
        spec = layout.spec
        sigma = max(self.noise.angle_sigma, _MIN_SIGMA)
        targets = legal_targets(layout, state)
        hps = find_hitpoints(layout, targets, kinds=cfg.kinds, max_cut=cfg.max_cut) if targets else []
        priors = [pot_probability(h, spec.ball_radius, sigma) for h in hps]
        order = sorted(range(len(hps)), key=lambda i: -priors[i])[: cfg.max_candidates]
        z = rng.standard_normal((cfg.samples, 5))

        strokes = self._verify([(hps[i], priors[i]) for i in order], layout, state, budget)
        potting = [s for s in strokes if s.turn is not None and s.turn.shot_succeeded]
        for s in potting:
            s.runs, s.successes = 1, 1
            s.score = 1.0 + cfg.lookahead * self._value(s.result, s.turn, sigma)
        potting.sort(key=lambda s: -(s.prior * s.score))
        chosen = potting[: cfg.max_verified]
        self._replay(chosen, layout, state, z, sigma, budget)
        if not chosen:
            return self._safety(strokes, layout, state)
        ranked = sorted(chosen, key=lambda s: (-s.ev, -s.p)) + potting[len(chosen) :]
        return [Suggestion(s.shot, s.hp.target, s.hp.pocket, s.hp.kind, s.p, s.ev, s.hp) for s in ranked]

    # ------------------------------------------------------------- phases
    def _simulate(self, layout: TableLayout, shot: Shot, budget: _Budget) -> ShotResult | None:
        budget.sims += 1
        try:
            return self.simulator.simulate(layout, shot)
        except RuntimeError:
            return None

    def _verify(self, ranked, layout, state, budget) -> list[_Stroke]:
        """Clean execution of every candidate stroke, in prior order, until the budget is spent."""
        cfg = self.config
        out: list[_Stroke] = []
        for hp, prior in ranked:
            heights = cfg.heights if hp.kind is ShotKind.DIRECT else (0.0,)
            for speed in cfg.speeds:
                for height in heights:
                    if not budget.left():
                        return out
                    stroke = _Stroke(hp, hp.shot(speed, height=height), prior)
                    stroke.result = self._simulate(layout, stroke.shot, budget)
                    if stroke.result is not None:
                        stroke.turn = turn_outcome(stroke.result, state)
                        if cfg.correct_aim and not stroke.turn.shot_succeeded and budget.left():
                            self._correct(stroke, layout, state, budget)
                    out.append(stroke)
        return out

    def _correct(self, stroke: _Stroke, layout, state, budget) -> None:
        """Retry a stroke that hit its target but missed the pocket, turning the object ball onto the line."""
        res = stroke.result
        hp = stroke.hp
        if res is None or res.first_contact != hp.target or hp.kind is not ShotKind.DIRECT:
            return
        # where did the object ball end up relative to its planned line? (rest position, a proxy)
        if hp.target in res.pocketed:
            return
        final_idx = res.final_ids.index(hp.target)
        b0 = layout.positions[hp.target]
        b1 = res.final.positions[final_idx]
        moved = b1 - b0
        if float(np.hypot(*moved)) < 0.05:
            return
        actual = math.atan2(moved[1], moved[0])
        err = math.atan2(math.sin(actual - hp.object_angle), math.cos(actual - hp.object_angle))
        if abs(err) > math.radians(15):  # bounced off something: the rest position says nothing
            return
        # object direction changes ~ (2r cos cut / D)-scaled with the cue angle; solve for the cue offset
        r = layout.spec.ball_radius
        gain = hp.cue_distance / (2 * r * max(math.cos(hp.cut_angle), 0.1))
        fix = -err / max(gain, 1.0)
        shot = Shot(stroke.shot.angle + fix, stroke.shot.speed, stroke.shot.side, stroke.shot.height)
        result = self._simulate(layout, shot, budget)
        if result is None:
            return
        turn = turn_outcome(result, state)
        if turn.shot_succeeded:
            stroke.shot, stroke.result, stroke.turn = shot, result, turn

    def _value(self, result: ShotResult, turn: TurnResult, sigma: float) -> float:
        if turn.outcome is Outcome.WIN:
            return 1.0
        return position_value(result.final, GameState(turn.group), sigma)

    def _replay(self, chosen: list[_Stroke], layout, state, z: np.ndarray, sigma: float, budget) -> None:
        """Noisy executions, one round over all strokes at a time, while the budget lasts."""
        cfg = self.config
        if self.noise.is_zero:
            return
        for k in range(len(z)):
            for s in chosen:
                if not budget.left():
                    return
                result = self._simulate(layout, self.noise.apply(s.shot, z[k]), budget)
                s.runs += 1
                if result is None:
                    continue
                turn = turn_outcome(result, state)
                if turn.shot_succeeded:
                    s.successes += 1
                    s.score += 1.0 + cfg.lookahead * self._value(result, turn, sigma)

    def _safety(self, strokes: list[_Stroke], layout, state) -> list[Suggestion]:
        """No pot found: a legal miss (own ball first, no foul) if one was seen, else the plain fallback."""
        legal = [s for s in strokes if s.turn is not None and s.turn.outcome is Outcome.END_TURN]
        if legal:
            s = max(legal, key=lambda s: s.prior)
            return [Suggestion(s.shot, s.hp.target, None, None, 0.0, 0.0, s.hp, safety=True)]
        return [fallback_shot(layout, state, self.config.speeds[len(self.config.speeds) // 2])]

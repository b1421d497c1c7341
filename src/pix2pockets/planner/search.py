"""Our search planner: hitpoint candidates verified by the physics engine under execution noise.

1. **Candidates**: hitpoints (direct, bank, kick) for the shooter's legal balls, ranked by a geometric
   pot probability (:func:`~pix2pockets.planner.position.pot_probability`); the best ``max_candidates``
   are expanded over ``speeds`` and tip ``heights`` (follow / draw; direct shots only).
2. **Aim fan**: every stroke is simulated without noise at ``fan`` cue angles around the ghost-ball aim,
   spread over the geometric aim tolerance. The longest run of angles that legally pot an own ball gives
   the corrected aim (its centre; engines with throw or real cushions deviate from ideal geometry) and
   its width a noise-free robustness measure. Strokes with no potting angle are dropped.
3. **Robustness and position**: the best ``max_verified`` strokes are replayed with ``samples`` noisy
   executions (common random numbers: the same draws for every stroke). Each execution scores
   ``success x (1 + lookahead x V)``, ``V`` the best next-shot pot probability from where the balls stop
   (one shot of look-ahead). The mean score ranks the suggestions; the success fraction of the noisy
   replays is their success probability.
4. **Endgame and rescue**: with at most ``endgame`` legal balls left, the best ``endgame_candidates``
   hitpoints are also expanded over a finer stroke set (more speeds and tip heights, side spin) and twice
   as many strokes are verified: cue-ball control decides the run-out there. Elsewhere, when the best
   verified stroke succeeds less often than ``rescue_below``, the same finer set is tried and merged.
5. **Two-ply look-ahead**: with at most ``two_ply`` legal balls left, the best ``two_ply_top`` verified strokes
   are valued again: from where up to ``two_ply_outcomes`` of their successful replays left the balls, the next
   shot's best ``two_ply_hitpoints`` hitpoints get an aim fan, its best ``two_ply_verified`` strokes get
   ``two_ply_samples`` noisy replays, and the best of them (success x value) replaces the geometric next-shot
   value, weighted ``two_ply_weight``. The last balls' position play then rests on simulated next shots.
6. **The winning shot**: with only the 8 left, ``final_scale`` times the replays tell close strokes apart.
7. **Fallback**: with no pot, shots at the legal balls over a range of cut offsets are tried; failing
   that, a legal safety (own ball first, no foul) or a plain shot at the nearest legal ball.

The paper's 1-ball task (only the cue ball on the table) pots the cue ball: the aim fan and the noisy
replays run over the cue ball's own pocket windows.

Simulators with a lean batch API (``simulate_arrays``, the ``event`` backend) are called in batches;
others shot by shot. ``time_budget`` [s] stops the search early (results then depend on timing; set it to
``None`` for reproducible evaluations); ``stroke_budget`` stops it after that many simulated strokes, the same on
any machine.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from pix2pockets.physics import Simulator, make_simulator
from pix2pockets.planner.base import Suggestion, cue_pot_suggestions, fallback_shot, legal_targets, lone_cue
from pix2pockets.planner.hitpoints import Hitpoint, ShotKind, find_hitpoints
from pix2pockets.planner.noise import GaussianNoise, noise_model
from pix2pockets.planner.paper_protocol import paper_continues
from pix2pockets.planner.position import fast_position_value, pot_probability
from pix2pockets.rules import GameState, Outcome, judge_for
from pix2pockets.state import BallClass, Shot, TableLayout

_MIN_SIGMA = math.radians(0.05)  # planning never assumes perfect aim
RULES = ("8ball", "blackball", "paper")
"""What :attr:`SearchConfig.rules` may name."""


@dataclass(frozen=True, slots=True)
class SearchConfig:
    """Search planner settings.

    Attributes:
        physics: simulator backend name (``make_simulator``).
        noise: planning noise model name (``noise_model``); the planner prefers strokes that survive it.
        samples: noisy executions per verified stroke.
        refine_top: the best strokes after the first replay get ``refine_samples`` more executions (less
            winner's curse when picking among close candidates).
        refine_samples: extra noisy executions for the ``refine_top`` strokes.
        widen_below: expand more hitpoints while the best aim-fan success estimate is below this.
        prior_weight: the success fraction is shrunk toward the aim-fan estimate with this many pseudo-runs.
        speeds: candidate cue-ball speeds [m/s].
        heights: vertical tip offsets (fraction of the radius; + follow, - draw) tried on direct shots.
        kinds: hitpoint kinds to consider.
        max_candidates: hitpoints expanded per decision.
        fan: cue angles per stroke in the aim fan (odd).
        max_verified: strokes that get noisy replays.
        max_cut: largest cut angle [rad].
        lookahead: weight of the next-shot value.
        endgame: with at most this many legal balls left (the group's last balls, or the 8), the best
            ``endgame_candidates`` hitpoints are expanded over ``endgame_speeds``, ``endgame_heights`` and
            ``endgame_sides`` (direct shots), and ``max_verified`` and ``refine_top`` are multiplied by
            ``endgame_scale``; 0 turns this off.
        endgame_candidates: hitpoints expanded with the endgame stroke set.
        endgame_speeds: endgame cue-ball speeds [m/s].
        endgame_heights: endgame vertical tip offsets (fraction of the radius).
        endgame_sides: endgame side tip offsets (fraction of the radius; english).
        endgame_scale: endgame multiplier of the verification effort.
        rescue_below: outside the endgame, when the best stroke's success probability is below this, the
            best ``endgame_candidates`` hitpoints are also tried with the endgame stroke set (with a
            ``time_budget``, only while at least half of it is left).
        time_budget: wall-clock limit per decision [s], ``None`` for none.
        stroke_budget: limit on the strokes simulated per decision, ``None`` for none; checked where the time budget
            is, but the same decision on any machine (a budget of work, not of seconds).
        rules: what counts as a successful stroke: ``8ball`` (a legal pot: own ball first, no scratch, the
            8 only when it wins), ``blackball`` (the same, and no opponent's ball down: WEPF rules,
            :mod:`pix2pockets.rules.blackball`) or ``paper`` (the paper's judgement: own balls drop and neither the
            cue ball, the 8 nor an opponent's ball does; see :mod:`pix2pockets.planner.paper_protocol`).
        two_ply: with at most this many legal balls left, the best strokes are valued by simulating the next
            shot (two-ply look-ahead); 0 turns this off.
        two_ply_top: verified strokes valued that way.
        two_ply_outcomes: successful noisy replays per stroke whose end positions are searched.
        two_ply_hitpoints: next-shot hitpoints given an aim fan per end position.
        two_ply_samples: noisy replays of the next shot's best ``two_ply_verified`` strokes per end position
            (their measured success replaces the aim-fan estimate); 0 values the next shot by its aim fan only.
        two_ply_verified: next-shot strokes replayed per end position.
        two_ply_weight: weight of the simulated next-shot value (``lookahead`` weighs the geometric one).
        final_scale: on the winning shot (only the 8 left), ``samples``, ``refine_samples`` and ``refine_top`` are
            multiplied by this: with no position to play for, the strokes differ by their success alone, which more
            replays tell apart (less winner's curse); 1 treats it like any other shot.
        simulator_params: keyword parameters for the simulator backend.
    """

    physics: str = "event"
    noise: str = "fastfiz"
    samples: int = 16
    refine_top: int = 3
    refine_samples: int = 32
    prior_weight: float = 2.0
    widen_below: float = 0.8
    speeds: tuple[float, ...] = (1.0, 1.8, 3.0)
    heights: tuple[float, ...] = (0.0, 0.35, -0.35)
    kinds: tuple[ShotKind, ...] = (ShotKind.DIRECT, ShotKind.BANK, ShotKind.KICK)
    max_candidates: int = 8
    fan: int = 7
    max_verified: int = 8
    max_cut: float = math.radians(80.0)
    lookahead: float = 2.0
    endgame: int = 5
    endgame_candidates: int = 6
    endgame_speeds: tuple[float, ...] = (0.7, 1.0, 1.4, 1.8, 2.4, 3.0)
    endgame_heights: tuple[float, ...] = (0.0, 0.2, 0.4, -0.2, -0.4)
    endgame_sides: tuple[float, ...] = (0.0, 0.3, -0.3)
    endgame_scale: int = 2
    rescue_below: float = 0.9
    time_budget: float | None = 0.5
    stroke_budget: int | None = None
    rules: str = "8ball"
    two_ply: int = 3
    two_ply_top: int = 6
    two_ply_outcomes: int = 8
    two_ply_hitpoints: int = 4
    two_ply_samples: int = 8
    two_ply_verified: int = 2
    two_ply_weight: float = 8.0
    final_scale: int = 3
    simulator_params: dict = field(default_factory=dict, hash=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "kinds", tuple(ShotKind(k) for k in self.kinds))
        if self.samples < 0 or self.max_candidates < 1 or self.max_verified < 1:
            raise ValueError("SearchConfig needs samples >= 0, max_candidates >= 1 and max_verified >= 1")
        if self.fan < 1 or self.fan % 2 == 0:
            raise ValueError(f"SearchConfig.fan must be a positive odd number, got {self.fan}")
        if not self.speeds or any(not s > 0 for s in self.speeds):
            raise ValueError(f"SearchConfig.speeds must be positive, got {self.speeds}")
        if not self.heights or any(abs(h) > 0.5 for h in self.heights):
            raise ValueError(f"SearchConfig.heights must lie in [-0.5, 0.5], got {self.heights}")
        if self.two_ply < 0 or self.two_ply_top < 1 or self.two_ply_outcomes < 1 or self.two_ply_hitpoints < 1:
            raise ValueError(
                "SearchConfig needs two_ply >= 0 and two_ply_top, two_ply_outcomes, two_ply_hitpoints >= 1"
            )
        if self.final_scale < 1:
            raise ValueError(f"SearchConfig.final_scale must be >= 1, got {self.final_scale}")
        if self.two_ply_samples < 0 or self.two_ply_verified < 1:
            raise ValueError("SearchConfig needs two_ply_samples >= 0 and two_ply_verified >= 1")
        if self.two_ply_samples > self.samples + self.refine_samples:
            raise ValueError(
                f"SearchConfig.two_ply_samples ({self.two_ply_samples}) cannot exceed samples + refine_samples "
                f"({self.samples + self.refine_samples}): the next shot reuses the decision's noise draws"
            )
        if self.two_ply_weight < 0:
            raise ValueError(f"SearchConfig.two_ply_weight must be >= 0, got {self.two_ply_weight}")
        if self.time_budget is not None and not self.time_budget > 0:
            raise ValueError(f"SearchConfig.time_budget must be positive or None, got {self.time_budget}")
        if self.stroke_budget is not None and not self.stroke_budget > 0:
            raise ValueError(f"SearchConfig.stroke_budget must be positive or None, got {self.stroke_budget}")
        if self.lookahead < 0:
            raise ValueError(f"SearchConfig.lookahead must be >= 0, got {self.lookahead}")
        if self.endgame < 0 or self.endgame_candidates < 1 or self.endgame_scale < 1:
            raise ValueError("SearchConfig needs endgame >= 0, endgame_candidates >= 1 and endgame_scale >= 1")
        if not self.endgame_speeds or any(not s > 0 for s in self.endgame_speeds):
            raise ValueError(f"SearchConfig.endgame_speeds must be positive, got {self.endgame_speeds}")
        tips = [math.hypot(s, h) for s in self.endgame_sides for h in self.endgame_heights]
        if not tips or max(tips) > 0.5 + 1e-9:
            raise ValueError(
                f"SearchConfig.endgame_sides {self.endgame_sides} and endgame_heights {self.endgame_heights} "
                "must combine to tip offsets within 0.5 ball radius"
            )
        noise_model(self.noise)  # validate the name early
        if self.rules not in RULES:
            raise ValueError(f"SearchConfig.rules must be one of {RULES}, got {self.rules!r}")


@dataclass(slots=True)
class _Stroke:
    """One candidate stroke and what the search learnt about it."""

    shot: Shot
    hp: Hitpoint | None
    target: int
    margin: float = 0.0  # width of the potting aim run [rad]
    pocket: int | None = None  # for strokes found without a hitpoint: where the potted own ball dropped
    clean: float = 0.0  # score of the clean execution
    runs: int = 0
    successes: int = 0
    score: float = 0.0
    prior_p: float = 1.0
    prior_weight: float = 0.0
    outcomes: list = field(default_factory=list)
    deep: float | None = None

    @property
    def ev(self) -> float:
        """Mean score of the clean and noisy runs, the success part shrunk toward the aim-fan prior."""
        if not self.runs:
            return self.clean
        if self.deep is not None:
            return self.p * self.deep
        value = self.score / max(self.successes, 1) if self.successes else self.clean
        return self.p * 0.5 * (value + self.clean)

    @property
    def p(self) -> float:
        """Estimated success probability (noisy replays shrunk toward the aim-fan prior)."""
        if not self.runs:
            return 1.0
        w = self.prior_weight
        return (self.successes + w * self.prior_p) / (self.runs + w)


class SearchPlanner:
    """Physics-verified search planner (a :class:`~pix2pockets.planner.base.Planner`).

    Example:
        >>> from pix2pockets.state import Ball, TableLayout, Group
        >>> from pix2pockets.rules import GameState
        >>> lay = TableLayout((Ball.numbered(0), Ball.numbered(1)), [[1.0, 0.3], [1.8, 0.3]])
        >>> best = SearchPlanner(SearchConfig(time_budget=None)).suggest(lay, GameState(Group.SOLIDS))[0]
        >>> best.target, best.success_probability > 0.5
        (1, True)
    """

    def __init__(self, config: SearchConfig | None = None, simulator: Simulator | None = None) -> None:
        self.config = config or SearchConfig()
        self.noise: GaussianNoise = noise_model(self.config.noise)
        self.simulator = simulator or make_simulator(self.config.physics, **self.config.simulator_params)
        self.name = "search"
        self._judge = judge_for("blackball" if self.config.rules == "blackball" else "american")
        self._deadline = math.inf
        self._strokes = 0

    # ------------------------------------------------------------------ api
    def suggest(
        self, layout: TableLayout, state: GameState, rng: np.random.Generator | None = None
    ) -> list[Suggestion]:
        """Ranked suggestions, best expected value first (never empty while a cue ball is on the table)."""
        cfg = self.config
        rng = rng if rng is not None else np.random.default_rng(0)
        tb = cfg.time_budget
        self._deadline = time.perf_counter() + tb if tb is not None else math.inf
        self._strokes = 0
        if layout.cue_index is None:
            raise ValueError("cannot plan a shot: the layout has no cue ball")
        sigma = max(self.noise.angle_sigma, _MIN_SIGMA)
        if lone_cue(layout):
            return self._pot_cue(layout, state, rng.standard_normal((cfg.samples + cfg.refine_samples, 5)), sigma)
        targets = legal_targets(layout, state)
        if not targets:
            return [fallback_shot(layout, state, cfg.speeds[0])]
        replays = cfg
        if targets == [layout.black_index] and cfg.final_scale > 1:  # the winning shot: no position to play for
            k = cfg.final_scale
            replays = replace(
                cfg, samples=k * cfg.samples, refine_samples=k * cfg.refine_samples, refine_top=k * cfg.refine_top
            )
        z = rng.standard_normal((replays.samples + replays.refine_samples, 5))
        ranked = self._ranked_hitpoints(layout, targets, sigma)
        endgame = len(targets) <= cfg.endgame
        strokes: list[_Stroke] = []
        if endgame:  # few balls left: position play decides the run-out; finer stroke control, more samples
            strokes += self._fan(ranked[: cfg.endgame_candidates], layout, state, sigma, True)
        lo, hi = (cfg.endgame_candidates, 2 * cfg.max_candidates) if endgame else (0, cfg.max_candidates)
        rounds = 0
        while lo < len(ranked) and not self._spent():
            strokes += self._fan(ranked[lo:hi], layout, state, sigma)
            lo, hi, rounds = hi, 3 * hi, rounds + 1  # widen: the next candidates, more of them
            best = max((_angle_p(s.margin, sigma) for s in strokes), default=0.0)
            if strokes and (best >= cfg.widen_below or rounds >= 2):
                break
        if not strokes and not self._spent():
            strokes = self._sweep(layout, state, sigma)
        if not strokes:
            return self._safety(layout, state, targets)
        verified, rest = self._verify(strokes, layout, state, z, sigma, cfg.endgame_scale if endgame else 1, replays)
        half_left = self._half_left()  # the pass costs about that
        if not endgame and verified[0].p < cfg.rescue_below and half_left:
            # a hard shot: the finer endgame stroke set on the best hitpoints may find a safer stroke
            extra = self._fan(ranked[: cfg.endgame_candidates], layout, state, sigma, True)
            if extra:
                more, rest2 = self._verify(extra, layout, state, z, sigma, 1)
                verified = sorted(verified + more, key=lambda s: (-s.ev, -s.p))
                rest += rest2
        if len(targets) <= cfg.two_ply:
            verified = self._two_ply(verified, layout, state, z, sigma)
        return [self._suggestion(s) for s in verified + rest]

    def _two_ply(self, verified: list[_Stroke], layout, state, z: np.ndarray, sigma: float) -> list[_Stroke]:
        """Re-value the best verified strokes by simulating the next shot from where their successful replays
        left the balls. Under a time budget all of them are re-valued or, when time runs out, none."""
        cfg = self.config
        top = verified[: cfg.two_ply_top]
        deep: list[float | None] = []
        for s in top:
            if self._spent():
                return verified
            values = [self._next_value(layout, state, pr, fr, sigma, z) for pr, fr in s.outcomes]
            deep.append(1.0 + cfg.two_ply_weight * float(np.mean(values)) if values else None)
        if self._spent():  # the last strokes' fans may have been cut short
            return verified
        for s, d in zip(top, deep, strict=True):
            s.deep = d
        return sorted(top, key=lambda s: (-s.ev, -s.p)) + verified[cfg.two_ply_top :]

    def _next_value(self, layout, state, pocket_row, final_row, sigma, z: np.ndarray | None = None) -> float:
        """Simulated next-shot value: the best next stroke's success x clean value, success measured over the
        first ``two_ply_samples`` noise draws of ``z`` (or, without draws, its aim-fan estimate)."""
        keep = pocket_row < 0
        balls = [b for b, k in zip(layout.balls, keep, strict=True) if k]
        if not any(b.ball_class is BallClass.BLACK for b in balls) and layout.black_index is not None:
            return 1.0
        try:
            nxt = TableLayout(tuple(balls), final_row[keep], layout.spec)
        except ValueError:
            return self._value(layout, state, pocket_row, final_row, sigma)
        if nxt.cue_index is None:
            return 0.0
        targets = legal_targets(nxt, state)
        if not targets:
            return 0.0
        ranked = self._ranked_hitpoints(nxt, targets, sigma)
        cfg = self.config
        strokes = self._fan(ranked[: cfg.two_ply_hitpoints], nxt, state, sigma)
        z = np.zeros((0, 5)) if z is None else z[: cfg.two_ply_samples]
        if len(z) and strokes and not self.noise.is_zero:
            strokes = self._shortlist(strokes, cfg.two_ply_verified, sigma)
            self._replay(strokes, nxt, state, z, sigma, keep_outcomes=False)
            best = max(s.ev for s in strokes)
        else:
            best = max((_angle_p(s.margin, sigma) * s.clean for s in strokes), default=0.0)
        return best / (1.0 + cfg.lookahead)

    def _ranked_hitpoints(self, layout: TableLayout, targets: list[int], sigma: float) -> list[Hitpoint]:
        """Hitpoints at ``targets``, the likeliest pot under aim noise ``sigma`` [rad] first."""
        half_contact = 0.5 * layout.spec.cue_contact_distance  # the ball radius, unless the cue ball is smaller
        hps = find_hitpoints(layout, targets, kinds=self.config.kinds, max_cut=self.config.max_cut)
        priors = [pot_probability(h, half_contact, sigma) for h in hps]
        order = sorted(range(len(hps)), key=lambda i: -priors[i])
        return [hps[i] for i in order]

    def _shortlist(self, strokes: list[_Stroke], n: int, sigma: float) -> list[_Stroke]:
        """Sort ``strokes`` by aim-fan score (in place) and return the best ``n``, their success prior set."""
        strokes.sort(key=lambda s: -s.clean * _angle_p(s.margin, sigma))
        for s in strokes[:n]:
            s.prior_p, s.prior_weight = _angle_p(s.margin, sigma), self.config.prior_weight
        return strokes[:n]

    def _verify(
        self, strokes, layout, state, z, sigma, scale: int, cfg: SearchConfig | None = None
    ) -> tuple[list[_Stroke], list[_Stroke]]:
        """Noisy replays of the most promising strokes: (verified ranked by value, the rest); ``cfg`` sets how many
        (default: the planner's)."""
        cfg = cfg or self.config
        n_verified = cfg.max_verified * scale
        verified = self._shortlist(strokes, n_verified, sigma)
        self._replay(verified, layout, state, z[: cfg.samples], sigma)
        verified.sort(key=lambda s: (-s.ev, -s.p))
        self._replay(verified[: cfg.refine_top * scale], layout, state, z[cfg.samples :], sigma)
        verified.sort(key=lambda s: (-s.ev, -s.p))
        return verified, strokes[n_verified:]

    # -------------------------------------------------------------- phases
    def _pot_cue(self, layout, state, z, sigma) -> list[Suggestion]:
        """The paper's 1-ball task: pot the lone cue ball (aim fan and noisy replays per pocket window)."""
        cfg = self.config
        meta, rows = [], []
        for sug in cue_pot_suggestions(layout, cfg.speeds[0]):
            offsets = np.linspace(-0.75, 0.75, cfg.fan) * min(sug.value, math.radians(4.0))
            for speed in cfg.speeds:
                meta.append((None, speed, 0.0, 0.0, offsets, layout.cue_index))
                rows.extend((sug.shot.angle + o, speed, 0.0, 0.0, 0.0) for o in offsets)
        strokes = self._fan_select(meta, np.array(rows).reshape(-1, 5), layout, state, sigma)
        if not strokes:
            return [fallback_shot(layout, state, cfg.speeds[0])]
        for s in strokes:
            s.prior_p, s.prior_weight = _angle_p(s.margin, sigma), cfg.prior_weight
        self._replay(strokes, layout, state, z, sigma)
        strokes.sort(key=lambda s: (-s.ev, -s.p))
        return [self._suggestion(s) for s in strokes]

    def _fan(self, hps: list[Hitpoint], layout, state, sigma, endgame: bool = False) -> list[_Stroke]:
        """Clean executions over an aim fan per stroke; keep the strokes with a potting run."""
        cfg = self.config
        contact = layout.spec.cue_contact_distance
        speeds = cfg.endgame_speeds if endgame else cfg.speeds
        rows, meta = [], []
        for hp in hps:
            gain = max(hp.cue_distance / (contact * max(math.cos(hp.cut_angle), 0.1)), 1.0)
            tol = float(np.clip(0.5 * hp.clear_window / gain, math.radians(0.03), math.radians(2.0)))
            offsets = np.linspace(-1.5 * tol, 1.5 * tol, cfg.fan)
            direct = hp.kind is ShotKind.DIRECT
            heights = (cfg.endgame_heights if endgame else cfg.heights) if direct else (0.0,)
            sides = cfg.endgame_sides if endgame and direct else (0.0,)
            for speed in speeds:
                for height in heights:
                    for side in sides:
                        meta.append((hp, speed, side, height, offsets, hp.target))
                        rows.extend((hp.cue_angle + o, speed, side, height, 0.0) for o in offsets)
        return self._fan_select(meta, np.array(rows).reshape(-1, 5), layout, state, sigma)

    def _fan_select(self, meta, rows, layout, state, sigma) -> list[_Stroke]:
        cfg = self.config
        if len(rows) == 0:
            return []
        first, pocket, final = self._run(layout, rows)
        ok = self._success(first, pocket, layout, state)
        out: list[_Stroke] = []
        for k, (hp, speed, side, height, offsets, target) in enumerate(meta):
            seg = ok[k * len(offsets) : (k + 1) * len(offsets)]
            start, length = _longest_run(seg)
            if length == 0:
                continue
            centre = start + (length - 1) // 2
            row = k * len(offsets) + centre
            step = float(offsets[1] - offsets[0]) if len(offsets) > 1 else math.radians(0.1)
            stroke = _Stroke(Shot(float(rows[row, 0]), speed, side, height), hp, target, margin=length * step)
            if hp is None:
                stroke.pocket = int(pocket[row, target])
            stroke.clean = 1.0 + cfg.lookahead * self._value(layout, state, pocket[row], final[row], sigma)
            out.append(stroke)
            if self._spent():
                break
        return out

    def _sweep(self, layout, state, sigma) -> list[_Stroke]:
        """No hitpoint pots: sweep the full circle of cue angles (finds multi-cushion kicks, combinations)."""
        cfg = self.config
        step = math.radians(0.25)
        angles = np.arange(0.0, 2 * math.pi, step)
        speeds = (cfg.speeds[len(cfg.speeds) // 2], cfg.speeds[-1])
        rows = np.array([(a, v, 0.0, 0.0, 0.0) for v in speeds for a in angles])
        first, pocket, final = self._run(layout, rows)
        ok = self._success(first, pocket, layout, state)
        out: list[_Stroke] = []
        n = len(angles)
        for j, speed in enumerate(speeds):
            seg = ok[j * n : (j + 1) * n]
            for start, length in _runs(seg):
                centre = j * n + (start + (length - 1) // 2) % n
                potted = self._potted_target(pocket[centre], layout, state)
                target = int(first[centre]) if potted is None else potted
                stroke = _Stroke(Shot(float(rows[centre, 0]), speed), None, target, length * step)
                stroke.pocket = None if potted is None else int(pocket[centre, potted])
                stroke.clean = 1.0 + cfg.lookahead * self._value(layout, state, pocket[centre], final[centre], sigma)
                out.append(stroke)
        return out

    def _replay(
        self, strokes: list[_Stroke], layout, state, z: np.ndarray, sigma: float, keep_outcomes: bool = True
    ) -> None:
        """Noisy executions of the verified strokes with shared draws ``z``."""
        if self.noise.is_zero or len(z) == 0 or not strokes or self._spent():
            return
        shots = [self.noise.apply(s.shot, zk) for s in strokes for zk in z]
        rows = np.array([(s.angle, s.speed, s.side, s.height, s.elevation) for s in shots])
        first, pocket, final = self._run(layout, rows)
        ok = self._success(first, pocket, layout, state)
        n = len(z)
        for i, s in enumerate(strokes):
            for k in range(n):
                row = i * n + k
                s.runs += 1
                if ok[row]:
                    s.successes += 1
                    if keep_outcomes and self.config.two_ply and len(s.outcomes) < self.config.two_ply_outcomes:
                        s.outcomes.append((pocket[row], final[row]))
                    if not self._spent():
                        v = self._value(layout, state, pocket[row], final[row], sigma)
                    else:
                        v = s.clean - 1.0
                    s.score += 1.0 + self.config.lookahead * v

    # ------------------------------------------------------------- helpers
    def _spent(self) -> bool:
        """Whether the decision's time or stroke budget is used up."""
        cap = self.config.stroke_budget
        return time.perf_counter() > self._deadline or (cap is not None and self._strokes >= cap)

    def _half_left(self) -> bool:
        """Whether at least half of each budget the decision has is left."""
        tb, cap = self.config.time_budget, self.config.stroke_budget
        time_left = tb is None or self._deadline - time.perf_counter() > 0.5 * tb
        return time_left and (cap is None or self._strokes < 0.5 * cap)

    def _run(self, layout: TableLayout, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Simulate strokes (m, 5): first contact (m,), pocket per ball (m, n), final centres (m, n, 2)."""
        sim = self.simulator
        self._strokes += len(rows)
        if hasattr(sim, "simulate_arrays"):
            out = sim.simulate_arrays(layout, rows)
            failed = out.status != 0
            first = np.where(failed, -1, out.first_contact)
            pocket = out.pocket.copy()
            pocket[failed, layout.cue_index] = 0  # a failed simulation counts as a scratch (no success)
            return first, pocket, out.final_positions
        m, n = len(rows), len(layout)
        first = np.full(m, -1)
        pocket = np.full((m, n), -1)
        final = np.repeat(layout.positions[None], m, axis=0).copy()
        for i, row in enumerate(rows):
            shot = Shot(float(row[0]), float(max(row[1], 0.0)), float(row[2]), float(row[3]), float(row[4]))
            try:
                res = sim.simulate(layout, shot)
            except RuntimeError:
                pocket[i, layout.cue_index] = 0
                continue
            first[i] = -1 if res.first_contact is None else res.first_contact
            for b, p in zip(res.pocketed, res.pocketed_into, strict=True):
                pocket[i, b] = p
            final[i, list(res.final_ids)] = res.final.positions
        return first, pocket, final

    def _success(self, first: np.ndarray, pocket: np.ndarray, layout: TableLayout, state: GameState) -> np.ndarray:
        """Legal pot of an own ball (or the winning 8), from lean outcome arrays.

        Mirrors :func:`~pix2pockets.rules.turn_outcome` for the success case: a pot makes the
        no-rail rule moot, so first contact, scratch, the 8 and own pots decide. With ``rules="paper"``
        it mirrors :func:`~pix2pockets.planner.paper_protocol.paper_turn_outcome` (continue or win).
        """
        cue, black = layout.cue_index, layout.black_index
        if lone_cue(layout):  # the 1-ball task: the cue ball is the target
            return pocket[:, cue] >= 0
        if self.config.rules == "paper" and state.group is not None:
            return paper_continues(pocket, layout, state)
        classes = np.array([b.ball_class.value for b in layout.balls])
        potted = pocket >= 0
        valid_first = first >= 0
        hit = np.where(valid_first, classes[np.maximum(first, 0)], "")
        if state.group is None:
            own_mask = np.isin(classes, [BallClass.SOLID.value, BallClass.STRIPE.value])
            legal_first = np.isin(hit, [BallClass.SOLID.value, BallClass.STRIPE.value])
            cleared = False
        else:
            own_mask = classes == state.group.ball_class.value
            cleared = not own_mask.any()
            legal_first = hit == (BallClass.BLACK.value if cleared else state.group.ball_class.value)
        no_foul = valid_first & legal_first & ~potted[:, cue]
        if self.config.rules == "blackball" and state.group is not None:  # an opponent's ball down is a foul
            no_foul &= ~np.any(potted & (classes == state.group.other.ball_class.value)[None, :], axis=1)
        black_potted = potted[:, black] if black is not None else np.zeros(len(first), dtype=bool)
        if cleared:
            return no_foul & black_potted
        return no_foul & ~black_potted & np.any(potted & own_mask[None, :], axis=1)

    def _value(self, layout: TableLayout, state: GameState, pocket_row, final_row, sigma: float) -> float:
        """Next-shot value after a successful shot with these outcome rows."""
        if lone_cue(layout):
            return 1.0
        keep = pocket_row < 0
        balls = [b for b, k in zip(layout.balls, keep, strict=True) if k]
        if not any(b.ball_class is BallClass.BLACK for b in balls) and layout.black_index is not None:
            return 1.0  # the 8 went down legally: game won
        group = state.group
        if group is None:  # open table: the first own pot decides; take the lowest potted object ball's group
            potted = [layout.balls[i].group for i in np.flatnonzero(~keep)]
            group = next((g for g in potted if g is not None), None)
        own = [i for i, b in enumerate(balls) if group is not None and b.ball_class is group.ball_class]
        if not own:
            own = [i for i, b in enumerate(balls) if b.ball_class is BallClass.BLACK]
        cue = next(i for i, b in enumerate(balls) if b.ball_class is BallClass.CUE)
        return fast_position_value(final_row[keep], cue, own, layout.spec, sigma)

    def _safety(self, layout: TableLayout, state: GameState, targets: list[int]) -> list[Suggestion]:
        """Nothing pots: the first stroke at a legal ball that verifies as foul-free, else the plain fallback."""
        pos = layout.positions
        c = pos[layout.cue_index]
        base = fallback_shot(layout, state, self.config.speeds[len(self.config.speeds) // 2])
        order = sorted(targets, key=lambda t: float(np.hypot(*(pos[t] - c))))
        for t in order[:4]:
            for speed in self.config.speeds:
                shot = Shot.toward(tuple(c), tuple(pos[t]), speed)
                try:
                    res = self.simulator.simulate(layout, shot)
                except RuntimeError:
                    continue
                if self._judge(res, state).outcome is Outcome.END_TURN:
                    return [Suggestion(shot, t, None, None, 0.0, 0.0, None, safety=True), base]
        return [base]

    @staticmethod
    def _potted_target(pocket_row: np.ndarray, layout: TableLayout, state: GameState) -> int | None:
        """The first legal target (by index) that dropped in this outcome row, if any."""
        for i in legal_targets(layout, state):
            if pocket_row[i] >= 0:
                return i
        return None

    @staticmethod
    def _suggestion(s: _Stroke) -> Suggestion:
        hp = s.hp
        if hp is None:  # found by the full-circle sweep: a combination or multi-cushion shot
            return Suggestion(s.shot, s.target, s.pocket, None, s.p, s.ev, None)
        return Suggestion(s.shot, hp.target, hp.pocket, hp.kind, s.p, s.ev, hp)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(start, length) of every run of True values, treating ``mask`` as circular."""
    m = np.asarray(mask, dtype=bool)
    if m.all():
        return [(0, len(m))]
    shift = int(np.argmin(m))  # start the scan at a False so no run wraps
    rolled = np.roll(m, -shift)
    runs, start = [], None
    for i, v in enumerate([*rolled.tolist(), False]):
        if v and start is None:
            start = i
        elif not v and start is not None:
            runs.append(((start + shift) % len(m), i - start))
            start = None
    return runs


def _longest_run(mask: np.ndarray) -> tuple[int, int]:
    """Start and length of the longest run of True values."""
    best_start, best_len, start = 0, 0, None
    for i, v in enumerate([*list(mask), False]):
        if v and start is None:
            start = i
        elif not v and start is not None:
            if i - start > best_len:
                best_start, best_len = start, i - start
            start = None
    return best_start, best_len


def _angle_p(margin: float, sigma: float) -> float:
    """Probability that aim noise ``sigma`` stays inside a potting run of width ``margin`` [rad]."""
    return math.erf(0.5 * margin / (sigma * math.sqrt(2.0)))

"""The paper's planner experiments: aim precision (Fig. 4b) and ball shift (sec. 6.2).

* **Aim precision**: success of one shot in the 1-ball and 2-ball environments when the cue direction
  gets Gaussian noise of standard deviation sigma (0-5 degrees). As in the paper, the 1-ball environment
  holds only the cue ball and the goal is to pot it (:func:`cue_pot_precision`: aimed at the middle of
  the widest clear pocket window); the 2-ball environment is the cue ball and the 8.
* **Ball shift**: in the 2-ball environment the planner plans on the layout it sees; the shot is then
  played with the target ball moved in a random direction by a distance drawn uniformly from the measured
  location error (shift-1; the paper's 0.22-0.76 cm) or by a fixed 2.5 cm (shift-2).
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from pix2pockets.planner.base import Planner
from pix2pockets.planner.evaluation import environment_state, evaluate_planner, sample_environment, wilson_interval
from pix2pockets.planner.hitpoints import pocket_window
from pix2pockets.planner.noise import aim_noise
from pix2pockets.rules import GameState, turn_outcome
from pix2pockets.state import Shot, ShotResult, TableLayout, random_layout

PAPER_SIGMAS_DEG: tuple[float, ...] = (0.0, 0.01, 0.05, 0.1, 0.25, 1.0, 3.0, 5.0)
"""Aim-noise levels of the paper's Fig. 4b [deg]."""

PAPER_SHIFT1 = (0.0022, 0.0076)
"""Range of the paper's measured mean projection shifts, best to worst camera view [m]."""

PAPER_SHIFT2 = 0.025
"""The paper's large fixed shift [m]."""


@dataclass(frozen=True, slots=True)
class Rate:
    """A success rate with its 95% Wilson interval."""

    successes: int
    trials: int

    @property
    def value(self) -> float:
        return self.successes / self.trials if self.trials else 0.0

    @property
    def ci95(self) -> tuple[float, float]:
        return wilson_interval(self.successes, self.trials)

    def to_dict(self) -> dict:
        return {"rate": self.value, "ci95": list(self.ci95), "successes": self.successes, "trials": self.trials}


def aim_precision(
    make: Callable[[float], Planner],
    simulate: Callable[[TableLayout, Shot], ShotResult],
    balls: int,
    sigmas_deg: Sequence[float] = PAPER_SIGMAS_DEG,
    layouts: int = 200,
    seed: int = 0,
) -> dict[float, Rate]:
    """One-shot success per aim sigma [deg] in the ``balls`` (1 or 2) environment.

    Args:
        make: builds the planner for a sigma (a search planner may plan for the noise it will get).
        simulate: the simulator.
        balls: 1 or 2.
        sigmas_deg: aim-noise standard deviations [deg].
        layouts: layouts per sigma (the same layouts for every sigma).
        seed: layout and noise seed.
    """
    if balls not in (1, 2):
        raise ValueError(f"the aim-precision experiment uses the 1- or 2-ball environment, got {balls}")
    out: dict[float, Rate] = {}
    for sigma in sigmas_deg:
        if not (math.isfinite(sigma) and sigma >= 0):
            raise ValueError(f"aim sigma must be >= 0 degrees, got {sigma}")
        s = evaluate_planner(make(sigma), simulate, balls, layouts, seed, aim_noise(sigma))
        out[float(sigma)] = Rate(s.clears, s.turns)
    return out


def cue_pot_precision(
    simulate: Callable[[TableLayout, Shot], ShotResult],
    sigmas_deg: Sequence[float] = PAPER_SIGMAS_DEG,
    layouts: int = 200,
    seed: int = 0,
    speed: float = 3.0,
) -> dict[float, Rate]:
    """The paper's 1-ball environment: pot the lone cue ball, aimed at the widest clear pocket window.

    Args:
        simulate: the simulator.
        sigmas_deg: aim-noise standard deviations [deg].
        layouts: random cue-ball spots per sigma (the same for every sigma).
        seed: layout and noise seed.
        speed: stroke speed [m/s].
    """
    out: dict[float, Rate] = {}
    for sigma in sigmas_deg:
        if not (math.isfinite(sigma) and sigma >= 0):
            raise ValueError(f"aim sigma must be >= 0 degrees, got {sigma}")
        noise = aim_noise(sigma)
        wins = 0
        for i in range(layouts):
            layout = random_layout(np.random.default_rng([seed, i, 0]), [0])
            c = layout.positions[0]
            r = layout.spec.ball_radius
            best = max(
                (w for w in (pocket_window(c, p.jaws, r) for p in layout.spec.pockets) if w is not None),
                key=lambda w: w[2],
                default=None,
            )
            if best is None:
                continue
            shot = noise.perturb(Shot(angle=best[1], speed=speed), np.random.default_rng([seed, i, 2]))
            with contextlib.suppress(RuntimeError):  # a simulator time-out counts as a miss
                wins += simulate(layout, shot).cue_pocketed
        out[float(sigma)] = Rate(wins, layouts)
    return out


def shifted(layout: TableLayout, index: int, distance: float, rng: np.random.Generator, tries: int = 50) -> TableLayout:
    """``layout`` with ball ``index`` moved ``distance`` [m] in a random valid direction."""
    for _ in range(tries):
        a = rng.uniform(0.0, 2 * math.pi)
        pos = np.array(layout.positions)
        pos[index] += distance * np.array([math.cos(a), math.sin(a)])
        try:
            return layout.with_positions(pos)
        except ValueError:
            continue
    return layout  # boxed in: no valid shift (rare); the shot is played unshifted


def ball_shift(
    planner: Planner,
    simulate: Callable[[TableLayout, Shot], ShotResult],
    layouts: int = 200,
    seed: int = 0,
    shift1: tuple[float, float] = PAPER_SHIFT1,
    shift2: float = PAPER_SHIFT2,
) -> dict[str, Rate]:
    """2-ball success with the target unshifted, shifted by U(shift1) [m] and by ``shift2`` [m]."""
    lo, hi = shift1
    if not 0 <= lo <= hi or shift2 < 0:
        raise ValueError(f"shifts must be >= 0 with lo <= hi, got shift1={shift1}, shift2={shift2}")
    state: GameState = environment_state(2)
    wins = {"none": 0, "shift1": 0, "shift2": 0}
    for i in range(layouts):
        layout = sample_environment(2, np.random.default_rng([seed, i, 0]))
        rng = np.random.default_rng([seed, i, 3])
        shot = planner.suggest(layout, state, np.random.default_rng([seed, i, 1]))[0].shot
        target = layout.black_index
        cases = {
            "none": layout,
            "shift1": shifted(layout, target, rng.uniform(lo, hi), rng),
            "shift2": shifted(layout, target, shift2, rng),
        }
        for name, lay in cases.items():
            try:
                won = turn_outcome(simulate(lay, shot), state).shot_succeeded
            except RuntimeError:
                won = False
            wins[name] += won
    return {k: Rate(v, layouts) for k, v in wins.items()}

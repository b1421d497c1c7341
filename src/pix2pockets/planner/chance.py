"""Success chances that mean something: the measured fraction of sampled executions that succeed.

A stroke's chance is measured by replaying it ``samples`` times under a noise model (fresh draws, not the
planner's own replays, so the choice of the best stroke does not bias it), optionally with the balls'
positions jittered to model the photo's location error. It is reported with its sample size and shown
rounded; a finite sample never shows "100%" or "0%" (``">99%"``, ``"<1%"``).

Example:
    >>> Chance(200, 200).text, Chance(130, 200).text, Chance(0, 200).text
    ('>99%', '65%', '<1%')
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pix2pockets.planner.evaluation import wilson_interval
from pix2pockets.planner.noise import GaussianNoise
from pix2pockets.rules import GameState
from pix2pockets.state import Shot, TableLayout


@dataclass(frozen=True, slots=True)
class Chance:
    """A measured success chance.

    Attributes:
        successes: sampled executions that succeeded.
        samples: sampled executions.
        noise: name of the noise model the executions were drawn from.
        position_sigma: ball-position error per axis used for the draws [m] (0: positions as given; with an error
            per ball, the median of the balls' errors along their worst direction).
        pocket_sigma: error per axis of where the pocket lies [m] used for the draws (0: the pocket is where the table
            fit puts it; a pocket out of the photo is not fixed by it).
    """

    successes: int
    samples: int
    noise: str = ""
    position_sigma: float = 0.0
    pocket_sigma: float = 0.0

    def __post_init__(self) -> None:
        if self.samples < 1 or not 0 <= self.successes <= self.samples:
            raise ValueError(f"Chance needs 0 <= successes <= samples and samples >= 1, got {self}")

    @property
    def p(self) -> float:
        """Measured fraction in [0, 1]."""
        return self.successes / self.samples

    @property
    def ci95(self) -> tuple[float, float]:
        """95% Wilson interval of the chance."""
        return wilson_interval(self.successes, self.samples)

    @property
    def text(self) -> str:
        """The chance for people, whole percent; never 100% or 0% from a finite sample."""
        return format_chance(self.p)

    def to_dict(self) -> dict:
        lo, hi = self.ci95
        return {
            "chance": round(self.p, 4),
            "text": self.text,
            "successes": self.successes,
            "samples": self.samples,
            "ci95": [round(lo, 4), round(hi, 4)],
            "noise": self.noise,
            "position_sigma_m": self.position_sigma,
            "pocket_sigma_m": self.pocket_sigma,
        }


def format_chance(p: float) -> str:
    """Whole percent, with ``>99%`` and ``<1%`` at the ends (a sample never proves certainty)."""
    if p > 0.99:
        return ">99%"
    if p < 0.01:
        return "<1%"
    return f"{min(max(round(100 * p), 1), 99)}%"


def measure_chance(
    planner,
    layout: TableLayout,
    state: GameState,
    shot: Shot,
    noise: GaussianNoise | None = None,
    samples: int = 200,
    rng: np.random.Generator | None = None,
    position_sigma: float | np.ndarray = 0.0,
    position_draws: int = 20,
    target: int | None = None,
    aim_point: np.ndarray | tuple[float, float] | None = None,
    pocket_sigma: float = 0.0,
    pocket_distance: float | None = None,
) -> Chance:
    """Replay ``shot`` ``samples`` times under ``noise`` and count legal successes.

    Args:
        planner: a :class:`~pix2pockets.planner.search.SearchPlanner` (its simulator and success test are used).
        layout: the table.
        state: the shooter's group.
        shot: the planned stroke.
        noise: execution noise (default: the planner's planning noise).
        samples: executions drawn.
        rng: randomness (default: seed 0).
        position_sigma: Gaussian error per axis of every ball's position [m], or each ball's position covariance
            (n, 2, 2) [m^2] (the photo's location error, :mod:`pix2pockets.vision.locate.position_error`); the draws
            are split over ``position_draws`` jittered layouts.
        position_draws: jittered layouts when ``position_sigma`` > 0.
        target: index of the object ball the stroke aims at; with ``aim_point`` the player re-aims on each
            jittered layout (a player aims at the real balls, not at the photo's coordinates).
        aim_point: where the cue ball is sent on the given layout [m] (the ghost-ball centre); it moves with
            the target ball and the stroke's direction is taken from the moved cue ball to it.
        pocket_sigma: Gaussian error per axis of where the pocket lies [m] (a pocket out of the photo): each execution
            sends the target ball along its planned line toward a pocket that lies elsewhere, i.e. turned by the
            error's part across the line over ``pocket_distance``. Needs ``target`` and ``aim_point``.
        pocket_distance: how far the target ball travels to the pocket [m] (along its path, cushions included).

    Raises:
        ValueError: ``samples`` < 1, a negative error, or ``pocket_sigma`` without a target, aim point or distance.
    """
    if samples < 1:
        raise ValueError(f"samples must be >= 1, got {samples}")
    if not pocket_sigma >= 0:
        raise ValueError(f"pocket_sigma must be >= 0, got {pocket_sigma}")
    if pocket_sigma > 0 and (target is None or aim_point is None or not (pocket_distance or 0) > 0):
        raise ValueError("pocket_sigma needs the target ball, its aim point and a positive pocket_distance")
    spread = position_spread(position_sigma, len(layout.positions))
    noise = noise if noise is not None else planner.noise
    rng = rng if rng is not None else np.random.default_rng(0)
    z = rng.standard_normal((samples, 5))
    turns = rng.standard_normal(samples) * (pocket_sigma / pocket_distance) if pocket_sigma > 0 else np.zeros(samples)
    if spread is not None:
        groups = np.array_split(np.arange(samples), max(1, min(position_draws, samples)))
        layouts = [_jitter(layout, spread, rng) for _ in groups]
    else:
        groups, layouts = [np.arange(samples)], [layout]
    successes = 0
    for idx, lay in zip(groups, layouts, strict=True):
        shots = [noise.apply(_reaim(shot, layout, lay, target, aim_point, turns[k]), z[k]) for k in idx]
        rows = np.array([(s.angle, s.speed, s.side, s.height, s.elevation) for s in shots])
        first, pocket, _ = planner._run(lay, rows)
        successes += int(np.count_nonzero(planner._success(first, pocket, lay, state)))
    shown = 0.0 if spread is None else float(np.median(np.sqrt(np.linalg.eigvalsh(spread)[:, -1])))
    return Chance(successes, samples, noise.name, shown, float(pocket_sigma))


def position_spread(position_sigma: float | np.ndarray, n_balls: int) -> np.ndarray | None:
    """Each ball's position covariance (n, 2, 2) [m^2] from an error per axis [m] or from covariances; ``None`` for no
    error.

    Raises:
        ValueError: a negative error, or covariances of another shape than (n, 2, 2).
    """
    if np.ndim(position_sigma) == 0:
        sigma = float(position_sigma)
        if not sigma >= 0:
            raise ValueError(f"position_sigma must be >= 0, got {position_sigma}")
        return None if sigma == 0 else np.tile(np.eye(2) * sigma**2, (n_balls, 1, 1))
    cov = np.asarray(position_sigma, dtype=float)
    if cov.shape != (n_balls, 2, 2) or not np.all(np.isfinite(cov)):
        raise ValueError(f"position covariances must be finite and of shape ({n_balls}, 2, 2), got {cov.shape}")
    return cov


def _reaim(
    shot: Shot, layout: TableLayout, moved: TableLayout, target: int | None, aim_point, turn: float = 0.0
) -> Shot:
    """``shot`` aimed on ``moved`` as a player would: the aim point follows the target ball, turned about it by
    ``turn`` [rad] (which turns the target ball's line by as much)."""
    if (moved is layout and turn == 0.0) or target is None or aim_point is None or layout.cue_index is None:
        return shot
    ball = layout.positions[target]
    c, s = math.cos(turn), math.sin(turn)
    offset = np.asarray(aim_point, dtype=float) - ball
    point = ball + np.array([c * offset[0] - s * offset[1], s * offset[0] + c * offset[1]])
    point = point + (moved.positions[target] - ball)
    d = point - moved.positions[moved.cue_index]
    if not np.hypot(*d) > 1e-9:
        return shot
    return Shot(float(np.arctan2(d[1], d[0])), shot.speed, shot.side, shot.height, shot.elevation)


def _jitter(layout: TableLayout, cov: np.ndarray, rng: np.random.Generator) -> TableLayout:
    """The layout with each ball moved by Gaussian noise of its covariance (n, 2, 2) [m^2], kept on the cloth and
    apart."""
    spec = layout.spec
    r = spec.ball_radius
    root = np.linalg.cholesky(cov + np.eye(2) * 1e-18)  # a ball known exactly has no Cholesky factor without it
    pos = layout.positions + np.einsum("nij,nj->ni", root, rng.standard_normal(layout.positions.shape))
    pos[:, 0] = np.clip(pos[:, 0], r, spec.length - r)
    pos[:, 1] = np.clip(pos[:, 1], r, spec.width - r)
    for _ in range(10):  # push overlapping pairs apart (rare at photo-error sizes)
        d = pos[:, None, :] - pos[None, :, :]
        dist = np.hypot(d[..., 0], d[..., 1]) + np.eye(len(pos)) * 1e9
        i, j = np.unravel_index(np.argmin(dist), dist.shape)
        if dist[i, j] >= 2 * r:
            break
        u = d[i, j] / max(dist[i, j], 1e-9)
        push = 0.5 * (2 * r - dist[i, j]) + 1e-6
        pos[i] += u * push
        pos[j] -= u * push
        pos[:, 0] = np.clip(pos[:, 0], r, spec.length - r)
        pos[:, 1] = np.clip(pos[:, 1], r, spec.width - r)
    try:
        return TableLayout(layout.balls, pos, spec)
    except ValueError:  # a crowded cluster that would not separate: keep the positions as located
        return layout

"""The paper's Oracle as its environment code computes it, for the ``paper`` physics.

The paper describes its Oracle in a few lines (:mod:`pix2pockets.planner.oracle` is that description on
any table); the figures it reports come from its code, whose hitpoints differ in detail. This module
computes them the way the code does, on the paper's own layout (pixels of its zoom-2 world, see
:class:`~pix2pockets.geometry.raster.PaperEnvLayout`):

* **Aiming points**: a pocket is aimed at where the two ball-centre lines meet at a corner, or at the
  middle of a long rail's ball-centre line (:attr:`PaperEnvLayout.target_points`), not at the mouth.
* **Window**: the angle between the two jaw points as seen from the object ball, divided by 60 degrees.
* **Cut**: the cosine between the cue ball's direction to the ghost ball and the object ball's direction
  to the aiming point; cuts over 80 degrees are dropped.
* **Blocking**: a path (object ball to aiming point, cue ball to ghost ball) is blocked when any ball, any
  aiming point or (mirror mode) any mirrored ball passes within two ball radii of it, ends included.
* **Mirror mode**: every ball, and every aiming point more than a pocket radius from the line, is mirrored
  across each of the four ball-centre lines (a ball within one ball radius of a line gets no image there).
  Object balls and their images aim at real and mirrored aiming points; multipliers 1 (direct), 1/2 (real
  ball to a mirrored point: bank), 3/4 and 1/4 (an image: kick). The code picks 3/4 when the *position of
  the image in its list of images of all the shooter's balls* (1-based) equals the mirror side (1-4) of the
  aiming point, 1/4 otherwise; ``kick_rule="side"`` compares the image's own mirror side instead.
* **No hitpoint**: the best-scoring candidate among all of them, blocked and over-cut ones included.

The stroke is always the top power level (500 px/s, :data:`~pix2pockets.physics.paper.PAPER_MAX_SPEED`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from pix2pockets.geometry.raster import PAPER_LAYOUT
from pix2pockets.physics.paper.simulator import paper_level_speed
from pix2pockets.planner.base import Suggestion, fallback_shot, legal_targets, lone_cue
from pix2pockets.planner.hitpoints import ShotKind
from pix2pockets.planner.oracle import OracleMode
from pix2pockets.rules import GameState
from pix2pockets.state import Shot, TableLayout

_PAPER_ORDER = (0, 2, 3, 5, 4, 1)  # its aiming points' order, as indices into TableSpec.pockets
_LEVELS = 30


class KickRule(StrEnum):
    """How the paper Oracle tells a kick (3/4) from other shots off a mirrored ball (1/4)."""

    CODE = "code"  # the image's position in the list of all images equals the aiming point's side
    SIDE = "side"  # the image's own mirror side equals the aiming point's side


@dataclass(frozen=True, slots=True)
class PaperOracleConfig:
    """Settings of the paper's Oracle.

    Attributes:
        mode: angle / power choice, as :class:`~pix2pockets.planner.oracle.OracleMode` (random angle = a
            uniformly random hitpoint; random power = one of the 30 levels).
        mirror: add the mirrored balls and aiming points (its ``bank_shots``).
        kick_rule: see :class:`KickRule` (``code`` reproduces its figures).
        max_cut_deg: largest cut angle kept [deg] (its ``THETA_LIMIT``).
    """

    mode: OracleMode = OracleMode.BEST_MAX
    mirror: bool = False
    kick_rule: KickRule = KickRule.CODE
    max_cut_deg: float = 80.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "mode", OracleMode(self.mode))
        object.__setattr__(self, "kick_rule", KickRule(self.kick_rule))
        if not 0.0 < self.max_cut_deg <= 90.0:
            raise ValueError(f"PaperOracleConfig.max_cut_deg must be in (0, 90], got {self.max_cut_deg}")


@dataclass(frozen=True, slots=True)
class _Targets:
    """Aiming points [px] with their jaw points, pocket index (spec order) and mirror side (0 = real)."""

    points: np.ndarray
    jaws: np.ndarray
    pocket: np.ndarray
    side: np.ndarray


def _lines() -> tuple[tuple[float, int], ...]:
    """The four ball-centre lines as (coordinate, axis), in the paper's order: left, right, bottom, top."""
    u0, u1, v0, v1 = PAPER_LAYOUT.centre_box
    return ((u0, 0), (u1, 0), (v1, 1), (v0, 1))


def _targets(mirror: bool) -> _Targets:
    lay = PAPER_LAYOUT
    order = list(_PAPER_ORDER)
    pts, jaws = lay.target_points[order], lay.jaw_points[order]
    points, jaw_list, pocket, side = list(pts), list(jaws), list(order), [0] * 6
    if mirror:
        for i, (line, axis) in enumerate(_lines()):
            for k in range(6):
                dist = pts[k, axis] - line
                if abs(dist) > lay.pocket_radius:
                    p, j = pts[k].copy(), jaws[k].copy()
                    p[axis] = line - dist
                    j[:, axis] = 2 * line - j[:, axis]
                    points.append(p)
                    jaw_list.append(j)
                    pocket.append(order[k])
                    side.append(i + 1)
    return _Targets(np.array(points), np.array(jaw_list), np.array(pocket), np.array(side))


_TARGETS = {False: _targets(False), True: _targets(True)}


def _images(uv: np.ndarray, balls: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """Mirror images [px] of ``balls`` across the four ball-centre lines, and each image's side (1-4)."""
    r = PAPER_LAYOUT.ball_radius
    pts, sides = [], []
    for b in balls:
        for i, (line, axis) in enumerate(_lines()):
            dist = uv[b, axis] - line
            if abs(dist) > r:
                p = uv[b].copy()
                p[axis] = line - dist
                pts.append(p)
                sides.append(i + 1)
    return np.array(pts).reshape(-1, 2), np.array(sides, dtype=int)


def _blocked(start: np.ndarray, end: np.ndarray, obstacles: np.ndarray, skip: np.ndarray) -> np.ndarray:
    """For m segments (m, 2) -> (m, 2): whether an obstacle (k, 2) not skipped (m, k) lies within 2 R."""
    if obstacles.shape[0] == 0:
        return np.zeros(len(start), dtype=bool)
    d = end - start
    ll = np.einsum("ij,ij->i", d, d)
    rel = obstacles[None, :, :] - start[:, None, :]
    t = np.clip(np.einsum("mkj,mj->mk", rel, d) / np.where(ll > 0, ll, 1.0)[:, None], 0.0, 1.0)
    close = rel - t[..., None] * d[:, None, :]
    dist2 = np.einsum("mkj,mkj->mk", close, close)
    lim = (2.0 * PAPER_LAYOUT.ball_radius) ** 2
    return np.any((dist2 <= lim) & ~skip, axis=1)


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.hypot(v[..., 0], v[..., 1])
    return v / np.where(n > 0, n, 1.0)[..., None]


def _angle_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Unsigned angle between vectors [deg] (pymunk's ``get_angle_degrees_between``, absolute)."""
    cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    dot = np.einsum("...j,...j->...", a, b)
    return np.abs(np.degrees(np.arctan2(cross, dot)))


class PaperOraclePlanner:
    """The paper's Oracle, computed as its environment code does (a :class:`~pix2pockets.planner.base.Planner`).

    Works on layouts of :func:`~pix2pockets.geometry.raster.paper_table`; the order of the layout's balls
    matters as it did there (the paper's creation order: solids, the 8, stripes, the cue ball), through
    the list of mirror images in mirror mode.

    Example:
        >>> from pix2pockets.planner.paper_protocol import PAPER_SHOOTER, paper_start_layout
        >>> lay = paper_start_layout(12345)
        >>> best = PaperOraclePlanner().suggest(lay, GameState(PAPER_SHOOTER))[0]
        >>> best.kind.value
        'direct'
    """

    def __init__(self, config: PaperOracleConfig | None = None) -> None:
        self.config = config or PaperOracleConfig()
        self.name = "paper-oracle" + ("-mirror" if self.config.mirror else "")

    def candidates(self, layout: TableLayout, state: GameState) -> list[tuple[float, bool, Suggestion]]:
        """Every candidate with its score and whether it is a hitpoint (unblocked, cut within the limit),
        in the code's order."""
        cfg = self.config
        lay = PAPER_LAYOUT
        r = lay.ball_radius
        cue = layout.cue_index
        if cue is None:
            raise ValueError("cannot plan a shot: the layout has no cue ball")
        uv = lay.from_table(layout.positions)
        own = legal_targets(layout, state)
        others = [i for i in range(len(layout)) if i != cue and i not in own]
        tg = _TARGETS[cfg.mirror]
        if cfg.mirror:
            ghosts, ghost_side = _images(uv, own)
            opp_ghosts, _ = _images(uv, others)
        else:
            ghosts, ghost_side = np.zeros((0, 2)), np.zeros(0, dtype=int)
            opp_ghosts = np.zeros((0, 2))
        n_t = len(tg.points)
        out: list[tuple[float, bool, Suggestion]] = []
        for rank, b in enumerate(own):
            # the object ball itself, then (for the first ball only: the code repeats them identically for
            # every ball, and the first copy wins ties) every image of the shooter's balls
            sources = [(uv[b], 0, -1)]
            if rank == 0:
                sources += [(g, k + 1, k) for k, g in enumerate(ghosts)]
            src = np.array([s[0] for s in sources])
            g_idx = np.repeat([s[1] for s in sources], n_t)
            img = np.repeat([s[2] for s in sources], n_t)
            start = np.repeat(src, n_t, axis=0)
            tgt = np.tile(tg.points, (len(sources), 1))
            k_idx = np.tile(np.arange(n_t), len(sources))
            pocket_vec = _unit(tgt - start)
            hit = start - 2 * r * pocket_vec
            aim = hit - uv[cue]
            cut = _angle_deg(_unit(aim), pocket_vec)
            m = len(start)
            # object-ball path: every ball but itself, every image but itself, every other aiming point
            skip_balls = np.zeros((m, len(layout)), dtype=bool)
            skip_balls[img < 0, b] = True
            skip_ghosts = np.zeros((m, len(ghosts)), dtype=bool)
            skip_ghosts[img >= 0, img[img >= 0]] = True
            skip_targets = np.zeros((m, n_t), dtype=bool)
            skip_targets[np.arange(m), k_idx] = True
            no_skip_opp = np.zeros((m, len(opp_ghosts)), dtype=bool)
            obj_blocked = (
                _blocked(start, tgt, uv, skip_balls)
                | _blocked(start, tgt, ghosts, skip_ghosts)
                | _blocked(start, tgt, opp_ghosts, no_skip_opp)
                | _blocked(start, tgt, tg.points, skip_targets)
            )
            # cue-ball path to the ghost ball: everything but the cue ball and the object ball (or image)
            skip_cue = skip_balls.copy()
            skip_cue[:, cue] = True
            no_skip_targets = np.zeros((m, n_t), dtype=bool)
            cue_start = np.repeat(uv[cue][None], m, axis=0)
            cue_blocked = (
                _blocked(cue_start, hit, uv, skip_cue)
                | _blocked(cue_start, hit, ghosts, skip_ghosts)
                | _blocked(cue_start, hit, opp_ghosts, no_skip_opp)
                | _blocked(cue_start, hit, tg.points, no_skip_targets)
            )
            good = (cut <= cfg.max_cut_deg) & ~obj_blocked & ~cue_blocked
            side = tg.side[k_idx]
            # the kick test compares the aiming point's side with the image's list position (its code) or side
            own_side = np.where(img >= 0, ghost_side[np.maximum(img, 0)], 0) if len(ghost_side) else 0 * img
            g_side = own_side if cfg.kick_rule is KickRule.SIDE else g_idx
            mult = np.where(
                (g_idx == 0) & (side == 0), 1.0, np.where(g_side == side, 0.75, np.where(g_idx == 0, 0.5, 0.25))
            )
            jaws = tg.jaws[k_idx]
            window = _angle_deg(jaws[:, 0] - start, jaws[:, 1] - start) / 60.0
            cosine = np.einsum("ij,ij->i", _unit(aim), pocket_vec)
            score = (window + cosine) * mult
            for c in range(m):
                kind = ShotKind.DIRECT if g_idx[c] == 0 and side[c] == 0 else ShotKind.BANK
                if g_idx[c] != 0:
                    kind = ShotKind.KICK
                angle = math.atan2(-aim[c, 1], aim[c, 0])  # pixels have v down
                sug = Suggestion(
                    Shot(angle=angle, speed=_speed(_LEVELS)), b, int(tg.pocket[k_idx[c]]), kind, None,
                    float(score[c]),
                )  # fmt: skip
                out.append((float(score[c]), bool(good[c]), sug))
        return out

    def suggest(
        self, layout: TableLayout, state: GameState, rng: np.random.Generator | None = None
    ) -> list[Suggestion]:
        """Ranked suggestions: the Oracle's choice first, then the other hitpoints by score."""
        cfg = self.config
        rng = rng if rng is not None else np.random.default_rng(0)
        if lone_cue(layout):  # its 1-ball task: a random aiming point
            uv = PAPER_LAYOUT.from_table(layout.positions)
            k = int(rng.integers(6))
            d = PAPER_LAYOUT.target_points[_PAPER_ORDER[k]] - uv[layout.cue_index]
            shot = Shot(angle=math.atan2(-d[1], d[0]), speed=_speed(_LEVELS))
            return [Suggestion(shot, layout.cue_index, _PAPER_ORDER[k], ShotKind.DIRECT)]
        if not legal_targets(layout, state):
            return [fallback_shot(layout, state, _speed(_LEVELS))]
        cands = self.candidates(layout, state)
        pool = [c for c in cands if c[1]] or cands
        if not pool:
            return [fallback_shot(layout, state, _speed(_LEVELS))]
        if cfg.mode is OracleMode.BEST_MAX:
            scores = np.array([c[0] for c in pool])
            best = int(np.argmax(scores))
        else:
            best = int(rng.integers(len(pool)))
        chosen = pool[best][2]
        if cfg.mode is OracleMode.RANDOM_RANDOM:
            level = int(rng.integers(1, _LEVELS + 1))
            chosen = Suggestion(
                Shot(chosen.shot.angle, _speed(level)), chosen.target, chosen.pocket, chosen.kind, None, chosen.value
            )
        rest = sorted((c[2] for i, c in enumerate(pool) if i != best), key=lambda s: -s.value)
        return [chosen, *rest]


def _speed(level: int) -> float:
    """Speed [m/s] of power level ``level`` (1-30) in the paper's world."""
    return float(paper_level_speed(level))


__all__ = ["KickRule", "PaperOracleConfig", "PaperOraclePlanner"]

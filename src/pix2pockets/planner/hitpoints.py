"""Hitpoints: where the cue ball must go to send an object ball into a pocket (ghost-ball aiming).

For an object ball at ``B`` that should leave in direction ``u`` toward a pocket, the cue ball must reach
the **ghost-ball** centre ``G = B - 2 r u`` (``r`` the ball radius); the impulse then acts along ``u``.
Direct shots send the cue straight to ``G``; bank shots send the object ball off one cushion into the
pocket (``u`` points at the pocket's mirror image); kick shots send the cue ball off one cushion to ``G``
(it is aimed at ``G``'s mirror image). See :mod:`pix2pockets.planner.mirror`.

The object ball aims at the middle of the pocket's *clear* window: the directions in which its centre
passes both jaw points by at least one ball radius. Hitpoints are dropped when the cut angle exceeds
``max_cut``, when the ball does not fit between the jaws, when a path (cue to ghost, object ball to pocket,
and each leg of a cushion path) passes within ``clearance`` (two ball radii: touching) of another ball, or
when a cushion contact falls in a pocket mouth.

References:
    Schiøtt et al., pix2pockets, section "Hitpoints" and "Introduce Mirror table".

Example:
    >>> from pix2pockets.state import Ball, TableLayout
    >>> lay = TableLayout((Ball.numbered(0), Ball.numbered(1)), [[1.0, 0.3], [1.8, 0.3]])
    >>> hps = find_hitpoints(lay, [1])
    >>> sorted({hp.pocket for hp in hps})[:1]
    [2]
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from pix2pockets.planner.mirror import RAILS, bounce_point, cushion_at, rail_pockets, reflect
from pix2pockets.state import Shot, TableLayout


class ShotKind(StrEnum):
    """How a shot reaches the pocket."""

    DIRECT = "direct"  # cue -> object ball -> pocket
    BANK = "bank"  # cue -> object ball -> cushion -> pocket
    KICK = "kick"  # cue -> cushion -> object ball -> pocket


@dataclass(frozen=True, slots=True, eq=False)
class Hitpoint:
    """One way to pot one ball in one pocket.

    Attributes:
        target: index of the object ball in the layout.
        pocket: pocket index (``TableSpec.pockets`` order).
        kind: direct, bank or kick.
        ghost: ghost-ball centre the cue ball must reach [m], shape (2,).
        aim_point: the point the cue ball is aimed at [m]: ``ghost``, or its mirror image for kicks.
        cue_angle: direction of the stroke [rad], counter-clockwise from +x, in (-pi, pi].
        cut_angle: angle between the cue ball's incoming direction at the ghost and the object ball's
            outgoing direction [rad], in [0, pi/2).
        window: angle the pocket mouth (jaw point to jaw point) subtends at the object ball [rad]
            (via the mirror image for banks).
        cushions: cushion segment indices (``TableSpec.cushion_segments`` order) the planned path touches.
        object_angle: direction the object ball leaves in [rad].
        cue_distance: path length of the cue ball to the ghost [m].
        object_distance: path length of the object ball to the pocket mouth [m].
        clear_window: width of the angular interval in which the object ball clears both jaws [rad].
    """

    target: int
    pocket: int
    kind: ShotKind
    ghost: np.ndarray
    aim_point: np.ndarray
    cue_angle: float
    cut_angle: float
    window: float
    cushions: tuple[int, ...] = ()
    object_angle: float = 0.0
    cue_distance: float = 0.0
    object_distance: float = 0.0
    clear_window: float = 0.0

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Hitpoint):
            return NotImplemented
        return (
            (self.target, self.pocket, self.kind, self.cushions)
            == (other.target, other.pocket, other.kind, other.cushions)
            and bool(np.allclose(self.ghost, other.ghost, atol=1e-12))
            and bool(np.allclose(self.aim_point, other.aim_point, atol=1e-12))
            and math.isclose(self.cue_angle, other.cue_angle, abs_tol=1e-12)
        )

    __hash__ = None  # type: ignore[assignment]

    def shot(self, speed: float, **kw: float) -> Shot:
        """A stroke along ``cue_angle`` at ``speed`` [m/s]; ``kw`` passes tip offsets / elevation."""
        return Shot(angle=self.cue_angle, speed=speed, **kw)

    @property
    def label(self) -> str:
        """Short description, e.g. ``"ball 3 -> pocket 2 (bank, cushions 4)"``."""
        extra = f", cushions {','.join(map(str, self.cushions))}" if self.cushions else ""
        return f"ball {self.target} -> pocket {self.pocket} ({self.kind.value}{extra})"


def _wrap(angle: float) -> float:
    """Angle wrapped to (-pi, pi]."""
    return math.atan2(math.sin(angle), math.cos(angle))


def _unit(v: np.ndarray) -> np.ndarray:
    return v / float(np.hypot(v[0], v[1]))


def path_blocked(start: np.ndarray, end: np.ndarray, obstacles: np.ndarray, clearance: float) -> bool:
    """Whether a ball centre moving from ``start`` to ``end`` passes within ``clearance`` of an obstacle.

    Args:
        start, end: path end points [m], shape (2,).
        obstacles: centres of the other balls [m], shape (n, 2).
        clearance: minimal centre distance [m] (``2 r`` = the balls would touch).
    """
    if len(obstacles) == 0:
        return False
    d = end - start
    length2 = float(d @ d)
    rel = obstacles - start
    t = np.clip(rel @ d / length2, 0.0, 1.0) if length2 > 0 else np.zeros(len(obstacles))
    closest = start + t[:, None] * d
    dist2 = np.sum((obstacles - closest) ** 2, axis=1)
    return bool(np.any(dist2 < clearance * clearance))


def pocket_window(ball: np.ndarray, jaws: np.ndarray, radius: float) -> tuple[float, float, float] | None:
    """The pocket mouth seen from an object ball.

    Args:
        ball: object-ball centre [m].
        jaws: the two jaw points [m], shape (2, 2) (mirror images for banks).
        radius: ball radius [m].

    Returns:
        ``(window, aim_angle, clear_window)`` [rad]: the angle between the jaw points, the middle of the
        directions in which the ball passes both jaws by ``radius``, and the width of that interval;
        ``None`` when the ball does not fit through.
    """
    v1, v2 = jaws[0] - ball, jaws[1] - ball
    d1, d2 = float(np.hypot(*v1)), float(np.hypot(*v2))
    if d1 <= radius or d2 <= radius:
        return None
    a1, a2 = math.atan2(v1[1], v1[0]), math.atan2(v2[1], v2[0])
    window = _wrap(a2 - a1)
    if window < 0:  # order the jaws counter-clockwise as seen from the ball
        a1, a2, d1, d2, window = a2, a1, d2, d1, -window
    lo = a1 + math.asin(radius / d1)
    hi = a1 + window - math.asin(radius / d2)
    if hi <= lo:
        return None
    return window, _wrap(0.5 * (lo + hi)), hi - lo


def _obstacles(positions: np.ndarray, exclude: Iterable[int]) -> np.ndarray:
    keep = np.ones(len(positions), dtype=bool)
    keep[list(exclude)] = False
    return positions[keep]


def _cut(incoming: np.ndarray, outgoing: np.ndarray) -> float:
    c = float(np.clip(incoming @ outgoing, -1.0, 1.0))
    return math.acos(c)


def find_hitpoints(
    layout: TableLayout,
    targets: Iterable[int],
    kinds: Iterable[ShotKind | str] = (ShotKind.DIRECT,),
    max_cut: float = math.radians(80.0),
    clearance: float | None = None,
    cushion_margin: float | None = None,
) -> list[Hitpoint]:
    """All unblocked hitpoints for the given object balls.

    Args:
        layout: the table; must hold a cue ball.
        targets: indices of the object balls to pot.
        kinds: shot kinds to include (direct, bank, kick).
        max_cut: largest cut angle kept [rad] (the paper drops cuts over 80 degrees).
        clearance: a path is blocked when it passes a ball centre closer than this [m]; default two ball
            radii (touching).
        cushion_margin: a cushion contact must lie this far [m] from the jaw points; default half a ball
            radius.

    Returns:
        Hitpoints ordered by target (as given), pocket, then kind (direct, bank, kick) and cushion.

    Raises:
        ValueError: no cue ball, a target index out of range or the cue ball itself, bad ``max_cut``.
    """
    cue = layout.cue_index
    if cue is None:
        raise ValueError("cannot find hitpoints: the layout has no cue ball")
    if not 0.0 < max_cut < math.pi / 2 + 1e-12:
        raise ValueError(f"max_cut must be in (0, pi/2] rad, got {max_cut}")
    kinds = {ShotKind(k) for k in kinds}
    spec = layout.spec
    r = spec.ball_radius
    contact = spec.cue_contact_distance  # cue and object centres at impact (a UK cue ball is smaller)
    clear = 2.0 * r if clearance is None else float(clearance)
    margin = 0.5 * r if cushion_margin is None else float(cushion_margin)
    pos = layout.positions
    c = pos[cue]
    out: list[Hitpoint] = []
    pockets = spec.pockets
    for t in targets:
        t = int(t)
        if not 0 <= t < len(layout):
            raise ValueError(f"target index {t} is out of range for a layout of {len(layout)} balls")
        if t == cue:
            raise ValueError(f"target index {t} is the cue ball")
        b = pos[t]
        others = _obstacles(pos, (cue, t))  # balls other than cue and target
        not_cue = _obstacles(pos, (cue,))
        for k, pocket in enumerate(pockets):
            direct = None
            if kinds & {ShotKind.DIRECT, ShotKind.KICK}:
                direct = _object_leg(b, pocket.jaws, r, others, clear, spec)
            if direct is not None:
                window, u, clear_w, dist = direct
                ghost = b - contact * u
                if ShotKind.DIRECT in kinds:
                    hp = _cue_direct(c, ghost, u, others, clear, spec, max_cut)
                    if hp is not None:
                        angle, cut, cue_dist = hp
                        out.append(
                            Hitpoint(t, k, ShotKind.DIRECT, _ro(ghost), _ro(ghost), angle, cut, window, (),
                                     math.atan2(u[1], u[0]), cue_dist, dist, clear_w)
                        )  # fmt: skip
                if ShotKind.KICK in kinds:
                    for rail in RAILS:
                        kick = _cue_kick(c, ghost, u, rail, others, not_cue, t, clear, spec, max_cut, margin)
                        if kick is not None:
                            aim, angle, cut, cushion, cue_dist = kick
                            out.append(
                                Hitpoint(t, k, ShotKind.KICK, _ro(ghost), _ro(aim), angle, cut, window, (cushion,),
                                         math.atan2(u[1], u[0]), cue_dist, dist, clear_w)
                            )  # fmt: skip
            if ShotKind.BANK in kinds:
                for rail in RAILS:
                    if k in rail_pockets(rail):
                        continue
                    bank = _object_bank(b, pocket.jaws, rail, r, others, clear, spec, margin)
                    if bank is None:
                        continue
                    window, u, clear_w, dist, cushion = bank
                    ghost = b - contact * u
                    hp = _cue_direct(c, ghost, u, others, clear, spec, max_cut)
                    if hp is not None:
                        angle, cut, cue_dist = hp
                        out.append(
                            Hitpoint(t, k, ShotKind.BANK, _ro(ghost), _ro(ghost), angle, cut, window, (cushion,),
                                     math.atan2(u[1], u[0]), cue_dist, dist, clear_w)
                        )  # fmt: skip
    order = {ShotKind.DIRECT: 0, ShotKind.BANK: 1, ShotKind.KICK: 2}
    rank = {t: i for i, t in enumerate(dict.fromkeys(int(x) for x in [h.target for h in out]))}
    out.sort(key=lambda h: (rank[h.target], h.pocket, order[h.kind], h.cushions))
    return out


def _ro(v: np.ndarray) -> np.ndarray:
    v = np.array(v, dtype=float)
    v.setflags(write=False)
    return v


def _on_table(p: np.ndarray, spec, r: float) -> bool:
    return bool(spec.contains(p, margin=r - 1e-9))


def _object_leg(b, jaws, r, others, clear, spec):
    """Object ball straight into a pocket: (window, direction, clear window, distance) or None."""
    w = pocket_window(b, jaws, r)
    if w is None:
        return None
    window, angle, clear_w = w
    u = np.array([math.cos(angle), math.sin(angle)])
    mouth = _mouth_crossing(b, u, jaws)
    if path_blocked(b, mouth, others, clear):
        return None
    return window, u, clear_w, float(np.hypot(*(mouth - b)))


def _mouth_crossing(b: np.ndarray, u: np.ndarray, jaws: np.ndarray) -> np.ndarray:
    """Where the ray from ``b`` along ``u`` crosses the line through the jaw points."""
    j0, j1 = jaws
    e = j1 - j0
    den = u[0] * e[1] - u[1] * e[0]
    if abs(den) < 1e-12:
        return 0.5 * (j0 + j1)
    w = j0 - b
    s = (w[0] * e[1] - w[1] * e[0]) / den
    return b + max(s, 0.0) * u


def _object_bank(b, jaws, rail, r, others, clear, spec, margin):
    """Object ball off one cushion into a pocket, via the pocket's mirror image."""
    mj = reflect(jaws, spec, rail)
    w = pocket_window(b, mj, r)
    if w is None:
        return None
    window, angle, clear_w = w
    u = np.array([math.cos(angle), math.sin(angle)])
    mouth_m = _mouth_crossing(b, u, mj)
    hit = bounce_point(b, mouth_m, spec, rail)
    if hit is None:
        return None
    cushion = cushion_at(hit, spec, rail, margin)
    if cushion is None:
        return None
    mouth = reflect(mouth_m, spec, rail)
    if path_blocked(b, hit, others, clear) or path_blocked(hit, mouth, others, clear):
        return None
    dist = float(np.hypot(*(hit - b)) + np.hypot(*(mouth - hit)))
    return window, u, clear_w, dist, cushion


def _cue_direct(c, ghost, u, others, clear, spec, max_cut):
    """Cue ball straight to the ghost: (angle, cut, distance) or None."""
    r = spec.ball_radius
    if not _on_table(ghost, spec, r):
        return None
    d = ghost - c
    dist = float(np.hypot(*d))
    if dist < 1e-9:
        return None
    v = d / dist
    cut = _cut(v, u)
    if cut > max_cut:
        return None
    if path_blocked(c, ghost, others, clear):
        return None
    return math.atan2(v[1], v[0]), cut, dist


def _cue_kick(c, ghost, u, rail, others, not_cue, target, clear, spec, max_cut, margin):
    """Cue ball off one cushion to the ghost: (aim point, angle, cut, cushion, distance) or None."""
    r = spec.ball_radius
    if not _on_table(ghost, spec, r):
        return None
    aim = reflect(ghost, spec, rail)
    hit = bounce_point(c, aim, spec, rail)
    if hit is None:
        return None
    cushion = cushion_at(hit, spec, rail, margin)
    if cushion is None:
        return None
    leg2 = ghost - hit
    n2 = float(np.hypot(*leg2))
    if n2 < 1e-9:
        return None
    cut = _cut(leg2 / n2, u)
    if cut > max_cut:
        return None
    # first leg: nothing (target included) may be touched; second leg ends touching the target
    if path_blocked(c, hit, not_cue, clear) or path_blocked(hit, ghost, others, clear):
        return None
    d = aim - c
    return aim, math.atan2(d[1], d[0]), cut, cushion, float(np.hypot(*(hit - c)) + n2)

"""Game-like ball layouts for rendering: racks, break spreads, scattered balls, clusters, balls frozen to a
rail or hanging in a pocket's jaws, and nearly empty tables."""

from __future__ import annotations

import math

import numpy as np

from pix2pockets.geometry.table import PocketKind, TableSpec
from pix2pockets.state.ball import Ball
from pix2pockets.state.layout import TableLayout
from pix2pockets.state.racks import eight_ball_rack

LAYOUT_MODES: dict[str, float] = {
    "rack": 0.05,
    "break_spread": 0.12,
    "scattered": 0.33,
    "clusters": 0.25,
    "endgame": 0.17,
    "few": 0.08,
}
"""Layout modes and their sampling probabilities."""

GAP = 1e-5  # [m] clearance between touching balls


class _Placer:
    """Places balls one by one without overlap, inside the cushions."""

    def __init__(self, spec: TableSpec) -> None:
        self.spec = spec
        self.r = spec.ball_radius
        self.pts: list[np.ndarray] = []

    def fits(self, p: np.ndarray) -> bool:
        r = self.r
        if not (r + GAP <= p[0] <= self.spec.length - r - GAP and r + GAP <= p[1] <= self.spec.width - r - GAP):
            return False
        return not (self.pts and np.min(np.linalg.norm(np.asarray(self.pts) - p, axis=1)) < 2 * r + GAP)

    def add(self, p: np.ndarray) -> bool:
        if self.fits(p):
            self.pts.append(np.asarray(p, dtype=float))
            return True
        return False

    def random_spot(self, rng: np.random.Generator, tries: int = 200) -> bool:
        lo = np.array([self.r, self.r]) + GAP
        hi = self.spec.size - self.r - GAP
        return any(self.add(lo + rng.random(2) * (hi - lo)) for _ in range(tries))

    def touching(self, rng: np.random.Generator, tries: int = 60) -> bool:
        """A ball touching a random already placed ball."""
        if not self.pts:
            return self.random_spot(rng)
        for _ in range(tries):
            base = self.pts[int(rng.integers(len(self.pts)))]
            a = rng.uniform(0, 2 * math.pi)
            d = 2 * self.r + GAP * 2 + abs(rng.normal(0, 0.002)) * (rng.random() < 0.5)
            if self.add(base + d * np.array([math.cos(a), math.sin(a)])):
                return True
        return False

    def on_rail(self, rng: np.random.Generator, tries: int = 60) -> bool:
        """A ball frozen to (or just off) a cushion."""
        L, W, r = self.spec.length, self.spec.width, self.r
        for _ in range(tries):
            off = r + GAP * 2 + (0.0 if rng.random() < 0.7 else rng.uniform(0, 0.02))
            side = int(rng.integers(4))
            s = rng.uniform(0.08, 0.92)
            p = [
                np.array([s * L, off]),
                np.array([L - off, s * W]),
                np.array([s * L, W - off]),
                np.array([off, s * W]),
            ][side]
            if self.add(p):
                return True
        return False

    def in_jaws(self, rng: np.random.Generator, tries: int = 30) -> bool:
        """A ball hanging in front of a pocket (on the lip)."""
        r = self.r
        for _ in range(tries):
            pocket = self.spec.pockets[int(rng.integers(6))]
            if pocket.kind is PocketKind.CORNER:
                corner = np.round(pocket.jaws.mean(axis=0) / self.spec.size) * self.spec.size
                inward = np.sign(self.spec.size / 2 - corner)
                d = r + GAP * 2 + rng.uniform(0.0, 0.03)
                p = corner + inward * d + inward * rng.normal(0, 0.004, 2)
            else:
                inward = 1.0 if pocket.aim[1] < self.spec.width / 2 else -1.0
                p = pocket.aim + np.array([rng.normal(0, 0.02), inward * (r + GAP * 2 + rng.uniform(0, 0.02))])
            if self.add(p):
                return True
        return False


def _numbers(rng: np.random.Generator, n: int, cue_p: float = 0.93, black_p: float = 0.88) -> list[int]:
    """``n`` distinct ball numbers; the cue and the 8 are present with the given probabilities."""
    n = int(np.clip(n, 1, 16))
    chosen: list[int] = []
    if rng.random() < cue_p:
        chosen.append(0)
    if rng.random() < black_p and len(chosen) < n:
        chosen.append(8)
    others = [k for k in range(1, 16) if k != 8]
    rng.shuffle(others)
    chosen += others[: n - len(chosen)]
    return chosen


def sample_layout(rng: np.random.Generator, spec: TableSpec, mode: str | None = None) -> tuple[TableLayout, str]:
    """A layout drawn like positions seen in real games.

    Args:
        rng: random source.
        spec: the table.
        mode: one of :data:`LAYOUT_MODES` (drawn at random when ``None``).

    Returns:
        The layout (cue ball first when present) and the mode used.
    """
    if mode is None:
        keys = list(LAYOUT_MODES)
        p = np.array([LAYOUT_MODES[k] for k in keys])
        mode = keys[int(rng.choice(len(keys), p=p / p.sum()))]
    if mode not in LAYOUT_MODES:
        raise ValueError(f"unknown layout mode {mode!r}; choose one of {sorted(LAYOUT_MODES)}")
    placer = _Placer(spec)
    if mode == "rack":
        rack = eight_ball_rack(spec, rng)
        numbers = [b.number for b in rack.balls]
        placer.pts = [p.copy() for p in rack.positions[1:]]
        placer.pts.insert(0, rack.positions[0])
        if rng.random() < 0.7:  # cue ball in hand behind the head string
            placer.pts.pop(0)
            while not placer.add(
                np.array([rng.uniform(0.05, spec.head_string_x), rng.uniform(0.05, spec.width - 0.05)])
            ):
                pass
            placer.pts.insert(0, placer.pts.pop())
        return TableLayout(rack.balls, np.array(placer.pts), spec), mode
    if mode == "break_spread":
        numbers = _numbers(rng, int(rng.integers(12, 17)), cue_p=1.0, black_p=0.97)
        # a loose remnant of the rack plus balls spread over the table
        apex = spec.foot_spot + rng.normal(0, 0.08, 2)
        core = int(rng.integers(2, 7))
        placer.add(apex)
        for _ in range(core - 1):
            placer.touching(rng)
        for _ in range(len(numbers) - core):
            (placer.on_rail if rng.random() < 0.2 else placer.random_spot)(rng)
    elif mode == "scattered":
        numbers = _numbers(rng, int(rng.integers(4, 17)))
        for _ in numbers:
            u = rng.random()
            (placer.on_rail if u < 0.15 else placer.in_jaws if u < 0.22 else placer.random_spot)(rng)
    elif mode == "clusters":
        numbers = _numbers(rng, int(rng.integers(5, 17)))
        n_clusters = int(rng.integers(1, 4))
        for _ in range(n_clusters):
            placer.random_spot(rng)
        for _ in range(len(numbers) - n_clusters):
            u = rng.random()
            (placer.touching if u < 0.6 else placer.on_rail if u < 0.75 else placer.random_spot)(rng)
    elif mode == "endgame":
        numbers = _numbers(rng, int(rng.integers(2, 8)), cue_p=0.97, black_p=0.95)
        for _ in numbers:
            u = rng.random()
            (placer.on_rail if u < 0.25 else placer.in_jaws if u < 0.35 else placer.random_spot)(rng)
    else:  # few
        numbers = _numbers(rng, int(rng.integers(1, 4)), cue_p=0.8, black_p=0.6)
        for _ in numbers:
            placer.random_spot(rng)
    numbers = numbers[: len(placer.pts)]
    balls = tuple(Ball.numbered(n) for n in numbers)
    return TableLayout(balls, np.array(placer.pts[: len(numbers)]).reshape(-1, 2), spec), mode

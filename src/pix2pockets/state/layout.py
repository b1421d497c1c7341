"""Table layout: which balls are on the table and where."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from pix2pockets.geometry.table import TableSpec
from pix2pockets.state.ball import CLASS_CAPS, Ball, BallClass

OVERLAP_TOLERANCE = 1e-6  # [m] balls may touch (frozen) but not interpenetrate by more than this


@dataclass(frozen=True, slots=True, eq=False)
class TableLayout:
    """Balls at rest on a table.

    Attributes:
        balls: the balls, in a fixed order; ``ids`` index into this tuple.
        positions: ball centres in the table frame [m], shape (n, 2), read-only.
        spec: the table.

    Raises:
        ValueError: overlapping balls, a ball off the playing surface, more balls of a class than a
            table holds (e.g. two cue balls), or a ball number used twice.
    """

    balls: tuple[Ball, ...]
    positions: np.ndarray
    spec: TableSpec = field(default_factory=TableSpec)

    def __post_init__(self) -> None:
        balls = tuple(b if isinstance(b, Ball) else Ball(*b) for b in self.balls)
        object.__setattr__(self, "balls", balls)
        pos = np.array(self.positions, dtype=float).reshape(-1, 2) if len(balls) else np.zeros((0, 2))
        pos.setflags(write=False)
        object.__setattr__(self, "positions", pos)
        if len(balls) != len(pos):
            raise ValueError(f"layout has {len(balls)} balls but {len(pos)} positions")
        if not np.all(np.isfinite(pos)):
            raise ValueError("layout positions must be finite numbers")
        counts = Counter(b.ball_class for b in balls)
        for cls, n in counts.items():
            if n > CLASS_CAPS[cls]:
                raise ValueError(f"layout has {n} {cls.value} balls; a table holds at most {CLASS_CAPS[cls]}")
        numbers = [b.number for b in balls if b.number is not None]
        dup = [n for n, k in Counter(numbers).items() if k > 1]
        if dup:
            raise ValueError(f"ball number(s) {dup} appear more than once")
        r = self.radii
        tol = OVERLAP_TOLERANCE
        inside = self.spec.contains(pos, margin=r - tol)
        if not np.all(inside):
            i = int(np.flatnonzero(~inside)[0])
            raise ValueError(
                f"ball {i} ({balls[i].label}) at ({pos[i, 0]:.4f}, {pos[i, 1]:.4f}) m is off the playing "
                f"surface (centres must stay {r[i]:.4f} m inside the cushions of a "
                f"{self.spec.length:.3f} x {self.spec.width:.3f} m table)"
            )
        if len(pos) > 1:
            d = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=-1) - (r[:, None] + r[None, :])
            d[np.diag_indices(len(pos))] = np.inf
            i, j = np.unravel_index(np.argmin(d), d.shape)
            if d[i, j] < -tol:
                touch = r[i] + r[j]
                raise ValueError(
                    f"balls {i} ({balls[i].label}) and {j} ({balls[j].label}) overlap: centres "
                    f"{(d[i, j] + touch) * 1000:.1f} mm apart, need at least {touch * 1000:.1f} mm"
                )

    @property
    def radii(self) -> np.ndarray:
        """Each ball's radius (n,) [m]: the table's ball radius, the cue ball's own where the set has a smaller one."""
        return self._per_ball(self.spec.cue_radius, self.spec.ball_radius)

    @property
    def masses(self) -> np.ndarray:
        """Each ball's mass (n,) [kg]: the table's ball mass, the cue ball's own where the set has a lighter one."""
        return self._per_ball(self.spec.cue_mass, self.spec.ball_mass)

    def _per_ball(self, cue: float, other: float) -> np.ndarray:
        return np.array([cue if b.ball_class is BallClass.CUE else other for b in self.balls], dtype=float)

    @classmethod
    def unchecked(cls, balls: tuple[Ball, ...], positions: np.ndarray, spec: TableSpec) -> TableLayout:
        """Build a layout WITHOUT validation: only for layouts the library derives from a validated one.

        For example a simulator's final state (a subset of the validated starting balls, positions
        produced by the physics, whose invariants its tests and soaks check). Never use it for user
        input: that goes through the validating constructor.
        """
        layout = object.__new__(cls)
        pos = np.array(positions, dtype=float).reshape(-1, 2)
        pos.setflags(write=False)
        object.__setattr__(layout, "balls", tuple(balls))
        object.__setattr__(layout, "positions", pos)
        object.__setattr__(layout, "spec", spec)
        return layout

    def __len__(self) -> int:
        return len(self.balls)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, TableLayout):
            return NotImplemented
        return (
            self.balls == other.balls
            and self.spec == other.spec
            and self.positions.shape == other.positions.shape
            and bool(np.allclose(self.positions, other.positions, atol=1e-12))
        )

    __hash__ = None  # type: ignore[assignment]

    def indices_of(self, ball_class: BallClass) -> list[int]:
        """Indices of the balls of one class."""
        return [i for i, b in enumerate(self.balls) if b.ball_class is ball_class]

    @property
    def cue_index(self) -> int | None:
        """Index of the cue ball, or ``None`` when it is not on the table."""
        idx = self.indices_of(BallClass.CUE)
        return idx[0] if idx else None

    @property
    def black_index(self) -> int | None:
        """Index of the 8-ball, or ``None``."""
        idx = self.indices_of(BallClass.BLACK)
        return idx[0] if idx else None

    def with_positions(self, positions: np.ndarray) -> TableLayout:
        """The same balls at new positions (validated)."""
        return TableLayout(self.balls, positions, self.spec)

    def without(self, indices: list[int] | set[int]) -> TableLayout:
        """A layout with the balls at ``indices`` removed (e.g. pocketed)."""
        keep = [i for i in range(len(self.balls)) if i not in set(indices)]
        return TableLayout(tuple(self.balls[i] for i in keep), self.positions[keep], self.spec)

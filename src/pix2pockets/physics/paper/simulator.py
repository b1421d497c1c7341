"""The ``paper`` backend: Python-facing simulator over the compiled kernel."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from pix2pockets.physics.base import BatchOutcome, Simulator, StopAfter
from pix2pockets.physics.paper._kernel import STATUS_NOT_FINITE, STATUS_OK, STATUS_TOO_LONG, run_shots
from pix2pockets.physics.paper.params import PAPER_PX, PaperParams
from pix2pockets.physics.paper.table import pack_table
from pix2pockets.state import Event, EventType, Shot, ShotResult, TableLayout

_EVENT_TYPES = (
    EventType.CUE_STRIKE,
    EventType.BALL_BALL,
    EventType.BALL_CUSHION,
    EventType.BALL_JAW,
    EventType.POCKET,
    EventType.ROLLING_TO_STATIONARY,
)
_STOP_CODES = {StopAfter.REST: 0, StopAfter.FIRST_CONTACT: 1, StopAfter.FIRST_POCKET: 2}
_FIRST_CAPACITY = 256  # event buffer size tried first [events]

PAPER_POWER_LEVELS = 30
"""The paper's discrete power levels (``MultiDiscrete([36000, 30])``)."""


def paper_level_speed(level: int | np.ndarray) -> float | np.ndarray:
    """Cue-ball speed [m/s] of the paper's power level ``level`` (1-30).

    The paper sets the cue ball's velocity to ``(245 / 29 * (level - 1) + 5) * 2`` px/s in its zoom-2
    world: 10 to 500 px/s, 0.019 to 0.971 m/s. At the top level a ball rolls 4,700 px (9.2 m, 3.6 table
    lengths) before it stops.

    Raises:
        ValueError: a level outside 1-30.
    """
    lv = np.asarray(level)
    if np.any((lv < 1) | (lv > PAPER_POWER_LEVELS)) or np.any(lv != np.rint(lv)):
        raise ValueError(f"power level must be an integer in 1-{PAPER_POWER_LEVELS}, got {level!r}")
    px = (245.0 / 29.0 * (lv - 1) + 5.0) * 2.0
    return float(px * PAPER_PX) if np.ndim(px) == 0 else px * PAPER_PX


def paper_continuous_speed(power: float) -> float:
    """Cue-ball speed [m/s] of the paper's continuous power ``power`` in [0, 1]: ``(175 p + 5) * 2`` px/s."""
    if not 0.0 <= power <= 1.0:
        raise ValueError(f"continuous power must be in [0, 1], got {power!r}")
    return (175.0 * power + 5.0) * 2.0 * PAPER_PX


def paper_power_level(speed: float) -> int:
    """The paper's power level (1-30) whose speed is nearest to ``speed`` [m/s]."""
    levels = paper_level_speed(np.arange(1, PAPER_POWER_LEVELS + 1))
    return int(np.argmin(np.abs(levels - speed))) + 1


PAPER_MAX_SPEED = paper_level_speed(PAPER_POWER_LEVELS)
"""The paper's top power level [m/s] (500 px/s: the Oracle's "max power")."""


class PaperSimulator(Simulator):
    """The seed paper's environment dynamics (see :mod:`pix2pockets.physics.paper`).

    Tip offsets and elevation of a :class:`~pix2pockets.state.Shot` are ignored: the paper's stroke sets
    the cue ball's velocity. Meant for the :func:`~pix2pockets.geometry.raster.paper_table` table (its exact
    cushion shapes); other tables get cushions built from their noses and jaw faces.

    Example:
        >>> from pix2pockets.physics import make_simulator
        >>> from pix2pockets.geometry.raster import paper_table
        >>> from pix2pockets.state import Ball, Shot, TableLayout
        >>> spec = paper_table()
        >>> lay = TableLayout((Ball.numbered(0), Ball.numbered(1)), [[0.6, 0.64], [1.6, 0.64]], spec)
        >>> sim = make_simulator("paper")
        >>> sim.simulate(lay, Shot(angle=0.0, speed=0.97)).first_contact
        1
    """

    name = "paper"

    def __init__(self, params: PaperParams | None = None, **overrides: float) -> None:
        base = params or PaperParams()
        if overrides:
            try:
                base = replace(base, **overrides)
            except TypeError as err:
                raise ValueError(f"unknown paper-simulator parameter: {err}") from None
        self.params = base
        self._prm: dict[float, np.ndarray] = {}

    def _prepare(self, layout: TableLayout) -> tuple[int, np.ndarray, tuple]:
        if not isinstance(layout, TableLayout):
            raise ValueError(f"expected a TableLayout, got {type(layout).__name__}")
        cue = layout.cue_index
        if cue is None:
            raise ValueError("the layout has no cue ball to strike")
        spec = layout.spec
        prm = self._prm.get(spec.ball_radius)
        if prm is None:
            prm = self._prm[spec.ball_radius] = self.params.packed(spec.ball_radius)
        size = np.array([spec.length, spec.width])
        return cue, prm, (*pack_table(spec), size)

    def _run(self, layout, rows, stop, record, capacity):
        cue, prm, geo = self._prepare(layout)
        m, n = len(rows), len(layout)
        out_pos = np.empty((m, n, 2))
        out_pocket = np.empty((m, n), dtype=np.int64)
        out_first = np.empty(m, dtype=np.int64)
        out_status = np.empty(m, dtype=np.int64)
        out_nev = np.empty(m, dtype=np.int64)
        out_time = np.empty(m)
        ev_t = np.empty(capacity)
        ev_k, ev_a, ev_b = (np.empty(capacity, dtype=np.int64) for _ in range(3))
        run_shots(
            np.array(layout.positions, dtype=float), cue, rows, prm, *geo, _STOP_CODES[StopAfter(stop)],
            self.params.max_events, record, ev_t, ev_k, ev_a, ev_b, out_pos, out_pocket, out_first, out_status,
            out_nev, out_time,
        )  # fmt: skip
        return cue, (out_pos, out_pocket, out_first, out_status, out_nev, out_time), (ev_t, ev_k, ev_a, ev_b)

    def simulate(self, layout: TableLayout, shot: Shot, stop: StopAfter = StopAfter.REST) -> ShotResult:
        """Simulate one stroke; events carry layout indices (pocket / cushion / jaw index in ``other``).

        Raises:
            ValueError: no cue ball, or ``shot`` is not a ``Shot``.
            RuntimeError: the shot ran past ``max_time`` or ``max_events``, or went non-finite.
        """
        if not isinstance(shot, Shot):
            raise ValueError(f"expected a Shot, got {type(shot).__name__}")
        rows = np.array([[shot.angle, shot.speed, 0.0, 0.0, 0.0]])
        cap = _FIRST_CAPACITY
        while True:
            _cue, out, ev = self._run(layout, rows, stop, True, cap)
            if out[4][0] <= cap:
                break
            cap = int(out[4][0]) + 1
        _check_status(int(out[3][0]), self.params)
        nev = int(out[4][0])
        ev_t, ev_k, ev_a, ev_b = (a[:nev].tolist() for a in ev)
        events = [Event(t, _EVENT_TYPES[k], a, b) for t, k, a, b in zip(ev_t, ev_k, ev_a, ev_b, strict=True)]
        return ShotResult.from_events(layout, events, out[0][0], validate=False)

    def simulate_arrays(
        self, layout: TableLayout, shots: np.ndarray | Sequence[Shot], stop: StopAfter = StopAfter.REST
    ) -> BatchOutcome:
        """Lean batch for the planner: outcome arrays only (shots that fail are flagged in ``status``).

        Args:
            layout: the starting layout.
            shots: ``Shot`` objects or an (m, 5) array (angle [rad], speed [m/s], then tip and elevation
                columns, ignored).
            stop: early-stop rule.
        """
        from pix2pockets.physics.event.simulator import shots_to_array

        rows = shots_to_array(shots)
        cue, out, _ = self._run(layout, rows, stop, False, 1)
        pos, pocket, first, status, nev, _time = out
        return BatchOutcome(first, pocket, pos, status, nev, cue)


def _check_status(status: int, params: PaperParams) -> None:
    if status == STATUS_TOO_LONG:
        raise RuntimeError(
            f"paper physics: the shot did not settle within {params.max_time:g} s or {params.max_events} events"
        )
    if status == STATUS_NOT_FINITE:
        raise RuntimeError("paper physics: the shot produced non-finite numbers")
    if status != STATUS_OK:
        raise RuntimeError(f"paper physics: the shot failed with status {status}")


__all__ = [
    "PAPER_MAX_SPEED",
    "PAPER_POWER_LEVELS",
    "PaperSimulator",
    "paper_continuous_speed",
    "paper_level_speed",
    "paper_power_level",
]

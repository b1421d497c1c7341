"""The ``event`` backend: Python-facing simulator over the compiled event loop."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from pix2pockets.geometry.table import TableSpec
from pix2pockets.physics.base import BatchOutcome, Simulator, StopAfter
from pix2pockets.physics.event._engine import (
    STATUS_NOT_FINITE,
    STATUS_OK,
    STATUS_TOO_MANY_EVENTS,
    TRACE_WIDTH,
    run_shots,
)
from pix2pockets.physics.event.params import PhysicsParams
from pix2pockets.state import Event, EventType, Shot, ShotResult, TableLayout

_EVENT_TYPES = (
    EventType.CUE_STRIKE,
    EventType.BALL_BALL,
    EventType.BALL_CUSHION,
    EventType.BALL_JAW,
    EventType.POCKET,
    EventType.SLIDING_TO_ROLLING,
    EventType.ROLLING_TO_SPINNING,
    EventType.SPINNING_TO_STATIONARY,
    EventType.ROLLING_TO_STATIONARY,
)
_STOP_CODES = {StopAfter.REST: 0, StopAfter.FIRST_CONTACT: 1, StopAfter.FIRST_POCKET: 2}
_FIRST_CAPACITY = 512  # event buffer size tried first [events]
PATH_STEP = 0.02
"""Spacing of the points :meth:`EventSimulator.ball_path` samples along a ball's parabolas [m]."""


def pack_table(spec: TableSpec) -> tuple[np.ndarray, ...]:
    """Table geometry as the arrays the kernels read.

    Returns:
        (seg_a, seg_u, seg_n, seg_len, pts, pt_jaw, pk_c, pk_r, size): 18 segments (6 cushion noses in
        ``cushion_segments`` order, then 12 jaw faces in ``jaw_segments`` order) as start point, unit
        direction, unit normal and length [m]; 24 segment end points with the jaw index each belongs
        to; pocket capture centres and radii [m]; the surface size (length, width) [m].
    """
    segs = np.concatenate([spec.cushion_segments, spec.jaw_segments]).astype(float)
    seg_a = np.ascontiguousarray(segs[:, 0])
    d = segs[:, 1] - segs[:, 0]
    seg_len = np.linalg.norm(d, axis=1)
    seg_u = d / seg_len[:, None]
    seg_n = np.ascontiguousarray(np.stack([-seg_u[:, 1], seg_u[:, 0]], axis=1))
    jaws = spec.jaw_segments
    pts = np.ascontiguousarray(jaws.reshape(-1, 2).astype(float))
    pt_jaw = np.repeat(np.arange(len(jaws), dtype=np.int64), 2)
    pk_c = np.ascontiguousarray(spec.pocket_centres.astype(float))
    pk_r = np.array([p.capture_radius for p in spec.pockets], dtype=float)
    size = np.array([spec.length, spec.width], dtype=float)
    return (seg_a, np.ascontiguousarray(seg_u), seg_n, seg_len, pts, pt_jaw, pk_c, pk_r, size)


class EventSimulator(Simulator):
    """Event-based pool physics: exact event times, sliding/rolling/spinning balls, no time step.

    Example:
        >>> from pix2pockets.physics import make_simulator
        >>> from pix2pockets.state import Shot, eight_ball_rack
        >>> sim = make_simulator("event")
        >>> result = sim.simulate(eight_ball_rack(), Shot(angle=0.0, speed=9.0))
        >>> len(result.final) + len(result.pocketed)
        16
    """

    name = "event"

    def __init__(self, params: PhysicsParams | None = None, **overrides: float) -> None:
        base = params or PhysicsParams()
        if overrides:
            try:
                base = replace(base, **overrides)
            except TypeError as err:
                raise ValueError(f"unknown event-simulator parameter: {err}") from None
        self.params = base
        self._geo_cache: dict[TableSpec, tuple] = {}
        self._ball_cache: dict[tuple[TableSpec, int, int], np.ndarray] = {}

    def _prepare(self, layout: TableLayout) -> tuple[int, np.ndarray, tuple]:
        if not isinstance(layout, TableLayout):
            raise ValueError(f"expected a TableLayout, got {type(layout).__name__}")
        cue = layout.cue_index
        if cue is None:
            raise ValueError("the layout has no cue ball to strike")
        spec = layout.spec
        cached = self._geo_cache.get(spec)
        if cached is None:
            cached = (pack_table(spec), self.params.packed(spec.ball_radius, spec.cushion_height))
            self._geo_cache[spec] = cached
        if spec.cue_radius == spec.ball_radius and spec.cue_mass == spec.ball_mass:
            return cue, cached[1], cached[0]
        return cue, self._ball_params(layout), cached[0]

    def _ball_params(self, layout: TableLayout) -> np.ndarray:
        """Packed parameters with a per-ball block: each ball's radius and mass (:attr:`TableLayout.radii`,
        :attr:`TableLayout.masses`), cached per table, ball count and cue index."""
        spec = layout.spec
        key = (spec, len(layout), layout.cue_index)
        prm = self._ball_cache.get(key)
        if prm is None:
            masses = layout.masses / spec.ball_mass
            prm = self.params.packed_balls(spec.ball_radius, spec.cushion_height, layout.radii, masses)
            self._ball_cache[key] = prm
        return prm

    def simulate(self, layout: TableLayout, shot: Shot, stop: StopAfter = StopAfter.REST) -> ShotResult:
        """Simulate one shot; events carry layout indices (pocket/cushion/jaw index in ``other``).

        Raises:
            ValueError: no cue ball, or ``shot`` is not a ``Shot``.
            RuntimeError: the event budget ``max_events`` was exceeded or the numbers went non-finite.
        """
        return self.simulate_traced(layout, shot, stop)[0]

    def simulate_traced(
        self, layout: TableLayout, shot: Shot, stop: StopAfter = StopAfter.REST
    ) -> tuple[ShotResult, np.ndarray]:
        """Like ``simulate``, plus the total kinetic energy per unit ball mass [J/kg] after each event."""
        result, trace = self._traced(layout, shot, stop)
        return result, trace[:, 0].copy()

    def ball_path(
        self,
        layout: TableLayout,
        shot: Shot,
        ball: int,
        from_first_contact: bool = False,
        step: float = PATH_STEP,
    ) -> np.ndarray:
        """Where ball ``ball`` (an index into ``layout``) goes on ``shot`` [m], (k, 2): from its start (or, with
        ``from_first_contact``, from where it first meets another ball; empty if it meets none) through each of its
        events (impacts, cushions, changes of motion) to where it comes to rest, or drops. Between events it runs on a
        parabola (a sliding ball with spin curves), sampled every ``step`` [m] or so."""
        result, trace = self._traced(layout, shot, StopAfter.REST)
        moves: list[tuple[float, np.ndarray]] = []  # time, and centre, velocity, acceleration it moves on with
        for event, row in zip(result.events, trace, strict=True):
            meets = event.kind is EventType.BALL_BALL and ball in (event.ball, event.other)
            if from_first_contact and not moves and not meets:
                continue
            if event.ball == ball:
                moves.append((event.time, row[1:7]))
            elif meets:
                moves.append((event.time, row[7:13]))
        if not moves:
            return np.zeros((0, 2)) if from_first_contact else layout.positions[[ball]].astype(float)
        points = [] if from_first_contact else [layout.positions[ball]]
        for k, (t0, motion) in enumerate(moves):  # its last event stops it (or drops it): no motion after that
            r0, v0, a = motion[0:2], motion[2:4], motion[4:6]
            t1 = moves[k + 1][0] if k + 1 < len(moves) else t0
            n = max(1, math.ceil(np.hypot(*v0) * (t1 - t0) / step))
            t = np.linspace(0.0, t1 - t0, n + 1)[:, None]
            points.extend(r0 + v0 * t + 0.5 * a * t * t)
        if ball in result.final_ids:
            points[-1] = result.final.positions[result.final_ids.index(ball)]
        path = np.array(points, dtype=float)
        keep = np.ones(len(path), dtype=bool)
        keep[1:] = np.linalg.norm(np.diff(path, axis=0), axis=1) > 1e-9  # a ball at rest through several events
        return path[keep]

    def _traced(self, layout: TableLayout, shot: Shot, stop: StopAfter) -> tuple[ShotResult, np.ndarray]:
        """One shot with its events, and per event (m, ``TRACE_WIDTH``): the kinetic energy after it per unit ball mass
        [J/kg], then the centre [m], velocity [m/s] and acceleration [m/s^2] its ball moves on with, and those of the
        other ball of a ball-ball event (NaN otherwise)."""
        cue, prm, geo = self._prepare(layout)
        if not isinstance(shot, Shot):
            raise ValueError(f"expected a Shot, got {type(shot).__name__}")
        stop_code = _STOP_CODES[StopAfter(stop)]
        row = np.array([[shot.angle, shot.speed, shot.side, shot.height, shot.elevation]], dtype=float)
        pos0 = np.array(layout.positions, dtype=float)
        cap = _FIRST_CAPACITY
        while True:  # small event buffers first; rerun with room for the whole budget if they overflow
            ev_t, ev_e = np.empty(cap), np.empty((cap, TRACE_WIDTH))
            ev_k, ev_a, ev_b = (np.empty(cap, dtype=np.int64) for _ in range(3))
            out = _Outputs(1, len(layout))
            run_shots(
                pos0,
                cue,
                row,
                prm,
                geo,
                stop_code,
                self.params.max_events,
                True,
                ev_t,
                ev_k,
                ev_a,
                ev_b,
                ev_e,
                *out.arrays,
            )
            if out.nev[0] <= cap:
                break
            cap = self.params.max_events + len(layout) + 1
        nev, status, pos = int(out.nev[0]), int(out.status[0]), out.pos[0]
        _check_status(status, self.params.max_events)
        nev = min(nev, cap)
        columns = (ev_t[:nev].tolist(), ev_k[:nev].tolist(), ev_a[:nev].tolist(), ev_b[:nev].tolist())
        events = [Event(t, _EVENT_TYPES[k], a, b) for t, k, a, b in zip(*columns, strict=True)]
        return ShotResult.from_events(layout, events, pos, validate=False), ev_e[:nev].copy()

    def simulate_arrays(
        self, layout: TableLayout, shots: np.ndarray | Sequence[Shot], stop: StopAfter = StopAfter.REST
    ) -> BatchOutcome:
        """Lean batch for the planner: outcome arrays only, no Python objects per event.

        Args:
            layout: the starting layout.
            shots: ``Shot`` objects, or an array of shape (m, 5) with columns angle [rad], speed [m/s],
                side, height (fractions of R) and elevation [rad] (not validated beyond shape/finiteness).
            stop: early-stop rule.

        Shots that exceed the event budget are flagged in ``status`` (1) instead of raising.
        """
        cue, prm, geo = self._prepare(layout)
        arr = shots_to_array(shots)
        out = _Outputs(len(arr), len(layout))
        dummy_f = np.zeros(1)
        dummy_e = np.zeros((1, TRACE_WIDTH))
        dummy_i = np.zeros(1, dtype=np.int64)
        run_shots(
            np.array(layout.positions, dtype=float),
            cue,
            arr,
            prm,
            geo,
            _STOP_CODES[StopAfter(stop)],
            self.params.max_events,
            False,
            dummy_f,
            dummy_i,
            dummy_i,
            dummy_i,
            dummy_e,
            *out.arrays,
        )
        return BatchOutcome(out.first, out.pocket, out.pos, out.status, out.nev, cue)


class _Outputs:
    """Output arrays of ``run_shots`` for ``m`` shots of ``n`` balls."""

    def __init__(self, m: int, n: int) -> None:
        self.pos = np.empty((m, n, 2))
        self.pocket = np.empty((m, n), dtype=np.int64)
        self.first = np.empty(m, dtype=np.int64)
        self.status = np.empty(m, dtype=np.int64)
        self.nev = np.empty(m, dtype=np.int64)
        self.time = np.empty(m)

    @property
    def arrays(self) -> tuple[np.ndarray, ...]:
        return (self.pos, self.pocket, self.first, self.status, self.nev, self.time)


def shots_to_array(shots: np.ndarray | Sequence[Shot]) -> np.ndarray:
    """Strokes as an (m, 5) float array: angle, speed, side, height, elevation."""
    if isinstance(shots, np.ndarray):
        arr = np.ascontiguousarray(shots, dtype=float)
        if arr.ndim != 2 or arr.shape[1] != 5:
            raise ValueError(f"shot array must have shape (m, 5), got {arr.shape}")
        if not np.all(np.isfinite(arr)):
            raise ValueError("shot array must be finite")
        if np.any(arr[:, 1] < 0):
            raise ValueError("shot speeds must be >= 0 m/s")
        return arr
    rows = []
    for s in shots:
        if not isinstance(s, Shot):
            raise ValueError(f"expected Shot objects, got {type(s).__name__}")
        rows.append((s.angle, s.speed, s.side, s.height, s.elevation))
    return np.array(rows, dtype=float).reshape(-1, 5)


def _check_status(status: int, max_events: int) -> None:
    if status == STATUS_TOO_MANY_EVENTS:
        raise RuntimeError(f"shot exceeded {max_events} events (PhysicsParams.max_events); simulation stopped")
    if status == STATUS_NOT_FINITE:
        raise RuntimeError("shot simulation produced non-finite numbers")
    if status != STATUS_OK:
        raise RuntimeError(f"shot simulation failed with status {status}")

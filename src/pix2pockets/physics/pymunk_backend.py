"""The ``pymunk`` backend: the seed paper's simplified physics, with its defects designed out.

Model (as in the paper's environment): rigid discs on a frictionless plane, no gravity, no spin; every
velocity decays by a fixed fraction per simulated second (the only rolling loss); ball-ball and
ball-cushion collisions with constant restitution; a shot sets the cue-ball velocity directly (tip
offsets and elevation are ignored). Cushions are the ``TableSpec`` cushion-nose segments, jaws its jaw
segments; a ball drops when its centre enters a pocket's capture circle.

Restitution: the paper sets shape elasticities 0.95 (balls) and 0.8 (cushions), and its code makes
ball-ball hits ideal elastic and cushion hits mirror reflections. Here ``ball_restitution`` and
``cushion_restitution`` are the coefficients of each *pair* (pymunk would otherwise multiply the two
shapes' values); ``PymunkParams(ball_restitution=1.0)`` gives the ideal elastic ball-ball hits.

Differences from the paper's code, on purpose:
    * the shot ends when every ball is slower than ``rest_speed`` (balls in resting contact were
      re-energised forever there); a simulated-time cap raises a clear ``RuntimeError`` instead of hanging;
    * every ball is kept on the table: outer walls behind the pockets, and a ball whose centre ends up
      beyond the cushion-nose line (it can only get there through a pocket mouth) drops into the nearest
      pocket; contact penetration left by the solver (< ``settle_tolerance``) is removed from the final
      layout, so results always form a valid :class:`~pix2pockets.state.TableLayout`.

References:
    pix2pockets paper, sec. 5.2 and 6.2 (environment); pymunk / Chipmunk2D documentation
    (``Space.damping``: fraction of velocity kept after one second).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

from pix2pockets.physics.base import Simulator, StopAfter, register_simulator
from pix2pockets.state import Event, EventType, Shot, ShotResult, TableLayout

_BALL, _CUSHION, _JAW, _POCKET, _WALL = 1, 2, 3, 4, 5


@dataclass(frozen=True, slots=True)
class PymunkParams:
    """Parameters of the paper-style physics.

    Attributes:
        ball_restitution: ball-ball coefficient of restitution (paper: 0.95).
        cushion_restitution: ball-cushion (and jaw) coefficient of restitution (paper: 0.8).
        damping: fraction of velocity kept after one simulated second (paper: 0.9, i.e. 10% lost per s).
        substep: simulation step [s] (paper: 1/300).
        rest_speed: the shot ends once every ball is slower than this [m/s].
        rest_check_every: check for rest and escapes every this many substeps.
        max_time: simulated-time cap [s]; exceeding it raises ``RuntimeError``.
        settle_tolerance: largest solver penetration silently removed from final positions [m].
    """

    ball_restitution: float = 0.95
    cushion_restitution: float = 0.8
    damping: float = 0.9
    substep: float = 1.0 / 300.0
    rest_speed: float = 0.01
    rest_check_every: int = 6
    max_time: float = 300.0
    settle_tolerance: float = 2e-3

    def __post_init__(self) -> None:
        for name in ("ball_restitution", "cushion_restitution", "damping"):
            value = getattr(self, name)
            if not 0.0 < value <= 1.0:
                raise ValueError(f"PymunkParams.{name} must be in (0, 1], got {value}")
        for name in ("substep", "rest_speed", "max_time", "settle_tolerance"):
            if not getattr(self, name) > 0:
                raise ValueError(f"PymunkParams.{name} must be positive, got {getattr(self, name)}")
        if self.rest_check_every < 1:
            raise ValueError(f"PymunkParams.rest_check_every must be >= 1, got {self.rest_check_every}")
        if self.damping == 1.0:
            raise ValueError("PymunkParams.damping must be < 1 or balls never come to rest")


class _Recorder:
    """Collects events from pymunk collision callbacks during one shot."""

    def __init__(self, cue: int | None) -> None:
        self.cue = cue
        self.time = 0.0
        self.events: list[Event] = []
        self.dropped: dict[int, int] = {}  # ball -> pocket, waiting to be removed from the space
        self.first_contact = False
        self.pocketed_any = False


class PymunkSimulator(Simulator):
    """Paper-style shot simulation with pymunk (see the module docstring for the model).

    Args:
        params: physics parameters.

    Example:
        >>> from pix2pockets.physics import make_simulator
        >>> sim = make_simulator("pymunk")
        >>> from pix2pockets.state import eight_ball_rack, Shot
        >>> result = sim.simulate(eight_ball_rack(), Shot(angle=0.0, speed=3.0))
        >>> result.first_contact is not None
        True
    """

    name = "pymunk"

    def __init__(self, params: PymunkParams | None = None, **overrides: float) -> None:
        base = params or PymunkParams()
        if overrides:
            from dataclasses import replace

            base = replace(base, **overrides)
        self.params = base
        # pymunk multiplies the two shapes' elasticities: choose them so the pairs get the set values.
        self._e_ball = math.sqrt(base.ball_restitution)
        self._e_cushion = base.cushion_restitution / self._e_ball

    # ------------------------------------------------------------------ public
    def simulate(self, layout: TableLayout, shot: Shot, stop: StopAfter = StopAfter.REST) -> ShotResult:
        """Simulate one shot struck on the layout's cue ball.

        Raises:
            ValueError: the layout has no cue ball.
            RuntimeError: the balls did not come to rest within ``params.max_time``.
        """
        stop = StopAfter(stop)
        cue = layout.cue_index
        if cue is None:
            raise ValueError("cannot simulate a shot: the layout has no cue ball")
        space, bodies, rec = self._build(layout)
        bodies[cue].velocity = (shot.speed * math.cos(shot.angle), shot.speed * math.sin(shot.angle))
        rec.events.append(Event(0.0, EventType.CUE_STRIKE, cue))
        self._run(layout, space, bodies, rec, stop)
        # An early stop can catch two balls mid-collision (up to one substep of travel apart).
        tol = self.params.settle_tolerance if stop is StopAfter.REST else layout.spec.ball_radius
        return self._result(layout, bodies, rec, tol)

    # ---------------------------------------------------------------- building
    def _build(self, layout: TableLayout) -> tuple[pymunk.Space, list[pymunk.Body], _Recorder]:
        spec = layout.spec
        p = self.params
        space = pymunk.Space()
        space.damping = p.damping
        space.collision_slop = 1e-5  # [m]; pymunk's default (0.1) assumes pixel units
        space.iterations = 10
        rec = _Recorder(layout.cue_index)
        owner: dict[pymunk.Shape, int] = {}

        static = space.static_body
        for i, (a, b) in enumerate(spec.cushion_segments):
            seg = pymunk.Segment(static, tuple(a), tuple(b), 0.0)
            seg.elasticity, seg.friction, seg.collision_type = self._e_cushion, 0.0, _CUSHION
            owner[seg] = i
            space.add(seg)
        for i, (a, b) in enumerate(spec.jaw_segments):
            seg = pymunk.Segment(static, tuple(a), tuple(b), 0.0)
            seg.elasticity, seg.friction, seg.collision_type = self._e_cushion, 0.0, _JAW
            owner[seg] = i
            space.add(seg)
        # Outer walls at the rail edge: nothing can leave the table, whatever happens in a pocket mouth.
        m = spec.rail_width
        box = [(-m, -m), (spec.length + m, -m), (spec.length + m, spec.width + m), (-m, spec.width + m)]
        for k in range(4):
            seg = pymunk.Segment(static, box[k], box[(k + 1) % 4], 0.0)
            seg.elasticity, seg.friction, seg.collision_type = self._e_cushion, 0.0, _WALL
            space.add(seg)
        # Pocket sensors: an object ball's circle overlaps the sensor exactly when its centre is in the capture circle
        # (a smaller cue ball's centre must come that much further in).
        for i, pocket in enumerate(spec.pockets):
            radius = pocket.capture_radius - spec.ball_radius
            if radius <= 0:
                raise ValueError(f"pocket {pocket.name}: capture radius must exceed the ball radius")
            sensor = pymunk.Circle(static, radius, tuple(pocket.centre))
            sensor.sensor, sensor.collision_type = True, _POCKET
            owner[sensor] = i
            space.add(sensor)

        bodies: list[pymunk.Body] = []
        radii, masses = layout.radii, layout.masses
        for i, (x, y) in enumerate(layout.positions):
            body = pymunk.Body(float(masses[i]), math.inf)
            body.position = (float(x), float(y))
            shape = pymunk.Circle(body, float(radii[i]))
            shape.elasticity, shape.friction, shape.collision_type = self._e_ball, 0.0, _BALL
            owner[shape] = i
            space.add(body, shape)
            bodies.append(body)

        def ball_ball(arb: pymunk.Arbiter, _space: pymunk.Space, _data: object) -> None:
            a, b = arb.shapes
            i, j = owner[a], owner[b]
            rec.events.append(Event(rec.time, EventType.BALL_BALL, i, j))
            if rec.cue in (i, j):
                rec.first_contact = True

        def ball_cushion(arb: pymunk.Arbiter, _space: pymunk.Space, _data: object) -> None:
            a, b = arb.shapes
            rec.events.append(Event(rec.time, EventType.BALL_CUSHION, owner[a], owner[b]))

        def ball_jaw(arb: pymunk.Arbiter, _space: pymunk.Space, _data: object) -> None:
            a, b = arb.shapes
            rec.events.append(Event(rec.time, EventType.BALL_JAW, owner[a], owner[b]))

        def ball_pocket(arb: pymunk.Arbiter, _space: pymunk.Space, _data: object) -> None:
            a, b = arb.shapes
            ball = owner[a]
            if ball not in rec.dropped:
                rec.dropped[ball] = owner[b]
            arb.process_collision = False

        space.on_collision(_BALL, _BALL, begin=ball_ball)
        space.on_collision(_BALL, _CUSHION, begin=ball_cushion)
        space.on_collision(_BALL, _JAW, begin=ball_jaw)
        space.on_collision(_BALL, _POCKET, begin=ball_pocket)
        return space, bodies, rec

    # ----------------------------------------------------------------- running
    def _run(
        self,
        layout: TableLayout,
        space: pymunk.Space,
        bodies: list[pymunk.Body],
        rec: _Recorder,
        stop: StopAfter,
    ) -> None:
        p = self.params
        spec = layout.spec
        r = spec.ball_radius
        lo = -r  # a centre this far beyond a nose line can only be inside a pocket mouth
        hi_x, hi_y = spec.length + r, spec.width + r
        max_steps = math.ceil(p.max_time / p.substep)
        rest2 = p.rest_speed**2
        on_table = set(range(len(bodies)))
        step = 0
        while True:
            space.step(p.substep)
            step += 1
            rec.time = step * p.substep
            if rec.dropped:
                self._drop(space, bodies, rec, on_table, list(rec.dropped.items()))
                rec.dropped.clear()
            if stop is StopAfter.FIRST_CONTACT and (rec.first_contact or rec.cue not in on_table):
                return
            if stop is StopAfter.FIRST_POCKET and rec.pocketed_any:
                return
            if step % p.rest_check_every:
                continue
            escaped = []
            moving = False
            for i in on_table:
                body = bodies[i]
                x, y = body.position
                if x < lo or y < lo or x > hi_x or y > hi_y:
                    escaped.append((i, _nearest_pocket(spec, x, y)))
                else:
                    vx, vy = body.velocity
                    if vx * vx + vy * vy > rest2:
                        moving = True
            if escaped:
                self._drop(space, bodies, rec, on_table, escaped)
            if not moving:
                for i in on_table:
                    bodies[i].velocity = (0.0, 0.0)
                return
            if step >= max_steps:
                raise RuntimeError(
                    f"pymunk: balls still moving after {p.max_time:g} s simulated "
                    f"(rest_speed {p.rest_speed} m/s, damping {p.damping}); the shot did not settle"
                )

    def _drop(
        self,
        space: pymunk.Space,
        bodies: list[pymunk.Body],
        rec: _Recorder,
        on_table: set[int],
        drops: list[tuple[int, int]],
    ) -> None:
        for ball, pocket in drops:
            if ball not in on_table:
                continue
            on_table.discard(ball)
            rec.events.append(Event(rec.time, EventType.POCKET, ball, pocket))
            rec.pocketed_any = True
            body = bodies[ball]
            body.velocity = (0.0, 0.0)
            space.remove(body, *body.shapes)

    # ------------------------------------------------------------------ result
    def _result(self, layout: TableLayout, bodies: list[pymunk.Body], rec: _Recorder, tol: float) -> ShotResult:
        spec = layout.spec
        pocketed = {e.ball for e in rec.events if e.kind is EventType.POCKET}
        pos = np.array([tuple(b.position) for b in bodies], dtype=float)
        keep = [i for i in range(len(bodies)) if i not in pocketed]
        # A ball resting beyond the cushion-nose band hangs in a pocket mouth: it drops in this model.
        r = layout.radii
        inside = spec.contains(pos[keep], margin=r[keep] - tol) if keep else np.zeros(0, bool)
        for i, ok in zip(list(keep), inside, strict=True):
            if not ok:
                rec.events.append(Event(rec.time, EventType.POCKET, i, _nearest_pocket(spec, *pos[i])))
                keep.remove(i)
        if keep:
            pos[keep] = _settle(pos[keep], r[keep], spec.size, tol)
        moved = [i for i in keep if np.any(pos[i] != layout.positions[i])]
        rec.events.extend(Event(rec.time, EventType.ROLLING_TO_STATIONARY, i) for i in moved)
        return ShotResult.from_events(layout, rec.events, pos)


def _nearest_pocket(spec, x: float, y: float) -> int:
    d = np.linalg.norm(spec.pocket_centres - np.array([x, y]), axis=1)
    return int(np.argmin(d))


def _settle(pos: np.ndarray, r: np.ndarray, size: np.ndarray, tol: float) -> np.ndarray:
    """Remove solver penetration (< ``tol`` [m]) so the positions form a valid layout of balls of radii ``r`` (n,)
    [m].

    Raises:
        RuntimeError: a penetration deeper than ``tol`` (the solver failed).
    """
    pos = pos.copy()
    r = np.asarray(r, dtype=float).reshape(-1, 1)
    gap = 2e-6  # [m] a little clearance beyond the layout tolerance
    touch = r + r.T
    for _ in range(50):
        clean = True
        lo, hi = r + gap / 2, size[None, :] - r - gap / 2
        if np.any(pos < lo - tol) or np.any(pos > hi + tol):
            raise RuntimeError("pymunk: a ball ended inside a cushion (penetration beyond the tolerance)")
        clipped = np.clip(pos, lo, hi)
        clean &= bool(np.all(clipped == pos))
        pos = clipped
        if len(pos) > 1:
            diff = pos[:, None, :] - pos[None, :, :]
            d = np.linalg.norm(diff, axis=-1)
            np.fill_diagonal(d, np.inf)
            ii, jj = np.nonzero(np.triu(d < touch + gap / 2))
            for i, j in zip(ii, jj, strict=True):
                depth = touch[i, j] + gap - d[i, j]
                if depth > tol + gap:
                    raise RuntimeError(f"pymunk: balls overlap by {depth * 1000:.2f} mm after the shot")
                n = diff[i, j] / d[i, j] if d[i, j] > 0 else np.array([1.0, 0.0])
                pos[i] += n * depth / 2
                pos[j] -= n * depth / 2
                clean = False
        if clean:
            return pos
    raise RuntimeError("pymunk: could not separate touching balls after the shot")


def _factory(**params: float) -> PymunkSimulator:
    return PymunkSimulator(**params)


register_simulator("pymunk", _factory)

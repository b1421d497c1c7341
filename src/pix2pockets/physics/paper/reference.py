"""The paper's environment world re-created in pymunk: the reference the ``paper`` kernel is checked against.

Built from the documented facts of the paper's environment (``docs/physics.md``, "The paper backend"): a
zoom-2 pixel world, discs of mass 10 and radius 14 (``moment_for_circle``), elasticity 0.95 / friction 0.9
on balls, 0.8 / 0.5 on the six polygon cushions, pocket circles of radius 30 that remove a ball on first
contact, ``damping`` 0.9, ``idle_speed_threshold`` 5, ``sleep_time_threshold`` 1e-8, 20 solver
iterations, collision slop 0.5, frames of 30 steps of 1/300 s ending when every ball sleeps. The
ball-ball post-solve callback replaces both velocities by the ideal elastic exchange computed from the
velocities at the start of the contact; the cushion post-solve callback turns the velocity into the mirror
image of the incoming one at the solved speed (one incoming velocity kept for all balls, as there).
About 150 times slower than the kernel; for tests and ``benchmarks/paper_pymunk_check.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk

from pix2pockets.geometry.raster import PAPER_LAYOUT
from pix2pockets.physics.paper.params import PAPER_PX
from pix2pockets.state import Event, EventType, Shot, ShotResult, TableLayout

BALL, POCKET, CUSHION = 1, 2, 3


def pymunk_shot(
    uv: np.ndarray, cue: int, angle_px: float, speed_px: float, max_frames: int = 10_000
) -> tuple[dict[int, tuple[int, int]], np.ndarray, int, int]:
    """Play one stroke in the re-created world.

    Args:
        uv: ball centres [px], zoom 2 (``v`` down).
        cue: index of the cue ball.
        angle_px: stroke direction in the pixel frame [rad].
        speed_px: cue-ball speed [px/s].
        max_frames: frames of 0.1 s before giving up (the paper's 10,000).

    Returns:
        (pocketed ball -> (pocket, step), final centres [px], first ball the cue ball hit or -1, frames).
    """
    lay = PAPER_LAYOUT
    space = pymunk.Space()
    space.gravity = (0, 0)
    space.damping = 0.9
    space.collision_slop = 0.5
    space.idle_speed_threshold = 5
    space.sleep_time_threshold = 1e-8
    space.iterations = 20
    for quad in lay.cushion_polygons:
        shape = pymunk.Poly(space.static_body, [tuple(p) for p in quad])
        shape.elasticity, shape.friction, shape.collision_type = 0.8, 0.5, CUSHION
        space.add(shape)
    pocket_of: dict[pymunk.Shape, int] = {}
    for k, centre in enumerate(lay.pocket_centres):
        shape = pymunk.Circle(space.static_body, lay.pocket_radius, tuple(centre))
        shape.collision_type = POCKET
        pocket_of[shape] = k
        space.add(shape)
    number: dict[pymunk.Shape, int] = {}
    bodies = []
    for i, (u, v) in enumerate(uv):
        body = pymunk.Body(10, pymunk.moment_for_circle(10, 0, lay.ball_radius))
        body.position = (float(u), float(v))
        shape = pymunk.Circle(body, lay.ball_radius)
        shape.elasticity, shape.friction, shape.collision_type = 0.95, 0.9, BALL
        number[shape] = i
        space.add(body, shape)
        bodies.append(body)
    state = {"first": -1, "contact_vel": {}, "cushion_vel": pymunk.Vec2d(0, 0), "pocketed": {}, "step": 0}

    def ball_begin(arb, _space, _data):
        a, b = arb.shapes
        i, j = number[a], number[b]
        if state["first"] < 0 and cue in (i, j):
            state["first"] = j if i == cue else i
        state["contact_vel"][i] = a.body.velocity
        state["contact_vel"][j] = b.body.velocity

    def ball_post(arb, _space, _data):
        a, b = arb.shapes
        v1, v2 = state["contact_vel"][number[a]], state["contact_vel"][number[b]]
        x1, x2 = a.body.position, b.body.position
        d = x1 - x2
        f = (v1 - v2).dot(d) / d.length_squared
        a.body.velocity = v1 - d * f
        b.body.velocity = v2 + d * f

    def pocket_begin(arb, space_, _data):
        a, b = arb.shapes
        state["pocketed"][number[a]] = (pocket_of[b], state["step"])
        space_.remove(a, a.body)
        arb.process_collision = False

    def cushion_begin(arb, _space, _data):
        state["cushion_vel"] = arb.shapes[0].body.velocity

    def cushion_post(arb, _space, _data):
        body = arb.shapes[0].body
        d, n = state["cushion_vel"], arb.normal
        speed = body.velocity.length
        body.velocity = (d - n * (2 * d.dot(n))).normalized() * speed

    space.on_collision(BALL, BALL, begin=ball_begin, post_solve=ball_post)
    space.on_collision(BALL, POCKET, begin=pocket_begin)
    space.on_collision(BALL, CUSHION, begin=cushion_begin, post_solve=cushion_post)
    body = bodies[cue]
    body.activate()
    body.velocity = (speed_px * math.cos(angle_px), speed_px * math.sin(angle_px))
    frames = 0
    while frames < max_frames:
        if all(b.is_sleeping for i, b in enumerate(bodies) if i not in state["pocketed"]):
            break
        frames += 1
        for _ in range(30):
            state["step"] += 1
            space.step(0.1 / 30)
    final = np.array([tuple(b.position) for b in bodies])
    return state["pocketed"], final, state["first"], frames


class PymunkPaperWorld:
    """The re-created world as a simulator (``simulate(layout, shot) -> ShotResult``) on paper layouts."""

    name = "paper-pymunk"

    def simulate(self, layout: TableLayout, shot: Shot) -> ShotResult:
        """Play ``shot`` (tip offsets ignored) on a layout of the paper's table; events: strike and drops."""
        uv = PAPER_LAYOUT.from_table(layout.positions)
        pots, final_uv, _first, _frames = pymunk_shot(uv, layout.cue_index, -shot.angle, shot.speed / PAPER_PX)
        events = [Event(0.0, EventType.CUE_STRIKE, layout.cue_index)]
        events += [Event(step / 300.0, EventType.POCKET, b, k) for b, (k, step) in pots.items()]
        return ShotResult.from_events(layout, events, PAPER_LAYOUT.to_table(final_uv), validate=False)

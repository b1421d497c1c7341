"""Exact next-event times from the motion polynomials (numba kernels).

Within a state each centre follows ``r(t) = r0 + v t + a t^2 / 2``, so

* ball-ball contact ``|r_j(t) - r_i(t)|^2 = (2R)^2`` is a quartic in ``t``;
* contact with a cushion or jaw segment's line ``n . (r(t) - p) = R`` is a quadratic (accepted only when
  the contact point lies on the segment);
* contact with a segment end point (a jaw point) ``|r(t) - p|^2 = R^2`` is a quartic;
* capture ``|r(t) - c|^2 = r_pocket^2`` (the centre enters a pocket's capture circle) is a quartic.

Each is solved for its first fresh crossing with :func:`~._roots.first_drop` up to the horizon where one
of the balls changes state. A pair already in contact (within ``CONTACT_TOL``) and approaching collides
at once; touching and separating pairs are skipped, so there is no immediate re-collision.
"""

from __future__ import annotations

import math

from numba import njit

from pix2pockets.physics.event._balls import radius_of
from pix2pockets.physics.event._motion import INF, ST_ROLLING, ST_SLIDING
from pix2pockets.physics.event._roots import first_drop

CONTACT_TOL = 1e-9  # [m] distances within this of contact count as touching
APPROACH_EPS = 1e-12  # [m/s] slower approaches do not count as an immediate impact
PRESS_EPS = 1e-9  # [m/s^2] weaker accelerations into a contact do not count as pressing

ENV_NONE, ENV_LINE, ENV_POINT, ENV_POCKET = 0, 1, 2, 3


@njit(cache=True, inline="always")
def _translating(s: int) -> bool:
    return s in (ST_SLIDING, ST_ROLLING)


@njit(cache=True)
def pair_time(i, j, now, pos, vel, acc, st, tend, prm) -> float:
    """Absolute time of the next impact of balls ``i`` and ``j`` before either changes state, or inf."""
    mi = _translating(st[i])
    mj = _translating(st[j])
    if not (mi or mj):
        return INF
    horizon = INF
    if mi:
        horizon = tend[i]
    if mj and tend[j] < horizon:
        horizon = tend[j]
    h = horizon - now
    if h < 0.0:
        h = 0.0
    D = radius_of(prm, i) + radius_of(prm, j)
    rx = pos[j, 0] - pos[i, 0]
    ry = pos[j, 1] - pos[i, 1]
    vx = vel[j, 0] - vel[i, 0]
    vy = vel[j, 1] - vel[i, 1]
    ax = acc[j, 0] - acc[i, 0]
    ay = acc[j, 1] - acc[i, 1]
    dist = math.hypot(rx, ry)
    reach = math.hypot(vx, vy) * h + 0.5 * math.hypot(ax, ay) * h * h
    if dist - D > reach + CONTACT_TOL:
        return INF
    c0 = (dist - D) * (dist + D)
    c1 = 2.0 * (rx * vx + ry * vy)
    c2 = vx * vx + vy * vy + rx * ax + ry * ay
    if dist - D <= CONTACT_TOL:
        eps = 2.0 * D * APPROACH_EPS
        if c1 < -eps:
            return now  # touching and approaching
        if h > 0.0 and c1 <= eps and c2 < -D * PRESS_EPS:
            return now  # touching and about to press into each other (one pushes the other)
    c3 = vx * ax + vy * ay
    c4 = 0.25 * (ax * ax + ay * ay)
    return now + first_drop(c0, c1, c2, c3, c4, h)


@njit(cache=True)
def env_time(i, now, pos, vel, acc, tend, prm, seg_a, seg_u, seg_n, seg_len, pts, pk_c, pk_r):
    """Next cushion/jaw/pocket event of moving ball ``i``: (absolute time, ENV_* kind, index)."""
    R = radius_of(prm, i)
    h = tend[i] - now
    if h < 0.0:
        h = 0.0
    px, py = pos[i, 0], pos[i, 1]
    vx, vy = vel[i, 0], vel[i, 1]
    ax, ay = acc[i, 0], acc[i, 1]
    reach = math.hypot(vx, vy) * h + 0.5 * math.hypot(ax, ay) * h * h
    best = INF
    kind = ENV_NONE
    idx = -1
    # segment lines (cushion noses, then jaw faces)
    for k in range(seg_a.shape[0]):
        nx, ny = seg_n[k, 0], seg_n[k, 1]
        dn = (px - seg_a[k, 0]) * nx + (py - seg_a[k, 1]) * ny
        if dn > 0.5 * R:
            side = 1.0
        elif dn < -0.5 * R:
            side = -1.0
        else:
            continue  # centre near the line beyond the segment: its end points handle it
        f0 = side * dn - R
        if f0 > reach + CONTACT_TOL:
            continue
        c1 = side * (vx * nx + vy * ny)
        c2 = 0.5 * side * (ax * nx + ay * ny)
        touching = f0 <= CONTACT_TOL
        if touching and (c1 < -APPROACH_EPS or (h > 0.0 and c1 <= APPROACH_EPS and c2 < -0.5 * PRESS_EPS)):
            tau = 0.0  # touching and approaching, or about to press into the cushion
        else:
            tau = first_drop(f0, c1, c2, 0.0, 0.0, h)
        if tau < best:
            qx = px + tau * (vx + 0.5 * tau * ax) - seg_a[k, 0]
            qy = py + tau * (vy + 0.5 * tau * ay) - seg_a[k, 1]
            s = qx * seg_u[k, 0] + qy * seg_u[k, 1]
            if -1e-12 <= s <= seg_len[k] + 1e-12:
                best, kind, idx = tau, ENV_LINE, k
    # segment end points
    for q in range(pts.shape[0]):
        tau = _circle_entry(px - pts[q, 0], py - pts[q, 1], vx, vy, ax, ay, R, reach, h, False)
        if tau < best:
            best, kind, idx = tau, ENV_POINT, q
    # pocket capture circles
    for q in range(pk_c.shape[0]):
        tau = _circle_entry(px - pk_c[q, 0], py - pk_c[q, 1], vx, vy, ax, ay, pk_r[q], reach, h, True)
        if tau < best:
            best, kind, idx = tau, ENV_POCKET, q
    return now + best, kind, idx


@njit(cache=True, inline="always")
def _circle_entry(rx, ry, vx, vy, ax, ay, radius, reach, h, inside_counts) -> float:
    """First time the centre (relative position ``r``) enters a circle of ``radius`` around the origin."""
    dist = math.hypot(rx, ry)
    if dist - radius > reach + CONTACT_TOL:
        return INF
    c1 = 2.0 * (rx * vx + ry * vy)
    if dist - radius <= CONTACT_TOL:
        if inside_counts and dist < radius:
            return 0.0
        if c1 < -2.0 * radius * APPROACH_EPS:
            return 0.0
    c0 = (dist - radius) * (dist + radius)
    c2 = vx * vx + vy * vy + rx * ax + ry * ay
    c3 = vx * ax + vy * ay
    c4 = 0.25 * (ax * ax + ay * ay)
    return first_drop(c0, c1, c2, c3, c4, h)

"""Impacts on groups of touching balls: the contacts resolved together, as compliant spheres (numba kernels).

Two balls meet for a fraction of a millisecond, and an instantaneous impulse with restitution describes them well.
A ball driven into a group of balls that touch (a rack, two or three frozen balls) is different: the first contact
is still on when the next ones start, so the force spreads through the group at once. Played as a chain of two-ball
impulses, a rack struck full passes nearly all of the cue ball's speed to one or two balls at its back; struck with
compliant contacts, the whole rack opens.

:func:`impact_group` collects the balls in such a group: those within reach of the struck pair through contacts
closer than the distance the impact's speed covers during one contact time. :func:`compliant_impact` resolves it:
Hertz's contact force between elastic spheres, ``F = k d^(3/2)`` with ``k = 4/3 E* sqrt(R*)`` for an overlap
``d``, damped after Hunt and Crossley, ``F (1 + 3 (1 - e) d' / (2 v))``, so that a pair meeting at speed ``v`` parts
with the restitution ``e`` of the two-ball law. The impact lasts about a millisecond, so the balls' centres are held
where they are (they move well under a millimetre) and only their velocities change: each contact's overlap follows
from the relative speed along its line of centres. The force is internal, so momentum is kept exactly; the balls'
spins are kept, as in the two-ball law (frictionless contacts).

References:
    L. D. Landau, E. M. Lifshitz, Theory of Elasticity, sec. 9 (Hertz's force and contact time); K. H. Hunt,
    F. R. E. Crossley, "Coefficient of restitution interpreted as damping in vibroimpact", J. Appl. Mech. 1975;
    S. Crown, phenolic-resin billiard balls: Young's modulus 5.84 GPa, Poisson's ratio 0.34.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from pix2pockets.physics.event._balls import mass_of, radius_of
from pix2pockets.physics.event._motion import mark_group
from pix2pockets.physics.event.params import P_E_BALL

BALL_YOUNG_MODULUS = 5.84e9
"""Young's modulus of a phenolic-resin ball [Pa]."""
BALL_POISSON = 0.34
"""Poisson's ratio of a phenolic-resin ball [-]."""
OBJECT_BALL_MASS = 0.163
"""Mass of an object ball [kg] (5.75 oz): sets the contact time, hence which neighbours share an impact."""
CONTACT_E = BALL_YOUNG_MODULUS / (2.0 * (1.0 - BALL_POISSON**2))
"""Effective modulus ``E*`` of two such balls in contact [Pa]."""
STEPS_PER_CONTACT = 60
"""Integration steps per contact time of the striking pair."""
MAX_STEPS = 200_000
"""Integration steps after which an impact ends whatever its state (about 3,000 contact times)."""


@njit(cache=True)
def contact_time(i, j, speed, prm) -> float:
    """Hertz's duration [s] of a contact between balls ``i`` and ``j`` meeting at ``speed`` [m/s]:
    ``2.87 (m*^2 / (R* E*^2 v))^(1/5)``."""
    ri, rj = radius_of(prm, i), radius_of(prm, j)
    mi, mj = OBJECT_BALL_MASS * mass_of(prm, i), OBJECT_BALL_MASS * mass_of(prm, j)
    m_eff = mi * mj / (mi + mj)
    r_eff = ri * rj / (ri + rj)
    return 2.87 * (m_eff * m_eff / (r_eff * CONTACT_E * CONTACT_E * max(speed, 1e-9))) ** 0.2


@njit(cache=True)
def closing_speed(i, j, pos, vel) -> float:
    """Speed [m/s] at which balls ``i`` and ``j`` approach each other along their line of centres."""
    dx, dy = pos[j, 0] - pos[i, 0], pos[j, 1] - pos[i, 1]
    d = math.hypot(dx, dy)
    if d == 0.0:
        return 0.0
    return ((vel[i, 0] - vel[j, 0]) * dx + (vel[i, 1] - vel[j, 1]) * dy) / d


@njit(cache=True)
def impact_group(i, j, n, pos, vel, st, prm, reach, member) -> int:
    """Mark in ``member`` (bool, (n,)) the balls linked to the pair ``i``, ``j`` through gaps of at most ``reach``
    [m], whatever their speed; returns how many."""
    return mark_group(i, j, n, pos, vel, st, prm, reach, math.inf, member)


@njit(cache=True)
def compliant_impact(i, j, n, pos, vel, prm, member, reach) -> int:
    """Resolve the impact of ball ``i`` on ball ``j`` together with every ball ``member`` marks (see the module).

    Contacts are the member pairs closer than ``reach`` [m]; their overlap starts at minus their gap. The velocities
    ``vel`` (n, 2) [m/s] of the members change in place. Returns the integration steps taken.
    """
    idx = np.empty(n, dtype=np.int64)
    m = 0
    for k in range(n):
        if member[k]:
            idx[m] = k
            m += 1
    pa = np.empty(m * (m - 1) // 2, dtype=np.int64)
    pb = np.empty_like(pa)
    nx = np.empty(pa.shape[0])
    ny = np.empty(pa.shape[0])
    overlap = np.empty(pa.shape[0])
    stiff = np.empty(pa.shape[0])
    c = 0
    for u in range(m):
        for v in range(u + 1, m):
            a, b = idx[u], idx[v]
            dx, dy = pos[b, 0] - pos[a, 0], pos[b, 1] - pos[a, 1]
            d = math.hypot(dx, dy)
            ra, rb = radius_of(prm, a), radius_of(prm, b)
            if d == 0.0 or d - ra - rb >= reach:
                continue
            pa[c], pb[c] = a, b
            nx[c], ny[c] = dx / d, dy / d
            overlap[c] = ra + rb - d
            stiff[c] = 4.0 / 3.0 * CONTACT_E * math.sqrt(ra * rb / (ra + rb))
            c += 1
    mass = np.empty(n)
    for k in range(n):
        mass[k] = OBJECT_BALL_MASS * mass_of(prm, k)
    v_in = closing_speed(i, j, pos, vel)
    damping = 1.5 * (1.0 - prm[P_E_BALL]) / max(v_in, 1e-9)
    t_contact = contact_time(i, j, v_in, prm)
    dt = t_contact / STEPS_PER_CONTACT
    force = np.zeros(c)
    steps = 0
    touched = False
    while steps < MAX_STEPS:
        steps += 1
        active = False
        for p in range(c):
            a, b = pa[p], pb[p]
            closing = (vel[a, 0] - vel[b, 0]) * nx[p] + (vel[a, 1] - vel[b, 1]) * ny[p]
            force[p] = 0.0
            if overlap[p] > 0.0:
                active = True
                f = stiff[p] * overlap[p] ** 1.5 * (1.0 + damping * closing)
                force[p] = max(f, 0.0)
        for p in range(c):
            a, b = pa[p], pb[p]
            f = force[p] * dt
            vel[a, 0] -= f * nx[p] / mass[a]
            vel[a, 1] -= f * ny[p] / mass[a]
            vel[b, 0] += f * nx[p] / mass[b]
            vel[b, 1] += f * ny[p] / mass[b]
        pending = False  # a pair still closing that would touch within one contact time
        for p in range(c):
            a, b = pa[p], pb[p]
            closing = (vel[a, 0] - vel[b, 0]) * nx[p] + (vel[a, 1] - vel[b, 1]) * ny[p]
            overlap[p] += closing * dt
            if overlap[p] <= 0.0 and closing > 0.0 and -overlap[p] < closing * t_contact:
                pending = True
        touched = touched or active
        if touched and not active and not pending:
            break
    return steps

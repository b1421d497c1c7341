"""Ball motion between events, the cue strike and the collision laws (numba kernels).

A ball is in one of five motion states. In every state its centre moves on a parabola
``r(t) = r0 + v0 t + a t^2 / 2`` with a constant acceleration ``a`` fixed when the state begins:

* sliding: the contact point slips with velocity ``u = v + w x (-R z)``; friction ``-mu_s g u_hat``
  brakes and spins the ball until ``u = 0`` after ``2 |u| / (7 mu_s g)``;
* rolling: ``w_xy = z x v / R``; rolling resistance ``-mu_r g v_hat`` until rest after ``|v| / (mu_r g)``;
* spinning: at rest on the cloth, ``w_z`` decays at ``5 mu_sp g / (2 R)`` until it stops;
* stationary; pocketed.

``w_z`` (side spin) decays at the same rate in every moving state; it does not move the centre.

References:
    W. Leckie, M. Greenspan, "An event-based pool physics simulator", ACG 2006, sec. 3 (equations of
    motion per state); E. Kiefl, pooltool documentation "Ball motion" (same model, default constants).
"""

from __future__ import annotations

import math

from numba import njit

from pix2pockets.physics.event._balls import cushion_sin_of, mass_of, radius_of
from pix2pockets.physics.event.params import (
    BALL_FRICTION_FIT,
    P_BALL_FRICTION,
    P_E_BALL,
    P_E_CUSHION,
    P_G,
    P_MU_CUSHION,
    P_MU_ROLL,
    P_MU_SLIDE,
    P_MU_SPIN,
    P_V_SETTLE,
)

ST_STATIONARY, ST_SPINNING, ST_SLIDING, ST_ROLLING, ST_POCKETED = 0, 1, 2, 3, 4
EPS_SLIP = 1e-9  # [m/s] slip speed below which a ball counts as rolling
EPS_SPEED = 1e-9  # [m/s] speed below which a ball counts as at rest
EPS_SPIN = 1e-7  # [rad/s] side spin below which a ball counts as stationary
INF = math.inf


@njit(cache=True, inline="always")
def moving(state: int) -> bool:
    """Whether a ball in ``state`` translates."""
    return state in (ST_SLIDING, ST_ROLLING)


@njit(cache=True)
def set_motion(i, now, vel, w, st, acc, wacc, tend, prm) -> None:
    """Classify ball ``i`` from its velocity and spin at time ``now`` and set its state constants."""
    R = radius_of(prm, i)
    g = prm[P_G]
    vx, vy = vel[i, 0], vel[i, 1]
    ux = vx - R * w[i, 1]
    uy = vy + R * w[i, 0]
    slip = math.hypot(ux, uy)
    speed = math.hypot(vx, vy)
    if slip > EPS_SLIP:
        mu = prm[P_MU_SLIDE]
        st[i] = ST_SLIDING
        acc[i, 0] = -mu * g * ux / slip
        acc[i, 1] = -mu * g * uy / slip
        k = 2.5 * mu * g / R
        wacc[i, 0] = -k * uy / slip
        wacc[i, 1] = k * ux / slip
        tend[i] = now + 2.0 * slip / (7.0 * mu * g)
        return
    if speed > EPS_SPEED:
        mu = prm[P_MU_ROLL]
        st[i] = ST_ROLLING
        w[i, 0] = -vy / R
        w[i, 1] = vx / R
        acc[i, 0] = -mu * g * vx / speed
        acc[i, 1] = -mu * g * vy / speed
        wacc[i, 0] = -acc[i, 1] / R
        wacc[i, 1] = acc[i, 0] / R
        tend[i] = now + speed / (mu * g)
        return
    vel[i, 0] = 0.0
    vel[i, 1] = 0.0
    w[i, 0] = 0.0
    w[i, 1] = 0.0
    acc[i, 0] = 0.0
    acc[i, 1] = 0.0
    wacc[i, 0] = 0.0
    wacc[i, 1] = 0.0
    if abs(w[i, 2]) > EPS_SPIN:
        st[i] = ST_SPINNING
        tend[i] = now + abs(w[i, 2]) / spin_decel(prm, i)
    else:
        st[i] = ST_STATIONARY
        w[i, 2] = 0.0
        tend[i] = INF


@njit(cache=True, inline="always")
def spin_decel(prm, i) -> float:
    """Angular deceleration of ball ``i``'s side spin [rad/s^2]."""
    return 2.5 * prm[P_MU_SPIN] * prm[P_G] / radius_of(prm, i)


@njit(cache=True)
def advance(n, dt, pos, vel, w, st, acc, wacc, prm) -> None:
    """Move every ball ``dt`` [s] along its current state (no state changes)."""
    if dt <= 0.0:
        return
    for i in range(n):
        s = st[i]
        if s in (ST_SLIDING, ST_ROLLING):
            pos[i, 0] += dt * (vel[i, 0] + 0.5 * dt * acc[i, 0])
            pos[i, 1] += dt * (vel[i, 1] + 0.5 * dt * acc[i, 1])
            vel[i, 0] += dt * acc[i, 0]
            vel[i, 1] += dt * acc[i, 1]
            w[i, 0] += dt * wacc[i, 0]
            w[i, 1] += dt * wacc[i, 1]
        if s in (ST_SLIDING, ST_ROLLING, ST_SPINNING):
            dw = spin_decel(prm, i) * dt
            wz = w[i, 2]
            if wz > 0.0:
                w[i, 2] = max(wz - dw, 0.0)
            elif wz < 0.0:
                w[i, 2] = min(wz + dw, 0.0)


@njit(cache=True)
def transition(i, now, vel, w, st, acc, wacc, tend, prm) -> int:
    """End ball ``i``'s current state at ``now``; returns the event code (see ``_engine``)."""
    s = st[i]
    if s == ST_SLIDING:
        R = radius_of(prm, i)
        w[i, 0] = -vel[i, 1] / R  # enforce the rolling constraint exactly
        w[i, 1] = vel[i, 0] / R
        set_motion(i, now, vel, w, st, acc, wacc, tend, prm)
        return 5
    if s == ST_ROLLING:
        vel[i, 0] = 0.0
        vel[i, 1] = 0.0
        w[i, 0] = 0.0
        w[i, 1] = 0.0
        set_motion(i, now, vel, w, st, acc, wacc, tend, prm)
        return 6 if st[i] == ST_SPINNING else 8
    w[i, 2] = 0.0
    st[i] = ST_STATIONARY
    tend[i] = INF
    return 7


@njit(cache=True)
def strike(i, angle, speed, side, height, elevation, vel, w, prm) -> None:
    """Give ball ``i`` the velocity and spin of a cue strike (instantaneous point impulse).

    The cue tip meets the ball at ``side * R`` right of and ``height * R`` above the centre, pushing
    along the cue (tilted down by ``elevation``); the table absorbs the vertical impulse, so the ball
    leaves at ``speed`` along ``angle`` with spin ``w = m (p x J) / I``, ``I = 2 m R^2 / 5``.

    References:
        Leckie & Greenspan 2006, sec. 4 (cue-ball strike); Alciatore, TP A.30 (natural roll at
        ``height = 0.4``). Squirt and swerve are not modelled.
    """
    R = radius_of(prm, i)
    dx, dy = math.cos(angle), math.sin(angle)
    rx, ry = dy, -dx  # right of the aiming direction
    c = R * math.sqrt(max(1.0 - side * side - height * height, 0.0))
    px = -c * dx + side * R * rx
    py = -c * dy + side * R * ry
    pz = height * R
    ce, se = math.cos(elevation), math.sin(elevation)
    fx, fy, fz = ce * dx, ce * dy, -se
    jmag = speed / ce  # impulse per unit mass along the cue [m/s]
    k = jmag * 2.5 / (R * R)
    vel[i, 0] = speed * dx
    vel[i, 1] = speed * dy
    w[i, 0] = k * (py * fz - pz * fy)
    w[i, 1] = k * (pz * fx - px * fz)
    w[i, 2] = k * (px * fy - py * fx)


COLLIDE_BOUNCE, COLLIDE_LOCK, COLLIDE_NUDGE = 0, 1, 2
NUDGE_GAP = 1e-7  # [m] gap a slow, pushing pair is set to so the next contact is a fresh crossing


@njit(cache=True)
def collide_balls(i, j, pos, vel, w, prm) -> int:
    """Frictionless instantaneous ball-ball impact with restitution; spins are kept.

    The normal impulse ``J = (1 + e) m_i m_j / (m_i + m_j) v_rel`` changes each ball's velocity by ``J / m``: equal
    balls exchange ``(1 + e) v_rel / 2``, a lighter cue ball bounces back from a heavier object ball.

    Slow contacts (normal approach below the settle speed, e.g. one ball pushing another) are not
    bounced: if the two balls barely move relative to each other the caller locks them together
    (``COLLIDE_LOCK``, see ``lock_cluster``); otherwise the impact is perfectly inelastic, the spin that
    drives either ball into the other is dropped and the pair is set ``NUDGE_GAP`` apart
    (``COLLIDE_NUDGE``), so the event loop never spins at one instant.

    Returns:
        ``COLLIDE_BOUNCE``, ``COLLIDE_LOCK`` or ``COLLIDE_NUDGE``.
    """
    nx = pos[j, 0] - pos[i, 0]
    ny = pos[j, 1] - pos[i, 1]
    d = math.hypot(nx, ny)
    if d == 0.0:
        return COLLIDE_BOUNCE
    nx /= d
    ny /= d
    dvx = vel[i, 0] - vel[j, 0]
    dvy = vel[i, 1] - vel[j, 1]
    vrel = dvx * nx + dvy * ny
    settle = prm[P_V_SETTLE]
    mi, mj = mass_of(prm, i), mass_of(prm, j)
    share_i, share_j = mj / (mi + mj), mi / (mi + mj)  # each ball's share of the velocity change
    if vrel >= settle:
        jn = (1.0 + prm[P_E_BALL]) * vrel
        vel[i, 0] -= jn * share_i * nx
        vel[i, 1] -= jn * share_i * ny
        vel[j, 0] += jn * share_j * nx
        vel[j, 1] += jn * share_j * ny
        if prm[P_BALL_FRICTION] > 0.0:
            _throw(i, j, nx, ny, jn * mi * share_i, vel, w, prm)
        return COLLIDE_BOUNCE
    if math.hypot(dvx, dvy) < settle:
        return COLLIDE_LOCK
    if vrel > 0.0:
        vel[i, 0] -= vrel * share_i * nx
        vel[i, 1] -= vrel * share_i * ny
        vel[j, 0] += vrel * share_j * nx
        vel[j, 1] += vrel * share_j * ny
    _drop_normal_slip(i, nx, ny, w)
    _drop_normal_slip(j, nx, ny, w)
    return COLLIDE_NUDGE


@njit(cache=True)
def _throw(i, j, nx, ny, impulse, vel, w, prm) -> None:
    """Friction at a ball-ball impact whose normal impulse is ``impulse`` [relative mass x m/s] along ``(nx, ny)``
    from ball ``i`` to ball ``j``.

    The contact points slip with the relative surface velocity ``s`` (centres and spins, 3-D, less its part along
    the normal). A tangential impulse against it, ``min(mu |J_n|, |s| / (7/2 (1/m_i + 1/m_j)))`` (Coulomb friction,
    capped at what stops the slip: each sphere's contact point moves ``7/2`` times as far per impulse as its centre,
    ``1/m + R^2/I``), changes the balls' velocities in the table plane (the cloth takes the vertical part) and their
    spins in full. ``mu`` falls with the slip speed (:data:`~pix2pockets.physics.event.params.BALL_FRICTION_FIT`).
    Momentum in the plane is kept; energy is only lost.
    """
    ri, rj = radius_of(prm, i), radius_of(prm, j)
    mi, mj = mass_of(prm, i), mass_of(prm, j)
    # surface velocity of each ball at the contact: v + w x r, r = R n for i and -R n for j
    six = vel[i, 0] - w[i, 2] * ri * ny - (vel[j, 0] + w[j, 2] * rj * ny)
    siy = vel[i, 1] + w[i, 2] * ri * nx - (vel[j, 1] - w[j, 2] * rj * nx)
    siz = ri * (w[i, 0] * ny - w[i, 1] * nx) + rj * (w[j, 0] * ny - w[j, 1] * nx)
    along = six * nx + siy * ny
    tx, ty, tz = six - along * nx, siy - along * ny, siz
    slip = math.sqrt(tx * tx + ty * ty + tz * tz)
    if slip < EPS_SLIP:
        return
    a, b, c = BALL_FRICTION_FIT
    mu = a + b * math.exp(-c * slip)
    p = min(mu * impulse, slip / (3.5 * (1.0 / mi + 1.0 / mj)))
    tx, ty, tz = tx / slip, ty / slip, tz / slip
    vel[i, 0] -= p * tx / mi
    vel[i, 1] -= p * ty / mi
    vel[j, 0] += p * tx / mj
    vel[j, 1] += p * ty / mj
    # n x t: the spin each impulse gives; r_i x (-p t) = -p R_i (n x t), r_j x (p t) = -p R_j (n x t)
    cx, cy, cz = ny * tz, -nx * tz, nx * ty - ny * tx
    ki = p / (0.4 * mi * ri)
    kj = p / (0.4 * mj * rj)
    w[i, 0] -= ki * cx
    w[i, 1] -= ki * cy
    w[i, 2] -= ki * cz
    w[j, 0] -= kj * cx
    w[j, 1] -= kj * cy
    w[j, 2] -= kj * cz


@njit(cache=True)
def nudge_apart(i, j, n, pos, st, prm, length, width) -> bool:
    """Set a slow, pressing pair ``NUDGE_GAP`` apart along its line of centres.

    Each ball moves half the way, unless that would bring it closer to a third ball it already nearly
    touches, or push it further past a cushion-nose line (``length`` x ``width`` [m] playing surface),
    so repeated nudges never build up an overlap with neighbours or push a ball pinned against a
    cushion through it.

    Returns:
        whether the pair is now apart (``False``: both balls are boxed in; the caller locks them).
    """
    D = radius_of(prm, i) + radius_of(prm, j)
    nx = pos[j, 0] - pos[i, 0]
    ny = pos[j, 1] - pos[i, 1]
    d = math.hypot(nx, ny)
    if d == 0.0:
        return False
    if d - D >= NUDGE_GAP:
        return True
    nx /= d
    ny /= d
    half = 0.5 * (NUDGE_GAP - (d - D))
    moved = False
    for b, sgn in ((i, -1.0), (j, 1.0)):
        mx = pos[b, 0] + sgn * half * nx
        my = pos[b, 1] + sgn * half * ny
        R = radius_of(prm, b)
        ok = _outside(mx, my, R, length, width) <= max(_outside(pos[b, 0], pos[b, 1], R, length, width), 0.0)
        for k in range(n):
            if not ok:
                break
            if k in (i, j) or st[k] == ST_POCKETED:
                continue
            touch = R + radius_of(prm, k)
            new_gap = math.hypot(mx - pos[k, 0], my - pos[k, 1]) - touch
            if new_gap < NUDGE_GAP:
                old_gap = math.hypot(pos[b, 0] - pos[k, 0], pos[b, 1] - pos[k, 1]) - touch
                if new_gap < old_gap:
                    ok = False
                    break
        if ok:
            pos[b, 0] = mx
            pos[b, 1] = my
            moved = True
    return moved


@njit(cache=True, inline="always")
def _outside(x, y, R, length, width) -> float:
    """How far a centre at (x, y) lies past the nearest cushion-nose line (<= 0 inside) [m]."""
    return max(R - x, x - (length - R), R - y, y - (width - R))


@njit(cache=True)
def mark_group(i, j, n, pos, vel, st, prm, max_gap, max_speed_apart, member) -> int:
    """Mark in ``member`` (bool, (n,)) the balls linked to the pair ``i``, ``j`` through gaps of at most ``max_gap``
    [m] whose velocity differs from the pair's mean by less than ``max_speed_apart`` [m/s] (``inf``: any); returns
    how many (pocketed balls never count)."""
    for k in range(n):
        member[k] = False
    ref_x = 0.5 * (vel[i, 0] + vel[j, 0])
    ref_y = 0.5 * (vel[i, 1] + vel[j, 1])
    stack = [i, j]
    member[i] = True
    member[j] = True
    count = 2
    while len(stack) > 0:
        a = stack.pop()
        for b in range(n):
            if member[b] or st[b] == ST_POCKETED:
                continue
            touch = radius_of(prm, a) + radius_of(prm, b)
            if math.hypot(pos[b, 0] - pos[a, 0], pos[b, 1] - pos[a, 1]) - touch > max_gap:
                continue
            if math.hypot(vel[b, 0] - ref_x, vel[b, 1] - ref_y) >= max_speed_apart:
                continue
            member[b] = True
            stack.append(b)
            count += 1
    return count


@njit(cache=True)
def lock_cluster(i, j, n, pos, vel, w, st, prm, member) -> int:
    """Make the touching, nearly co-moving balls around pair (i, j) move as one.

    Collects every ball connected to ``i`` or ``j`` through contacts (gap below ``NUDGE_GAP``) whose
    velocity differs from the pair's by less than the settle speed, and gives them all their mean
    velocity (weighted by mass) and spin (weighted by moment of inertia). Momentum is conserved and kinetic
    energy can only drop; afterwards the members share one trajectory, so no further events occur between them.

    Returns:
        the number of members; ``member`` (bool, shape (n,)) marks them.
    """
    count = mark_group(i, j, n, pos, vel, st, prm, NUDGE_GAP, prm[P_V_SETTLE], member)
    sv0 = sv1 = sw0 = sw1 = sw2 = sm = si = 0.0
    for k in range(n):
        if member[k]:
            m = mass_of(prm, k)
            inertia = m * radius_of(prm, k) ** 2
            sm += m
            si += inertia
            sv0 += m * vel[k, 0]
            sv1 += m * vel[k, 1]
            sw0 += inertia * w[k, 0]
            sw1 += inertia * w[k, 1]
            sw2 += inertia * w[k, 2]
    for k in range(n):
        if member[k]:
            vel[k, 0] = sv0 / sm
            vel[k, 1] = sv1 / sm
            w[k, 0] = sw0 / si
            w[k, 1] = sw1 / si
            w[k, 2] = sw2 / si
    return count


@njit(cache=True, inline="always")
def _drop_normal_slip(i, nx, ny, w) -> None:
    """Keep only the spin about ``n`` in the table plane: no contact-point slip along ``n`` remains."""
    k = w[i, 0] * nx + w[i, 1] * ny
    w[i, 0] = k * nx
    w[i, 1] = k * ny


@njit(cache=True)
def collide_cushion(i, nx, ny, vel, w, prm) -> None:
    """Ball ``i`` hits a cushion (or jaw) whose unit normal ``n`` (in the plane) points toward the ball.

    The cushion nose touches the ball above its equator, so the contact normal ``N`` tilts down by
    ``asin((h - R) / R)``. At the contact point an instantaneous impulse acts: along ``N`` with
    restitution ``e_cushion``, and Coulomb friction ``mu_cushion`` against the contact-point slip, capped
    at the impulse that stops the slip. This couples speed with all three spin components (running
    English, topspin and draw off the rail). The table absorbs the vertical part of the impulse.

    Impacts slower than the settle speed are not bounced: the normal velocity is removed along with the
    spin that would drive the ball back into the cushion.

    References:
        Rigid-body impulse of a sphere on a half-space with Coulomb friction (e.g. Mathavan et al.,
        "A theoretical analysis of billiard ball dynamics under cushion impacts", Proc. IMechE C 224,
        2010, sec. 2; pooltool's ``impulse_frictional_inelastic`` cushion model uses the same law).
    """
    R = radius_of(prm, i)
    vn = vel[i, 0] * nx + vel[i, 1] * ny
    settle = prm[P_V_SETTLE]
    if vn > -settle:
        # slow or pressing contact: no bounce, and no spin left that drives the ball into the cushion
        _drop_normal_slip(i, nx, ny, w)
        vt = -vel[i, 0] * ny + vel[i, 1] * nx
        if vn < settle:  # stop the normal motion exactly: the ball then runs along the cushion
            vel[i, 0] = -vt * ny
            vel[i, 1] = vt * nx
        return
    s = cushion_sin_of(prm, i)
    c = math.sqrt(1.0 - s * s)
    # contact point relative to the centre, and the unit normal from it to the centre
    rx, ry, rz = -R * c * nx, -R * c * ny, R * s
    Nx, Ny, Nz = c * nx, c * ny, -s
    wx, wy, wz = w[i, 0], w[i, 1], w[i, 2]
    ux = vel[i, 0] + (wy * rz - wz * ry)
    uy = vel[i, 1] + (wz * rx - wx * rz)
    uz = wx * ry - wy * rx
    un = ux * Nx + uy * Ny + uz * Nz
    if un >= 0.0:
        return
    jn = -(1.0 + prm[P_E_CUSHION]) * un
    tx, ty, tz = ux - un * Nx, uy - un * Ny, uz - un * Nz
    slip = math.sqrt(tx * tx + ty * ty + tz * tz)
    jx, jy, jz = jn * Nx, jn * Ny, jn * Nz
    if slip > 0.0:
        jt = min(prm[P_MU_CUSHION] * jn, slip * 2.0 / 7.0)
        jx -= jt * tx / slip
        jy -= jt * ty / slip
        jz -= jt * tz / slip
    vel[i, 0] += jx
    vel[i, 1] += jy
    k = 2.5 / (R * R)  # m / I
    w[i, 0] += k * (ry * jz - rz * jy)
    w[i, 1] += k * (rz * jx - rx * jz)
    w[i, 2] += k * (rx * jy - ry * jx)


@njit(cache=True)
def kinetic_energy(n, vel, w, st, prm) -> float:
    """Total kinetic energy per unit object-ball mass [J/kg] of the balls still on the table."""
    k = 0.0
    for i in range(n):
        if st[i] == ST_POCKETED:
            continue
        R = radius_of(prm, i)
        m = mass_of(prm, i)
        k += 0.5 * m * (vel[i, 0] ** 2 + vel[i, 1] ** 2)
        k += 0.2 * m * R * R * (w[i, 0] ** 2 + w[i, 1] ** 2 + w[i, 2] ** 2)
    return k

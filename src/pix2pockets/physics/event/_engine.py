"""The event loop: strike, then repeatedly jump to the earliest event and resolve it (numba kernels).

Next-event times are cached per ball pair (ball-ball), per ball (cushion/jaw/pocket) and per ball
(state transition). After an event only the entries of the one or two balls it changed are recomputed;
every other cached time stays exact because those balls' trajectories did not change.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from pix2pockets.physics.event._balls import radius_of
from pix2pockets.physics.event._detect import ENV_LINE, ENV_NONE, ENV_POCKET, env_time, pair_time
from pix2pockets.physics.event._impact import closing_speed, compliant_impact, contact_time, impact_group
from pix2pockets.physics.event._motion import (
    COLLIDE_LOCK,
    COLLIDE_NUDGE,
    INF,
    ST_POCKETED,
    ST_ROLLING,
    ST_SLIDING,
    ST_SPINNING,
    ST_STATIONARY,
    advance,
    collide_balls,
    collide_cushion,
    kinetic_energy,
    lock_cluster,
    nudge_apart,
    set_motion,
    strike,
    transition,
)
from pix2pockets.physics.event.params import P_V_SETTLE

# Event codes (mapped to EventType by the Python wrapper).
EV_STRIKE, EV_BALL, EV_CUSHION, EV_JAW, EV_POCKET = 0, 1, 2, 3, 4
EV_SLIDE_ROLL, EV_ROLL_SPIN, EV_SPIN_STOP, EV_ROLL_STOP = 5, 6, 7, 8
STOP_REST, STOP_FIRST_CONTACT, STOP_FIRST_POCKET = 0, 1, 2
STATUS_OK, STATUS_TOO_MANY_EVENTS, STATUS_NOT_FINITE = 0, 1, 2
N_CUSHIONS = 6  # the first 6 segments are cushion noses, the rest jaw faces
_SURFACE_TOL = 1e-7  # [m] a resting centre further outside the surface than this has dropped
_NO_BALL = np.int64(-1)


TRACE_WIDTH = 13
"""Columns of ``ev_e`` per event: the kinetic energy after it, then the centre, velocity and acceleration of its ball
(1-6) and of its other ball in a ball-ball event (7-12, NaN otherwise), as they move on from the event."""


@njit(cache=True, inline="always")
def _record(nev, record, ev_t, ev_k, ev_a, ev_b, ev_e, t, k, a, b, energy, pos, vel, acc) -> int:
    """Store one event: time, code, balls, and in ``ev_e`` (:data:`TRACE_WIDTH` columns) the kinetic energy after it
    and how its ball (and the other ball of a ball-ball event) moves on from it."""
    if record and nev < ev_t.shape[0]:
        ev_t[nev] = t
        ev_k[nev] = k
        ev_a[nev] = a
        ev_b[nev] = b
        ev_e[nev, 0] = energy
        for col, ball in ((1, a), (7, b)):
            known = col == 1 or k == EV_BALL  # the other ball of a ball-ball event only
            for axis in range(2):
                ev_e[nev, col + axis] = pos[ball, axis] if known else np.nan
                ev_e[nev, col + 2 + axis] = vel[ball, axis] if known else np.nan
                ev_e[nev, col + 4 + axis] = acc[ball, axis] if known else np.nan
    return nev + 1


@njit(cache=True)
def _refresh(c, n, now, pos, vel, acc, st, tend, prm, geo, ptime, et, ek, ei) -> None:
    """Recompute the cached event times involving ball ``c``."""
    seg_a, seg_u, seg_n, seg_len, pts, _pt_jaw, pk_c, pk_r, _size = geo
    if st[c] == ST_SLIDING or st[c] == ST_ROLLING:
        t, k, idx = env_time(c, now, pos, vel, acc, tend, prm, seg_a, seg_u, seg_n, seg_len, pts, pk_c, pk_r)
        et[c], ek[c], ei[c] = t, k, idx
    else:
        et[c], ek[c], ei[c] = INF, ENV_NONE, -1
    for j in range(n):
        if j == c:
            continue
        a, b = (c, j) if c < j else (j, c)
        if st[c] == ST_POCKETED or st[j] == ST_POCKETED:
            ptime[a, b] = INF
        else:
            ptime[a, b] = pair_time(a, b, now, pos, vel, acc, st, tend, prm)


@njit(cache=True)
def run_shot(
    pos,
    cue,
    angle,
    speed,
    side,
    height,
    elevation,
    prm,
    geo,
    stop_mode,
    max_events,
    record,
    ev_t,
    ev_k,
    ev_a,
    ev_b,
    ev_e,
    pocket_of,
):
    """Simulate one shot in place.

    Args:
        pos: ball centres [m], shape (n, 2); overwritten with the final centres.
        cue: index of the struck ball.
        angle, speed, side, height, elevation: the stroke (see ``Shot``).
        prm: packed ``PhysicsParams``; geo: packed table geometry (see ``pack_table``).
        stop_mode: ``STOP_*``; max_events: event budget.
        record: whether to store events in ``ev_*`` (time, code, ball, other; ``ev_e`` (m, :data:`TRACE_WIDTH`):
            the kinetic energy after each event and how its ball, and the other ball of a ball-ball event, move on).
        pocket_of: output, pocket index per ball or -1, shape (n,).

    Returns:
        (number of events, status, first ball the cue ball touched or -1, end time [s]).
    """
    seg_a, _seg_u, seg_n, _seg_len, pts, pt_jaw, pk_c, pk_r, size = geo
    n = pos.shape[0]
    vel = np.zeros((n, 2))
    w = np.zeros((n, 3))
    acc = np.zeros((n, 2))
    wacc = np.zeros((n, 2))
    st = np.full(n, ST_STATIONARY, dtype=np.int64)
    tend = np.full(n, INF)
    et = np.full(n, INF)
    ek = np.zeros(n, dtype=np.int64)
    ei = np.full(n, -1, dtype=np.int64)
    ptime = np.full((n, n), INF)
    member = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        pocket_of[i] = -1

    now = 0.0
    strike(cue, angle, speed, side, height, elevation, vel, w, prm)
    set_motion(cue, now, vel, w, st, acc, wacc, tend, prm)
    energy = kinetic_energy(n, vel, w, st, prm)
    nev = _record(0, record, ev_t, ev_k, ev_a, ev_b, ev_e, 0.0, EV_STRIKE, cue, -1, energy, pos, vel, acc)
    _refresh(cue, n, now, pos, vel, acc, st, tend, prm, geo, ptime, et, ek, ei)
    first = -1
    status = STATUS_OK
    stopped = False

    while True:
        # earliest cached event
        best = INF
        kind = -1  # 0 pair, 1 env, 2 transition
        # typed int64, not as the literal -1: a literal argument would make numba compile every callee
        # once more for that literal (a slower first run, same code)
        bi = _NO_BALL
        bj = _NO_BALL
        for i in range(n):
            if et[i] < best:
                best, kind, bi = et[i], 1, i
            s = st[i]
            if (s in (ST_SLIDING, ST_ROLLING, ST_SPINNING)) and tend[i] < best:
                best, kind, bi = tend[i], 2, i
            for j in range(i + 1, n):
                if ptime[i, j] < best:
                    best, kind, bi, bj = ptime[i, j], 0, i, j
        if best == INF:
            break
        if nev >= max_events:
            status = STATUS_TOO_MANY_EVENTS
            break
        if best < now:
            best = now
        advance(n, best - now, pos, vel, w, st, acc, wacc, prm)
        now = best

        c1 = bi
        c2 = _NO_BALL
        grouped = False  # the event changed the motion of every ball ``member`` marks
        if kind == 0:
            c2 = bj
            closing = closing_speed(bi, bj, pos, vel)
            group = 2
            reach = 0.0
            if closing >= prm[P_V_SETTLE]:
                reach = closing * contact_time(bi, bj, closing, prm)
                group = impact_group(bi, bj, n, pos, vel, st, prm, reach, member)
            if group > 2:  # balls touching either one share the impact
                compliant_impact(bi, bj, n, pos, vel, prm, member, reach)
                grouped = True
            else:
                outcome = collide_balls(bi, bj, pos, vel, w, prm)
                if outcome == COLLIDE_NUDGE and not nudge_apart(bi, bj, n, pos, st, prm, size[0], size[1]):
                    outcome = COLLIDE_LOCK
                if outcome == COLLIDE_LOCK:
                    grouped = True
                    lock_cluster(bi, bj, n, pos, vel, w, st, prm, member)
            if grouped:
                for k in range(n):
                    if member[k]:
                        set_motion(k, now, vel, w, st, acc, wacc, tend, prm)
            else:
                set_motion(bi, now, vel, w, st, acc, wacc, tend, prm)
                set_motion(bj, now, vel, w, st, acc, wacc, tend, prm)
            code, a, b = EV_BALL, bi, bj
            if first < 0 and (bi == cue or bj == cue):
                first = bj if bi == cue else bi
                if stop_mode == STOP_FIRST_CONTACT:
                    stopped = True
        elif kind == 1:
            k = ek[bi]
            idx = ei[bi]
            if k == ENV_POCKET:
                st[bi] = ST_POCKETED
                tend[bi] = INF
                vel[bi, 0] = vel[bi, 1] = 0.0
                w[bi, 0] = w[bi, 1] = w[bi, 2] = 0.0
                pocket_of[bi] = idx
                code, a, b = EV_POCKET, bi, idx
                if stop_mode == STOP_FIRST_POCKET or (stop_mode == STOP_FIRST_CONTACT and bi == cue):
                    stopped = True
            else:
                if k == ENV_LINE:
                    nx, ny = seg_n[idx, 0], seg_n[idx, 1]
                    dn = (pos[bi, 0] - seg_a[idx, 0]) * nx + (pos[bi, 1] - seg_a[idx, 1]) * ny
                    if dn < 0.0:
                        nx, ny = -nx, -ny
                    if idx < N_CUSHIONS:
                        code, a, b = EV_CUSHION, bi, idx
                    else:
                        code, a, b = EV_JAW, bi, idx - N_CUSHIONS
                else:  # ENV_POINT
                    nx = pos[bi, 0] - pts[idx, 0]
                    ny = pos[bi, 1] - pts[idx, 1]
                    d = math.hypot(nx, ny)
                    nx /= d
                    ny /= d
                    code, a, b = EV_JAW, bi, pt_jaw[idx]
                collide_cushion(bi, nx, ny, vel, w, prm)
                set_motion(bi, now, vel, w, st, acc, wacc, tend, prm)
        else:
            code = transition(bi, now, vel, w, st, acc, wacc, tend, prm)
            a, b = bi, -1

        energy = kinetic_energy(n, vel, w, st, prm) if record else 0.0
        nev = _record(nev, record, ev_t, ev_k, ev_a, ev_b, ev_e, now, code, a, b, energy, pos, vel, acc)
        if not (math.isfinite(pos[c1, 0]) and math.isfinite(pos[c1, 1]) and math.isfinite(now)):
            status = STATUS_NOT_FINITE
            break
        if stopped:
            break
        if grouped:
            for k in range(n):
                if member[k]:
                    _refresh(k, n, now, pos, vel, acc, st, tend, prm, geo, ptime, et, ek, ei)
        else:
            _refresh(c1, n, now, pos, vel, acc, st, tend, prm, geo, ptime, et, ek, ei)
            if c2 >= 0:
                _refresh(c2, n, now, pos, vel, acc, st, tend, prm, geo, ptime, et, ek, ei)

    # A ball resting beyond a cushion-nose line can only be in a pocket mouth: it drops.
    L, W = size[0], size[1]
    for i in range(n):
        if st[i] == ST_POCKETED:
            continue
        x, y = pos[i, 0], pos[i, 1]
        R = radius_of(prm, i)
        out = x < R - _SURFACE_TOL or x > L - R + _SURFACE_TOL or y < R - _SURFACE_TOL or y > W - R + _SURFACE_TOL
        if not out:
            continue
        if stopped or status != STATUS_OK:  # a snapshot mid-shot: keep it on the surface
            pos[i, 0] = min(max(x, R), L - R)
            pos[i, 1] = min(max(y, R), W - R)
            continue
        best_q = 0
        best_d = INF
        for q in range(pk_c.shape[0]):
            d = math.hypot(x - pk_c[q, 0], y - pk_c[q, 1]) - pk_r[q]
            if d < best_d:
                best_d, best_q = d, q
        st[i] = ST_POCKETED
        pocket_of[i] = best_q
        nev = _record(nev, record, ev_t, ev_k, ev_a, ev_b, ev_e, now, EV_POCKET, i, best_q, 0.0, pos, vel, acc)
    return nev, status, first, now


@njit(cache=True)
def run_shots(
    pos0,
    cue,
    shots,
    prm,
    geo,
    stop_mode,
    max_events,
    record,
    ev_t,
    ev_k,
    ev_a,
    ev_b,
    ev_e,
    out_pos,
    out_pocket,
    out_first,
    out_status,
    out_nev,
    out_time,
):
    """Simulate shots from one layout: the single compiled entry point (one JIT compile for all uses).

    Args:
        pos0: starting centres [m], shape (n, 2).
        shots: one stroke per row: angle, speed, side, height, elevation; shape (m, 5).
        record: store the events of the (single) shot in ``ev_*`` (time, code, ball, other, and in ``ev_e`` the
            energy after and how the event's balls move on, see :func:`run_shot`); with ``record`` pass ``m == 1``.
        out_pos: final centres, shape (m, n, 2); out_pocket: pocket per ball or -1, shape (m, n);
        out_first: cue ball's first contact or -1, shape (m,); out_status / out_nev / out_time: status,
        event count and end time [s] per shot, shape (m,).
    """
    n = pos0.shape[0]
    pos = np.empty_like(pos0)
    pocket_of = np.empty(n, dtype=np.int64)
    # element loops, not slice assignment: slice assignment compiles numba's shape-mismatch error
    # formatting (several seconds of the first run's compile)
    for m in range(shots.shape[0]):
        for i in range(n):
            pos[i, 0] = pos0[i, 0]
            pos[i, 1] = pos0[i, 1]
        nev, status, first, t_end = run_shot(
            pos,
            cue,
            shots[m, 0],
            shots[m, 1],
            shots[m, 2],
            shots[m, 3],
            shots[m, 4],
            prm,
            geo,
            stop_mode,
            max_events,
            record,
            ev_t,
            ev_k,
            ev_a,
            ev_b,
            ev_e,
            pocket_of,
        )
        for i in range(n):
            out_pos[m, i, 0] = pos[i, 0]
            out_pos[m, i, 1] = pos[i, 1]
            out_pocket[m, i] = pocket_of[i]
        out_first[m] = first
        out_status[m] = status
        out_nev[m] = nev
        out_time[m] = t_end

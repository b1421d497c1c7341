"""The paper's dynamics in closed form, event by event, on pymunk's step grid (numba kernel).

Every velocity (and disc spin) decays as ``exp(-k t)``, the same for every ball, so with the clock
``tau(t) = C (1 - exp(-k t)) / k`` each ball moves in a straight line at a constant ``tau``-velocity
``W = v exp(k t)`` between contacts: ``x = A + W tau``. Contact conditions are then linear or quadratic in
``tau`` and solved exactly. ``C = k dt / (1 - exp(-k dt))`` makes the positions at the step times
``t_n = n dt`` equal to pymunk's (which moves ``v dt`` per step, then damps ``v``).

pymunk finds contacts only at the end of a step; this kernel does the same: a contact becomes an event
at the first step time at which the shapes overlap (a contact whose overlap starts and ends between two
steps is missed, as in pymunk) and is resolved with the velocities the balls had during that step, at the
overlapping positions. That is what makes the object ball of a cut shot leave up to a degree or two
thinner than the ideal ghost-ball line, as in the paper's environment.

Contact laws (the paper's code on top of pymunk's impulse solver): ball-ball - the ideal elastic
exchange along the line of centres at the overlapping positions; the discs' friction impulse (capped by
``mu`` times pymunk's normal impulse) only spins them. Cushion - pymunk's impulse (restitution, friction
against the disc's slip) sets the speed, the direction is the mirror image of the incoming velocity
about the contact normal. A ball drops at the first step at which it overlaps a pocket circle, and falls
asleep (stops) at the first step it starts slower than the idle speed while touching no other ball.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# Packed parameter indices (``PaperParams.packed``).
(P_K, P_DT, P_CLOCK, P_R, P_SLEEP2, P_E_CUSHION, P_MU_CUSHION, P_E_BALL, P_MU_BALL, P_SPIN, P_MAX_STEPS,
 P_SURFACE_BAND) = range(12)  # fmt: skip
N_PARAMS = 12

# Event codes (mapped to EventType by the Python wrapper).
EV_STRIKE, EV_BALL, EV_CUSHION, EV_JAW, EV_POCKET, EV_STOP = 0, 1, 2, 3, 4, 5
KIND_CUSHION, KIND_JAW = 0, 1
STOP_REST, STOP_FIRST_CONTACT, STOP_FIRST_POCKET = 0, 1, 2
STATUS_OK, STATUS_TOO_LONG, STATUS_NOT_FINITE = 0, 1, 2
MOVING, ASLEEP, POCKETED = 0, 1, 2
NEVER = np.int64(1) << np.int64(60)
INF = math.inf


@njit(cache=True, inline="always")
def _tau(n, prm) -> float:
    """The clock ``tau`` at step ``n`` [s]."""
    k = prm[P_K]
    return prm[P_CLOCK] * -math.expm1(-k * n * prm[P_DT]) / k


@njit(cache=True)
def _first_step(tau, now, prm) -> np.int64:
    """The first step after ``now`` whose clock is at least ``tau`` (``NEVER`` past the clock's limit)."""
    x = prm[P_K] * tau / prm[P_CLOCK]
    if x >= 1.0:
        return NEVER
    t = -math.log1p(-x) / prm[P_K]
    n = np.int64(math.ceil(t / prm[P_DT]))
    if n > 0 and _tau(n - 1, prm) >= tau:
        n -= 1
    if n <= now:
        n = now + 1
    return n


@njit(cache=True, inline="always")
def _circle_entry(rx, ry, wx, wy, rad) -> float:
    """Clock time from now until a point at ``(rx, ry)`` moving at ``(wx, wy)`` enters the circle of radius
    ``rad`` around the origin (``INF`` if never; 0 if inside)."""
    c = rx * rx + ry * ry - rad * rad
    if c <= 0.0:
        return 0.0
    a = wx * wx + wy * wy
    b = rx * wx + ry * wy
    if a == 0.0 or b >= 0.0:
        return INF
    disc = b * b - a * c
    if disc <= 0.0:
        return INF
    return c / (-b + math.sqrt(disc))


@njit(cache=True)
def _poly_closest(poly, p, x, y):
    """Closest point of cushion polygon ``p`` to ``(x, y)``: (distance, cx, cy, edge, at_vertex)."""
    best, bx, by, be, bv = INF, 0.0, 0.0, 0, -1
    for e in range(4):
        ax, ay = poly[p, e, 0], poly[p, e, 1]
        ex, ey = poly[p, (e + 1) % 4, 0] - ax, poly[p, (e + 1) % 4, 1] - ay
        ll = ex * ex + ey * ey
        s = ((x - ax) * ex + (y - ay) * ey) / ll
        vertex = -1
        if s <= 0.0:
            s, vertex = 0.0, e
        elif s >= 1.0:
            s, vertex = 1.0, (e + 1) % 4
        cx, cy = ax + s * ex, ay + s * ey
        d = math.hypot(x - cx, y - cy)
        if d < best:
            best, bx, by, be, bv = d, cx, cy, e, vertex
    return best, bx, by, be, bv


@njit(cache=True)
def _pair_step(i, j, now, A, W, prm) -> np.int64:
    """First step at which balls ``i`` and ``j`` are found overlapping (``NEVER`` if not on these paths)."""
    tn = _tau(now, prm)
    d2 = 2.0 * prm[P_R]
    wx, wy = W[i, 0] - W[j, 0], W[i, 1] - W[j, 1]
    px = A[i, 0] - A[j, 0] + wx * tn
    py = A[i, 1] - A[j, 1] + wy * tn
    a = wx * wx + wy * wy
    b = px * wx + py * wy
    c = px * px + py * py - d2 * d2
    if c < 0.0:  # overlapping now: a contact again next step only if they still approach
        return now + 1 if b < 0.0 else NEVER
    if a == 0.0 or b >= 0.0:
        return NEVER
    disc = b * b - a * c
    if disc <= 0.0:
        return NEVER
    sq = math.sqrt(disc)
    s_in = c / (-b + sq)
    s_out = (-b + sq) / a
    n = _first_step(tn + s_in, now, prm)
    if n == NEVER or _tau(n, prm) >= tn + s_out:
        return NEVER  # the overlap lies between two steps: pymunk never sees it
    return n


@njit(cache=True)
def _cushion_step(i, now, A, W, prm, poly) -> np.int64:
    """First step at which ball ``i`` is found overlapping a cushion (or still pressing into one)."""
    r = prm[P_R]
    tn = _tau(now, prm)
    x0, y0 = A[i, 0] + W[i, 0] * tn, A[i, 1] + W[i, 1] * tn
    wx, wy = W[i, 0], W[i, 1]
    best = NEVER
    for p in range(poly.shape[0]):
        d, cx, cy, _e, _v = _poly_closest(poly, p, x0, y0)
        if d < r:
            if (x0 - cx) * wx + (y0 - cy) * wy < 0.0:
                best = min(best, now + 1)
            continue
        gx = 0.25 * (poly[p, 0, 0] + poly[p, 1, 0] + poly[p, 2, 0] + poly[p, 3, 0])
        gy = 0.25 * (poly[p, 0, 1] + poly[p, 1, 1] + poly[p, 2, 1] + poly[p, 3, 1])
        s_in = INF
        for e in range(4):
            ax, ay = poly[p, e, 0], poly[p, e, 1]
            ex, ey = poly[p, (e + 1) % 4, 0] - ax, poly[p, (e + 1) % 4, 1] - ay
            length = math.hypot(ex, ey)
            ux, uy = ex / length, ey / length
            nx, ny = -uy, ux
            if nx * (ax - gx) + ny * (ay - gy) < 0.0:
                nx, ny = -nx, -ny
            h0 = nx * (x0 - ax) + ny * (y0 - ay)
            h1 = nx * wx + ny * wy
            if h1 < 0.0 and h0 > r:
                s = (r - h0) / h1
                lam = ux * (x0 + wx * s - ax) + uy * (y0 + wy * s - ay)
                if 0.0 <= lam <= length:
                    s_in = min(s_in, s)
            s_in = min(s_in, _circle_entry(x0 - ax, y0 - ay, wx, wy, r))
        if s_in == INF:
            continue
        n = _first_step(tn + s_in, now, prm)
        if n >= best:
            continue
        tau = _tau(n, prm)
        d, _cx, _cy, _e, _v = _poly_closest(poly, p, A[i, 0] + wx * tau, A[i, 1] + wy * tau)
        if d < r:  # else the ball only grazed the corner between two steps
            best = n
    return best


@njit(cache=True)
def _pocket_step(i, now, A, W, prm, pk_c, pk_r) -> np.int64:
    """First step at which ball ``i`` is found overlapping a pocket circle."""
    tn = _tau(now, prm)
    x0, y0 = A[i, 0] + W[i, 0] * tn, A[i, 1] + W[i, 1] * tn
    best = NEVER
    for p in range(pk_c.shape[0]):
        s = _circle_entry(x0 - pk_c[p, 0], y0 - pk_c[p, 1], W[i, 0], W[i, 1], pk_r[p])
        if s == INF:
            continue
        n = _first_step(tn + s, now, prm)
        if n >= best:
            continue
        tau = _tau(n, prm)
        if math.hypot(A[i, 0] + W[i, 0] * tau - pk_c[p, 0], A[i, 1] + W[i, 1] * tau - pk_c[p, 1]) < pk_r[p]:
            best = n
    return best


@njit(cache=True)
def _sleep_step(i, now, W, OM, prm) -> np.int64:
    """First step at which ball ``i`` starts idle (its speed, spin included, at or below the idle speed)."""
    r = prm[P_R]
    e = W[i, 0] * W[i, 0] + W[i, 1] * W[i, 1] + prm[P_SPIN] * 0.5 * r * r * OM[i] * OM[i]
    thr = prm[P_SLEEP2]
    if e <= thr:
        return now + 1
    m = math.ceil(math.log(e / thr) / (2.0 * prm[P_K] * prm[P_DT]))
    return max(np.int64(m) + 1, now + 1)


@njit(cache=True)
def _refresh(c, now, st, A, W, OM, prm, poly, pk_c, pk_r, pair_next, cush_next, pock_next, sleep_next) -> None:
    """Recompute every predicted step that involves ball ``c``."""
    n = st.shape[0]
    for j in range(n):
        if j == c:
            continue
        a, b = (c, j) if c < j else (j, c)
        if st[a] == POCKETED or st[b] == POCKETED or (st[a] == ASLEEP and st[b] == ASLEEP):
            pair_next[a, b] = NEVER
        else:
            pair_next[a, b] = _pair_step(a, b, now, A, W, prm)
    if st[c] == MOVING:
        cush_next[c] = _cushion_step(c, now, A, W, prm, poly)
        pock_next[c] = _pocket_step(c, now, A, W, prm, pk_c, pk_r)
        sleep_next[c] = _sleep_step(c, now, W, OM, prm)
    else:
        cush_next[c] = NEVER
        pock_next[c] = NEVER
        sleep_next[c] = NEVER


@njit(cache=True, inline="always")
def _record(nev, record, ev_t, ev_k, ev_a, ev_b, t, k, a, b) -> int:
    if record and nev < ev_t.shape[0]:
        ev_t[nev] = t
        ev_k[nev] = k
        ev_a[nev] = a
        ev_b[nev] = b
    return nev + 1


@njit(cache=True)
def _settle(X, st, pocket, prm, size, pk_c, t, nev, record, ev_t, ev_k, ev_a, ev_b) -> int:
    """Make the resting layout valid: a ball past a cushion-nose line by more than the surface band rests
    in a pocket mouth and drops into the nearest pocket; within the band it is moved back onto the surface;
    touching balls left overlapping by less than a step are pushed apart."""
    r = prm[P_R]
    band = prm[P_SURFACE_BAND]
    n = st.shape[0]
    for i in range(n):
        if st[i] == POCKETED:
            continue
        out = max(r - X[i, 0], X[i, 0] - (size[0] - r), r - X[i, 1], X[i, 1] - (size[1] - r))
        if out > band:
            best, bp = INF, 0
            for p in range(pk_c.shape[0]):
                d = math.hypot(X[i, 0] - pk_c[p, 0], X[i, 1] - pk_c[p, 1])
                if d < best:
                    best, bp = d, p
            st[i] = POCKETED
            pocket[i] = bp
            nev = _record(nev, record, ev_t, ev_k, ev_a, ev_b, t, EV_POCKET, i, bp)
    gap = 1e-9
    for _ in range(50):
        clean = True
        for i in range(n):
            if st[i] == POCKETED:
                continue
            for ax in range(2):
                lo, hi = r + gap, size[ax] - r - gap
                if X[i, ax] < lo:
                    X[i, ax] = lo
                    clean = False
                elif X[i, ax] > hi:
                    X[i, ax] = hi
                    clean = False
        for i in range(n):
            if st[i] == POCKETED:
                continue
            for j in range(i + 1, n):
                if st[j] == POCKETED:
                    continue
                dx, dy = X[i, 0] - X[j, 0], X[i, 1] - X[j, 1]
                d = math.hypot(dx, dy)
                if d < 2.0 * r + gap:
                    push = 0.5 * (2.0 * r + 2.0 * gap - d)
                    ux, uy = (dx / d, dy / d) if d > 0.0 else (1.0, 0.0)
                    X[i, 0] += ux * push
                    X[i, 1] += uy * push
                    X[j, 0] -= ux * push
                    X[j, 1] -= uy * push
                    clean = False
        if clean:
            break
    return nev


@njit(cache=True)
def run_shot(
    pos0, cue, angle, speed, prm, poly, edge_kind, edge_index, vertex_kind, vertex_index, pk_c, pk_r, size,
    stop, max_events, record, ev_t, ev_k, ev_a, ev_b, out_pos, out_pocket,
):  # fmt: skip
    """Simulate one centre-ball stroke; returns (events, status, first contact, duration [s]).

    ``out_pos`` (n, 2) receives the final centres (pocketed balls: where they dropped), ``out_pocket`` (n,)
    the pocket each ball dropped into or -1.
    """
    n = pos0.shape[0]
    r = prm[P_R]
    k, dt = prm[P_K], prm[P_DT]
    spin = prm[P_SPIN] > 0.0
    max_steps = np.int64(prm[P_MAX_STEPS])
    A = pos0.copy()
    W = np.zeros((n, 2))
    OM = np.zeros(n)
    SV = np.zeros((n, 2))
    SO = np.zeros(n)
    st = np.full(n, ASLEEP, dtype=np.int64)
    pocket = np.full(n, -1, dtype=np.int64)
    X = pos0.copy()
    XP = pos0.copy()
    V = np.zeros((n, 2))
    OMn = np.zeros(n)
    NV = np.zeros((n, 2))
    NO = np.zeros(n)
    changed = np.zeros(n, dtype=np.bool_)
    touched = np.zeros(n, dtype=np.bool_)
    pair_next = np.full((n, n), NEVER, dtype=np.int64)
    cush_next = np.full(n, NEVER, dtype=np.int64)
    pock_next = np.full(n, NEVER, dtype=np.int64)
    sleep_next = np.full(n, NEVER, dtype=np.int64)

    W[cue, 0] = speed * math.cos(angle)
    W[cue, 1] = speed * math.sin(angle)
    st[cue] = MOVING
    for i in range(n):  # a ball placed inside a pocket circle drops at the first step, as in pymunk
        for p in range(pk_c.shape[0]):
            if math.hypot(A[i, 0] - pk_c[p, 0], A[i, 1] - pk_c[p, 1]) < pk_r[p]:
                st[i] = MOVING
    nev = _record(0, record, ev_t, ev_k, ev_a, ev_b, 0.0, EV_STRIKE, cue, -1)
    now = np.int64(0)
    for i in range(n):
        _refresh(i, now, st, A, W, OM, prm, poly, pk_c, pk_r, pair_next, cush_next, pock_next, sleep_next)
    first = -1
    status = STATUS_OK
    done = False
    while not done:
        step = NEVER
        any_moving = False
        for i in range(n):
            if st[i] == MOVING:
                any_moving = True
                step = min(step, cush_next[i], pock_next[i], sleep_next[i])
            for j in range(i + 1, n):
                step = min(step, pair_next[i, j])
        if not any_moving or step == NEVER:
            break
        if step > max_steps or nev > max_events or step <= now:
            status = STATUS_TOO_LONG
            break
        now = step
        t = now * dt
        tn = _tau(now, prm)
        tp = _tau(now - 1, prm)
        back = math.exp(-k * (now - 1) * dt)
        for i in range(n):
            changed[i] = False
            touched[i] = False
            if st[i] == POCKETED:
                continue
            X[i, 0] = A[i, 0] + W[i, 0] * tn
            X[i, 1] = A[i, 1] + W[i, 1] * tn
            XP[i, 0] = A[i, 0] + W[i, 0] * tp
            XP[i, 1] = A[i, 1] + W[i, 1] * tp
            if st[i] == MOVING:  # the velocity the ball moved with during this step
                V[i, 0], V[i, 1], OMn[i] = W[i, 0] * back, W[i, 1] * back, OM[i] * back
            else:
                V[i, 0], V[i, 1], OMn[i] = SV[i, 0], SV[i, 1], SO[i]
            NV[i, 0], NV[i, 1], NO[i] = V[i, 0], V[i, 1], OMn[i]
            if not (math.isfinite(X[i, 0]) and math.isfinite(X[i, 1])):
                status = STATUS_NOT_FINITE
        if status != STATUS_OK:
            break
        # pockets: a moving ball overlapping a pocket circle drops
        for i in range(n):
            if st[i] != MOVING:
                continue
            for p in range(pk_c.shape[0]):
                if math.hypot(X[i, 0] - pk_c[p, 0], X[i, 1] - pk_c[p, 1]) < pk_r[p]:
                    st[i] = POCKETED
                    pocket[i] = p
                    changed[i] = True
                    nev = _record(nev, record, ev_t, ev_k, ev_a, ev_b, t, EV_POCKET, i, p)
                    if stop == STOP_FIRST_POCKET or (stop == STOP_FIRST_CONTACT and i == cue):
                        done = True
                    break
        # sleep: an idle ball touching no other ball stops where it is
        for i in range(n):
            if st[i] != MOVING or sleep_next[i] > now:
                continue
            free = True
            for j in range(n):
                if j != i and st[j] != POCKETED and math.hypot(X[i, 0] - X[j, 0], X[i, 1] - X[j, 1]) < 2.0 * r:
                    free = False
                    break
            if not free:  # held awake by the contact; check again next step
                sleep_next[i] = now + 1
                continue
            if free:
                st[i] = ASLEEP
                A[i, 0], A[i, 1] = X[i, 0], X[i, 1]
                W[i, 0], W[i, 1], OM[i] = 0.0, 0.0, 0.0
                SV[i, 0], SV[i, 1], SO[i] = V[i, 0], V[i, 1], OMn[i]
                changed[i] = True
                nev = _record(nev, record, ev_t, ev_k, ev_a, ev_b, t, EV_STOP, i, -1)
        # ball-ball: ideal elastic exchange along the line of centres, from the velocities of this step
        for i in range(n):
            if st[i] == POCKETED:
                continue
            for j in range(i + 1, n):
                if st[j] == POCKETED or (st[i] == ASLEEP and st[j] == ASLEEP):
                    continue
                dx, dy = X[i, 0] - X[j, 0], X[i, 1] - X[j, 1]
                dist2 = dx * dx + dy * dy
                if dist2 >= 4.0 * r * r:
                    continue
                rvx, rvy = V[i, 0] - V[j, 0], V[i, 1] - V[j, 1]
                approach = rvx * dx + rvy * dy
                if approach >= 0.0:
                    continue
                f = approach / dist2
                NV[i, 0], NV[i, 1] = V[i, 0] - f * dx, V[i, 1] - f * dy
                NV[j, 0], NV[j, 1] = V[j, 0] + f * dx, V[j, 1] + f * dy
                if spin:  # pymunk's friction impulse spins the discs (their linear velocities are replaced)
                    dist = math.sqrt(dist2)
                    nx, ny = -dx / dist, -dy / dist
                    tx, ty = -ny, nx
                    slip = rvx * tx + rvy * ty + (OMn[i] + OMn[j]) * r
                    jn = 0.5 * (1.0 + prm[P_E_BALL]) * (rvx * nx + rvy * ny)
                    cap = prm[P_MU_BALL] * jn
                    jt = min(max(-slip / 6.0, -cap), cap)
                    NO[i] += 2.0 * jt / r
                    NO[j] += 2.0 * jt / r
                for b in (i, j):
                    changed[b] = True
                    touched[b] = True
                    if st[b] == ASLEEP:
                        st[b] = MOVING
                nev = _record(nev, record, ev_t, ev_k, ev_a, ev_b, t, EV_BALL, i, j)
                if first < 0 and (i == cue or j == cue):
                    first = j if i == cue else i
                    if stop == STOP_FIRST_CONTACT:
                        done = True
        # cushions: pymunk's impulse sets the speed, the direction is the mirror image of the incoming one
        for i in range(n):
            if st[i] != MOVING:
                continue
            for p in range(poly.shape[0]):
                d, cx, cy, e, vtx = _poly_closest(poly, p, X[i, 0], X[i, 1])
                if d >= r or d == 0.0:
                    continue
                nx, ny = (X[i, 0] - cx) / d, (X[i, 1] - cy) / d
                vx, vy = V[i, 0], V[i, 1]
                vn = vx * nx + vy * ny
                if vn >= 0.0:
                    continue
                tx, ty = -ny, nx
                vt = vx * tx + vy * ty
                if spin:
                    jn = (1.0 + prm[P_E_CUSHION]) * -vn
                    cap = prm[P_MU_CUSHION] * jn
                    jt = min(max(-(vt - OMn[i] * r) / 3.0, -cap), cap)
                    vt_after = vt + jt
                    NO[i] = OMn[i] - 2.0 * jt / r
                else:
                    vt_after = vt
                out_speed = math.hypot(prm[P_E_CUSHION] * vn, vt_after)
                in_speed = math.hypot(vx, vy)
                NV[i, 0] = (vx - 2.0 * vn * nx) / in_speed * out_speed
                NV[i, 1] = (vy - 2.0 * vn * ny) / in_speed * out_speed
                changed[i] = True
                if vtx >= 0:
                    kind, idx = vertex_kind[p, vtx], vertex_index[p, vtx]
                else:
                    kind, idx = edge_kind[p, e], edge_index[p, e]
                code = EV_CUSHION if kind == KIND_CUSHION else EV_JAW
                nev = _record(nev, record, ev_t, ev_k, ev_a, ev_b, t, code, i, idx)
        # commit the new motions and re-predict what they touch
        grow = math.exp(k * t)
        for i in range(n):
            if not changed[i] or st[i] != MOVING:
                continue
            W[i, 0], W[i, 1] = NV[i, 0] * grow, NV[i, 1] * grow
            OM[i] = NO[i] * grow
            A[i, 0], A[i, 1] = X[i, 0] - W[i, 0] * tn, X[i, 1] - W[i, 1] * tn
        for i in range(n):  # a prediction for this step that did not happen (a grazing contact within
            # rounding of the overlap distance) is made again from here
            if st[i] == MOVING and min(cush_next[i], pock_next[i], sleep_next[i]) <= now:
                changed[i] = True
            for j in range(i + 1, n):
                if pair_next[i, j] <= now:
                    changed[i] = True
        for i in range(n):
            if changed[i]:
                _refresh(i, now, st, A, W, OM, prm, poly, pk_c, pk_r, pair_next, cush_next, pock_next, sleep_next)
    # final centres; an early stop reports the step before the contact (nothing overlaps there yet)
    tn = _tau(now, prm)
    for i in range(n):
        if st[i] == POCKETED:
            continue
        if done:
            X[i, 0], X[i, 1] = XP[i, 0], XP[i, 1]
        elif st[i] == MOVING:
            X[i, 0] = A[i, 0] + W[i, 0] * tn
            X[i, 1] = A[i, 1] + W[i, 1] * tn
        else:
            X[i, 0], X[i, 1] = A[i, 0], A[i, 1]
    if stop == STOP_REST and status == STATUS_OK:
        nev = _settle(X, st, pocket, prm, size, pk_c, now * dt, nev, record, ev_t, ev_k, ev_a, ev_b)
    for i in range(n):
        out_pos[i, 0], out_pos[i, 1] = X[i, 0], X[i, 1]
        out_pocket[i] = pocket[i]
    return nev, status, first, now * dt


@njit(cache=True)
def run_shots(
    pos0, cue, shots, prm, poly, edge_kind, edge_index, vertex_kind, vertex_index, pk_c, pk_r, size, stop,
    max_events, record, ev_t, ev_k, ev_a, ev_b, out_pos, out_pocket, out_first, out_status, out_nev, out_time,
):  # fmt: skip
    """Simulate ``shots`` (m, 5: angle [rad], speed [m/s], ignored tip and elevation columns) from ``pos0``."""
    for s in range(shots.shape[0]):
        nev, status, first, duration = run_shot(
            pos0, cue, shots[s, 0], shots[s, 1], prm, poly, edge_kind, edge_index, vertex_kind, vertex_index,
            pk_c, pk_r, size, stop, max_events, record, ev_t, ev_k, ev_a, ev_b, out_pos[s], out_pocket[s],
        )  # fmt: skip
        out_first[s] = first
        out_status[s] = status
        out_nev[s] = nev
        out_time[s] = duration

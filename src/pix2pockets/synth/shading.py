"""Ray-caster building blocks (numba): cushion and rail solids, pocket holes, soft ball shadows, texture lookups
and ball albedo (cue, solids, stripes, numbers)."""

from __future__ import annotations

import math

from numba import njit

from pix2pockets.synth.scene_codes import (
    BALL_CUE,
    BALL_PLAIN,
    BALL_SOLID,
    G_CW,
    G_DC,
    G_KC,
    G_KS,
    G_L,
    G_LEGS,
    G_LEGW,
    G_PLATE,
    G_PLATE_SQ,
    G_SKIRT,
    G_SS,
    G_W,
    INF,
    S_BAND,
    S_CUE_DOTS,
    S_NUMR,
    SIGHT_OVAL,
    SIGHT_RHOMBUS,
    SIGHT_SQUARE,
)

SQUARE_HALF = 0.85
"""Half-side of a square sight, in sight sizes (``G_DR``): about the area of a round sight."""
OVAL_AXES = (1.5, 0.65)
"""Half-axes of an oval sight along and across its rail, in sight sizes (``G_DR``)."""


@njit(cache=True, inline="always")
def clamp(x, lo, hi):
    return lo if x < lo else (hi if x > hi else x)


@njit(cache=True, inline="always")
def _cushion_box(x, y, geo):
    """Whether (x, y) lies under a cushion top with jaw-cut ends (no rounding)."""
    L = geo[G_L]
    W = geo[G_W]
    cw = geo[G_CW]
    kc = geo[G_KC]
    ks = geo[G_KS]
    dc = geo[G_DC]
    ss = geo[G_SS]
    if -cw <= y < 0.0 or W < y <= W + cw:  # long rails
        if x < 0.0 or x > L:
            return False
        o = -y if y < 0.0 else y - W
        a0 = dc - kc * o
        a1 = L * 0.5 - ss + ks * o
        b0 = L * 0.5 + ss - ks * o
        b1 = L - dc + kc * o
        return (a0 <= x <= a1) or (b0 <= x <= b1)
    if -cw <= x < 0.0 or L < x <= L + cw:  # short rails
        if y < 0.0 or y > W:
            return False
        o = -x if x < 0.0 else x - L
        return dc - kc * o <= y <= W - dc + kc * o
    return False


@njit(cache=True)
def in_pocket_cut(x, y, holes, extra):
    """Whether (x, y) lies in the round cut of a rounded pocket: within ``holes[k, 3]`` [m] of its hole centre, or
    within the hole radius + ``extra`` [m] (the opening of the rim on the rail cap)."""
    for k in range(holes.shape[0]):
        rc = holes[k, 3]
        if rc > 0.0:
            rc = max(rc, holes[k, 2] + extra)
            dx = x - holes[k, 0]
            dy = y - holes[k, 1]
            if dx * dx + dy * dy < rc * rc:
                return True
    return False


@njit(cache=True)
def in_cushion(x, y, geo, holes):
    """Whether table point (x, y) lies under a cushion top (between nose line and cushion back); rounded pockets
    (``holes[k, 3] > 0``) cut the cushion ends along a circle of that radius [m] around the hole."""
    return _cushion_box(x, y, geo) and not in_pocket_cut(x, y, holes, 0.0)


@njit(cache=True)
def on_plate(x, y, holes, geo):
    """Whether rail-cap point (x, y) lies on a metal pocket plate (within ``G_PLATE`` of a hole centre)."""
    reach = geo[G_PLATE]
    if reach <= 0.0:
        return False
    square = geo[G_PLATE_SQ] > 0.5
    for k in range(holes.shape[0]):
        dx = abs(x - holes[k, 0])
        dy = abs(y - holes[k, 1])
        if square:
            if dx < reach and dy < reach:
                return True
        elif dx * dx + dy * dy < reach * reach:
            return True
    return False


@njit(cache=True)
def in_sight(ddx, ddy, dr, shape, long_rail):
    """Whether offset (ddx, ddy) [m] from a sight's centre lies inside it (size ``dr`` [m], ``SIGHT_*`` shape;
    rhombus and oval sights lie along the rail)."""
    along = abs(ddx) if long_rail else abs(ddy)
    across = abs(ddy) if long_rail else abs(ddx)
    if shape == SIGHT_RHOMBUS:
        return along / (1.6 * dr) + across / (0.8 * dr) < 1.0
    if shape == SIGHT_SQUARE:
        return along < SQUARE_HALF * dr and across < SQUARE_HALF * dr
    if shape == SIGHT_OVAL:
        a = along / (OVAL_AXES[0] * dr)
        b = across / (OVAL_AXES[1] * dr)
        return a * a + b * b < 1.0
    return ddx * ddx + ddy * ddy < dr * dr


@njit(cache=True)
def box_hit(ox, oy, oz, dx, dy, dz, x0, x1, y0, y1, z0, z1):
    """Entry distance and face of a ray into an axis-aligned box [m]: (t, face) with face 0/1/2 for an x/y/z
    face, or (-1, -1) when the ray misses it or starts inside."""
    tmin = -INF
    tmax = INF
    face = -1
    for a in range(3):
        o = ox if a == 0 else (oy if a == 1 else oz)
        d = dx if a == 0 else (dy if a == 1 else dz)
        lo = x0 if a == 0 else (y0 if a == 1 else z0)
        hi = x1 if a == 0 else (y1 if a == 1 else z1)
        if abs(d) < 1e-12:
            if o < lo or o > hi:
                return -1.0, -1
            continue
        t0 = (lo - o) / d
        t1 = (hi - o) / d
        if t0 > t1:
            t0, t1 = t1, t0
        if t0 > tmin:
            tmin = t0
            face = a
        if t1 < tmax:
            tmax = t1
        if tmin > tmax:
            return -1.0, -1
    if tmin <= 0.0:
        return -1.0, -1
    return tmin, face


@njit(cache=True)
def coin_box_dark(u, v):
    """Whether a point of a coin box's front, ``u`` across (-1..1) and ``v`` up (0..1), is an opening: the
    ball-return opening below, the coin slides above."""
    opening = 0.12 < v < 0.45 and abs(u) < 0.75
    slots = 0.6 < v < 0.88 and abs(u) < 0.8 and (u * 3.0 + 3.0) % 1.0 < 0.22
    return opening or slots


@njit(cache=True)
def body_solid(along, lo, hi, z, za, geo):
    """Whether the table body exists at this point of one of its faces (cabinet, or legs + skirt)."""
    legs = geo[G_LEGS]
    if legs < 0.5 or z > za - geo[G_SKIRT]:
        return True
    w = geo[G_LEGW]
    if along - lo < w or hi - along < w:
        return True
    mid = 0.5 * (lo + hi)
    return legs > 5.5 and abs(along - mid) < 0.5 * w and hi - lo > 2.0


@njit(cache=True)
def cap_step(oa, da, ob, db, oz, dz, plane, sg, lo, hi, h, hr):
    """Hit of a ray on the rail cap's inner step face, the vertical wall at coordinate ``a = plane`` facing
    ``sg`` (into the table) from the cushion top ``h`` up to the cap ``hr`` [m], spanning ``lo <= b <= hi``.

    ``a``/``b`` are the ray's coordinates across/along the rail (origin ``oa``, ``ob``; direction ``da``,
    ``db``). Returns (distance t, b at the hit), or (-1, 0) when the ray misses the face.
    """
    if sg * (oa - plane) > 0.0 and sg * da < 0.0:
        t = (plane - oa) / da
        z = oz + t * dz
        b = ob + t * db
        if h <= z <= hr and lo <= b <= hi:
            return t, b
    return -1.0, 0.0


@njit(cache=True)
def hole_of(x, y, holes, extra):
    """Index of the pocket hole whose circle (radius + ``extra``) contains (x, y), else -1."""
    for k in range(holes.shape[0]):
        dx = x - holes[k, 0]
        dy = y - holes[k, 1]
        rr = holes[k, 2] + extra
        if dx * dx + dy * dy < rr * rr:
            return k
    return -1


@njit(cache=True)
def hole_depth(ox, oy, oz, dx, dy, dz, t0, holes, k, zbottom):
    """Depth [m] below the cloth at which a ray entering hole ``k`` at ``t0`` meets the wall or bottom."""
    cx = holes[k, 0]
    cy = holes[k, 1]
    r = holes[k, 2]
    px = ox - cx
    py = oy - cy
    a = dx * dx + dy * dy
    b = 2.0 * (px * dx + py * dy)
    c = px * px + py * py - r * r
    t_exit = INF
    if a > 1e-12:
        disc = b * b - 4 * a * c
        if disc > 0:
            t_exit = (-b + math.sqrt(disc)) / (2 * a)
    z = oz + t_exit * dz
    if z < zbottom or t_exit == INF:
        return -zbottom
    return max(0.0, -z)


@njit(cache=True)
def ball_shadow(px, py, pz, lx, ly, lz, lsize, balls, skip):
    """Fraction of a spherical light (radius ``lsize``) seen from point p past all balls (centres ``balls`` (n, 3) on
    the cloth, so each centre's height is that ball's radius)."""
    vx = lx - px
    vy = ly - py
    vz = lz - pz
    D = math.sqrt(vx * vx + vy * vy + vz * vz)
    ux = vx / D
    uy = vy / D
    uz = vz / D
    f = 1.0
    lift = lz - pz
    for j in range(balls.shape[0]):
        if j == skip:
            continue
        r = balls[j, 2]
        # cheap cull: where the segment to the light crosses the ball centre's height, it must pass
        # within a few radii of the centre (plus the penumbra of a large light)
        tc = (balls[j, 2] - pz) / lift
        if tc > 0.0:
            qx = px + tc * vx - balls[j, 0]
            qy = py + tc * vy - balls[j, 1]
            lim = 2.0 * r + 2.0 * lsize * tc
            if qx * qx + qy * qy > lim * lim:
                continue
        wx = balls[j, 0] - px
        wy = balls[j, 1] - py
        wz = balls[j, 2] - pz
        tp = wx * ux + wy * uy + wz * uz
        if tp <= 1e-6 or tp >= D:
            continue
        cx = wx - tp * ux
        cy = wy - tp * uy
        cz = wz - tp * uz
        dc = math.sqrt(cx * cx + cy * cy + cz * cz)
        theta_o = r / tp
        theta_l = lsize / D + 1e-4  # angular radius of the light seen from p
        s = (dc / tp - theta_o) / theta_l
        if s < 1.0:
            vis = clamp(0.5 + 0.5 * s, 0.0, 1.0)
            f *= vis
    return f


@njit(cache=True)
def sample_tex2(tex, u, v):
    """Nearest sample of a tileable 2-D texture at texel coordinates (u, v)."""
    n0 = tex.shape[0]
    n1 = tex.shape[1]
    i = math.floor(u) % n0
    j = math.floor(v) % n1
    return tex[i, j]


@njit(cache=True)
def ball_albedo(q0, q1, q2, kind, number, col, shade, digits):
    """Albedo of a ball at unit direction (q0, q1, q2) in the ball's own frame."""
    white_r, white_g, white_b = 0.93, 0.92, 0.87
    cosn = shade[S_NUMR]
    sinn = math.sqrt(max(1e-6, 1.0 - cosn * cosn))
    if kind == BALL_CUE:
        # six red dots on the axes (measle-style TV cue ball)
        if shade[S_CUE_DOTS] > 0.5 and (abs(q0) > 0.985 or abs(q1) > 0.985 or abs(q2) > 0.985):
            return 0.75, 0.05, 0.05
        return col[0], col[1], col[2]
    if kind == BALL_PLAIN:
        return col[0], col[1], col[2]
    if kind == BALL_SOLID:
        base_r, base_g, base_b = col[0], col[1], col[2]
        pole = q2
        a = q0
        b = q1
    else:
        if abs(q2) < shade[S_BAND]:
            base_r, base_g, base_b = col[0], col[1], col[2]
        else:
            base_r, base_g, base_b = white_r, white_g, white_b
        pole = q0
        a = q1
        b = q2
    if abs(pole) > cosn:
        s = 1.0 if pole > 0 else -1.0
        n = digits.shape[1]
        u = (s * a / sinn * 0.5 + 0.5) * (n - 1)
        v = (-b / sinn * 0.5 + 0.5) * (n - 1)
        ink = 0.0
        if 0 <= u < n and 0 <= v < n:
            ink = digits[number, int(v), int(u)]
        k = 1.0 - 0.95 * ink
        return white_r * k, white_g * k, white_b * k
    return base_r, base_g, base_b

"""Per-pixel ray casting of a pool table scene (numba, one core).

One primary ray per pixel is intersected with the analytic scene: spheres (balls), the cloth plane with
pocket holes, the cushion tops and noses, the rail caps with inlaid diamonds, the outer rail faces, the
table body, the floor, four room walls and a ceiling. The hit is shaded right away (Lambert + Blinn-Phong
from point lights, soft ball shadows, contact/ambient occlusion, environment reflection on the balls).

Outputs per pixel: linear-ish RGB (float32, not clipped) and an object id (int16), see ``ID_*``. The ids
make the labels exact: a ball's or diamond's visible pixels are the pixels that carry its id.

Scene parameters travel as flat arrays (``geo``, ``shade``, ``mats``) indexed by the ``G_*``, ``S_*`` and
``M_*`` constants below, so the kernel has one fixed signature.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# ---- geometry vector indices (metres, table frame)
G_L, G_W, G_H, G_HR, G_CW, G_RW, G_ZA, G_BI, G_ZF, G_ZC = range(10)
G_RX0, G_RX1, G_RY0, G_RY1, G_BR, G_LINER, G_DR, G_KC, G_KS, G_DC, G_SS, G_ZHB = range(10, 22)
G_LEGS, G_LEGW, G_SKIRT = range(22, 25)  # legs: 0 closed cabinet, 4 or 6 legs; leg width, skirt depth [m]
G_RUGX, G_RUGY = range(25, 27)  # half-size of a rug under the table [m] (0: none)
N_GEO = 27
# ---- shading vector indices
S_AMB, S_CLOTH_TEX, S_CLOTH_SCALE, S_RAIL_TEX, S_RAIL_GLOSS, S_RAIL_SHIN, S_BALL_KS, S_BALL_SHIN = range(8)
S_FLOOR_SCALE, S_BOUNCE, S_DIA_SHAPE, S_CUE_DOTS, S_BAND, S_NUMR, S_REFL, S_ROOM = range(8, 16)
S_CLOTH_NAP, S_AO = range(16, 18)
N_SHADE = 18
# ---- material rows
M_CLOTH, M_RAIL, M_APRON, M_BODY, M_LINER, M_DIAMOND, M_CEIL, M_AMBCOL, M_WALLTINT, M_RUG = range(10)
N_MATS = 10

# ---- object ids in the id buffer
ID_NONE = 0
ID_CLOTH = 1
ID_CUSHION = 2
ID_NOSE = 3
ID_CAP = 4
ID_APRON = 5
ID_BODY = 6
ID_HOLE = 7
ID_LINER = 8
ID_FLOOR = 9
ID_WALL = 10
ID_CEIL = 11
ID_DIAMOND0 = 20  # diamonds 0-17 -> 20-37
ID_BALL0 = 40  # balls 0-15 -> 40-55

BALL_CUE, BALL_SOLID, BALL_STRIPE = 0, 1, 2
INF = 1e30
KU = 0.8  # cushion undercut: the face below the nose runs KU m back per m of depth (hidden from above ~51 deg)
KN = 1.0 / math.sqrt(1.0 + KU * KU)
AA_OFFSETS = np.array([[-0.375, -0.125], [0.125, -0.375], [0.375, 0.125], [-0.125, 0.375]])  # rotated grid [px]


@njit(cache=True, inline="always")
def _clamp(x, lo, hi):
    return lo if x < lo else (hi if x > hi else x)


@njit(cache=True)
def _in_cushion(x, y, geo):
    """Whether table point (x, y) lies under a cushion top (between nose line and cushion back)."""
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
def _body_solid(along, lo, hi, z, za, geo):
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
def _cap_step(oa, da, ob, db, oz, dz, plane, sg, lo, hi, h, hr):
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
def _hole_of(x, y, holes, extra):
    """Index of the pocket hole whose circle (radius + ``extra``) contains (x, y), else -1."""
    for k in range(holes.shape[0]):
        dx = x - holes[k, 0]
        dy = y - holes[k, 1]
        rr = holes[k, 2] + extra
        if dx * dx + dy * dy < rr * rr:
            return k
    return -1


@njit(cache=True)
def _hole_depth(ox, oy, oz, dx, dy, dz, t0, holes, k, zbottom):
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
def _ball_shadow(px, py, pz, lx, ly, lz, lsize, balls, r, skip):
    """Fraction of a spherical light (radius ``lsize``) seen from point p past all balls."""
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
            vis = _clamp(0.5 + 0.5 * s, 0.0, 1.0)
            f *= vis
    return f


@njit(cache=True)
def _sample_tex2(tex, u, v):
    """Nearest sample of a tileable 2-D texture at texel coordinates (u, v)."""
    n0 = tex.shape[0]
    n1 = tex.shape[1]
    i = math.floor(u) % n0
    j = math.floor(v) % n1
    return tex[i, j]


@njit(cache=True)
def _ball_albedo(q0, q1, q2, kind, number, col, shade, digits):
    """Albedo of a ball at unit direction (q0, q1, q2) in the ball's own frame."""
    white_r, white_g, white_b = 0.93, 0.92, 0.87
    cosn = shade[S_NUMR]
    sinn = math.sqrt(max(1e-6, 1.0 - cosn * cosn))
    if kind == BALL_CUE:
        # six red dots on the axes (measle-style TV cue ball)
        if shade[S_CUE_DOTS] > 0.5 and (abs(q0) > 0.985 or abs(q1) > 0.985 or abs(q2) > 0.985):
            return 0.75, 0.05, 0.05
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


def _pixel_py(
    fu,
    fv,
    count_sil,
    Kinv,
    Rt,
    cam,
    geo,
    shade,
    mats,
    holes,
    diamonds,
    balls,
    rots,
    bcols,
    bkinds,
    bnums,
    bboxes,
    lights,
    digits,
    noise,
    grain,
    floor_tex,
    wall_tex,
    sil_count,
):
    """Trace and shade the ray through image point (fu, fv) [px]: returns r, g, b, object id, distance."""
    L = geo[G_L]
    Wd = geo[G_W]
    h = geo[G_H]
    hr = geo[G_HR]
    cw = geo[G_CW]
    rw = geo[G_RW]
    za = geo[G_ZA]
    bi = geo[G_BI]
    zf = geo[G_ZF]
    zc = geo[G_ZC]
    rx0 = geo[G_RX0]
    rx1 = geo[G_RX1]
    ry0 = geo[G_RY0]
    ry1 = geo[G_RY1]
    br = geo[G_BR]
    liner = geo[G_LINER]
    dr = geo[G_DR]
    zhb = geo[G_ZHB]
    nb = balls.shape[0]
    nl = lights.shape[0]
    ox = cam[0]
    oy = cam[1]
    oz = cam[2]
    perim = 2.0 * ((rx1 - rx0) + (ry1 - ry0))
    cx_ = Kinv[0, 0] * fu + Kinv[0, 1] * fv + Kinv[0, 2]
    cy_ = Kinv[1, 0] * fu + Kinv[1, 1] * fv + Kinv[1, 2]
    cz_ = Kinv[2, 0] * fu + Kinv[2, 1] * fv + Kinv[2, 2]
    dx = Rt[0, 0] * cx_ + Rt[0, 1] * cy_ + Rt[0, 2] * cz_
    dy = Rt[1, 0] * cx_ + Rt[1, 1] * cy_ + Rt[1, 2] * cz_
    dz = Rt[2, 0] * cx_ + Rt[2, 1] * cy_ + Rt[2, 2] * cz_
    nrm = math.sqrt(dx * dx + dy * dy + dz * dz)
    dx /= nrm
    dy /= nrm
    dz /= nrm

    best = INF
    hit = ID_NONE
    nx = 0.0
    ny = 0.0
    nz = 1.0
    aux = -1  # ball / diamond / hole index

    # ---------------- balls
    for i in range(nb):
        if fu < bboxes[i, 0] or fu > bboxes[i, 2] + 1 or fv < bboxes[i, 1] or fv > bboxes[i, 3] + 1:
            continue
        px = ox - balls[i, 0]
        py = oy - balls[i, 1]
        pz = oz - balls[i, 2]
        bq = px * dx + py * dy + pz * dz
        cq = px * px + py * py + pz * pz - br * br
        disc = bq * bq - cq
        if disc < 0.0:
            continue
        t = -bq - math.sqrt(disc)
        if t <= 0.0:
            continue
        if count_sil:
            sil_count[i] += 1
        if t < best:
            best = t
            hit = ID_BALL0 + i
            aux = i

    # ---------------- horizontal surfaces seen from above
    if dz < 0.0:
        # rail cap (z = hr)
        t = (hr - oz) / dz
        if 0.0 < t < best:
            x = ox + t * dx
            y = oy + t * dy
            if -rw <= x <= L + rw and -rw <= y <= Wd + rw and not (-cw < x < L + cw and -cw < y < Wd + cw):
                k = _hole_of(x, y, holes, liner)
                if k >= 0:
                    if _hole_of(x, y, holes, 0.0) >= 0:
                        best = t
                        hit = ID_HOLE
                        aux = k
                    else:
                        best = t
                        hit = ID_LINER
                        nx, ny, nz = 0.0, 0.0, 1.0
                else:
                    best = t
                    hit = ID_CAP
                    nx, ny, nz = 0.0, 0.0, 1.0
                    for j in range(diamonds.shape[0]):
                        ddx = x - diamonds[j, 0]
                        ddy = y - diamonds[j, 1]
                        if shade[S_DIA_SHAPE] > 0.5 and shade[S_DIA_SHAPE] < 1.5:
                            # rhombus, long axis along the rail
                            along = abs(ddx) if j < 6 or 9 <= j < 15 else abs(ddy)
                            across = abs(ddy) if j < 6 or 9 <= j < 15 else abs(ddx)
                            inside = along / (1.6 * dr) + across / (0.8 * dr) < 1.0
                        else:
                            inside = ddx * ddx + ddy * ddy < dr * dr
                        if inside:
                            hit = ID_DIAMOND0 + j
                            aux = j
                            if shade[S_DIA_SHAPE] > 1.5:  # domed pearl
                                q = math.sqrt(ddx * ddx + ddy * ddy) / dr
                                nx = ddx / dr * 0.7
                                ny = ddy / dr * 0.7
                                nz = math.sqrt(max(0.05, 1.0 - q * q * 0.49))
                            break
        # cushion top (z = h)
        t = (h - oz) / dz
        if 0.0 < t < best:
            x = ox + t * dx
            y = oy + t * dy
            if _in_cushion(x, y, geo):
                best = t
                if _hole_of(x, y, holes, 0.0) >= 0:
                    hit = ID_HOLE
                    aux = _hole_of(x, y, holes, 0.0)
                else:
                    hit = ID_CUSHION
                    # the cushion top slopes down toward the nose: tilt the normal inward
                    if y < 0.0:
                        nx, ny, nz = 0.0, 0.25, 0.97
                    elif y > Wd:
                        nx, ny, nz = 0.0, -0.25, 0.97
                    elif x < 0.0:
                        nx, ny, nz = 0.25, 0.0, 0.97
                    else:
                        nx, ny, nz = -0.25, 0.0, 0.97
        # cloth (z = 0)
        t = -oz / dz
        if 0.0 < t < best:
            x = ox + t * dx
            y = oy + t * dy
            if -rw <= x <= L + rw and -rw <= y <= Wd + rw:
                best = t
                k = _hole_of(x, y, holes, 0.0)
                if k >= 0:
                    hit = ID_HOLE
                    aux = k
                elif -cw <= x <= L + cw and -cw <= y <= Wd + cw:
                    hit = ID_CLOTH
                    nx, ny, nz = 0.0, 0.0, 1.0
                else:  # the shadowed gap under a rail, seen through a pocket notch
                    hit = ID_NOSE
                    nx, ny, nz = 0.0, 0.0, 1.0
        # floor
        t = (zf - oz) / dz
        if 0.0 < t < best:
            best = t
            hit = ID_FLOOR
            nx, ny, nz = 0.0, 0.0, 1.0
    elif dz > 0.0:
        t = (zc - oz) / dz
        if 0.0 < t < best:
            best = t
            hit = ID_CEIL
            nx, ny, nz = 0.0, 0.0, -1.0

    # ---------------- vertical faces: cushion noses (inside), apron and body (outside), walls
    # x = const faces
    if dx != 0.0:
        # undercut cushion faces below the noses at x = 0 and x = L (seen from inside the table):
        # x = x_nose - s * ku * (h - z), s = +1 at the head rail, -1 at the foot rail
        for side in range(2):
            xp = 0.0 if side == 0 else L
            sg = 1.0 if side == 0 else -1.0
            den = dx - sg * KU * dz
            if sg * (ox - xp) > 0.0 and sg * dx - KU * dz < 0.0 and den != 0.0:
                t = (xp - sg * KU * (h - oz) - ox) / den
                if 0.0 < t < best:
                    z = oz + t * dz
                    y = oy + t * dy
                    if 0.0 <= z <= h and geo[G_DC] <= y <= Wd - geo[G_DC]:
                        best = t
                        hit = ID_NOSE
                        nx, ny, nz = sg * KN, 0.0, -KU * KN
            # inner step of the rail cap, from the cushion top (z = h) up to the cap (z = hr), seen from inside
            xs = -cw if side == 0 else L + cw
            t, y = _cap_step(ox, dx, oy, dy, oz, dz, xs, sg, -cw, Wd + cw, h, hr)
            if 0.0 < t < best and _hole_of(xs, y, holes, liner) < 0:
                best = t
                hit = ID_CAP
                nx, ny, nz = sg, 0.0, 0.0
            # apron / outer rail faces and body, seen from outside
            for layer in range(2):
                off = rw if layer == 0 else rw - bi
                xp2 = -off if side == 0 else L + off
                outside = ox < xp2 if side == 0 else ox > xp2
                toward = dx > 0.0 if side == 0 else dx < 0.0
                if (outside and toward) or (layer == 1 and geo[G_LEGS] > 0.5):
                    t = (xp2 - ox) / dx
                    if 0.0 < t < best:
                        z = oz + t * dz
                        y = oy + t * dy
                        lo = za if layer == 0 else zf
                        hi = hr if layer == 0 else za
                        if (
                            lo <= z <= hi
                            and -off <= y <= Wd + off
                            and (layer == 0 or _body_solid(y, -off, Wd + off, z, za, geo))
                        ):
                            best = t
                            hit = ID_APRON if layer == 0 else ID_BODY
                            nx, ny, nz = (-1.0 if side == 0 else 1.0), 0.0, 0.0
        # room walls
        xw = rx0 if dx < 0.0 else rx1
        t = (xw - ox) / dx
        if 0.0 < t < best:
            best = t
            hit = ID_WALL
            nx, ny, nz = (1.0 if dx < 0.0 else -1.0), 0.0, 0.0
    if dy != 0.0:
        for side in range(2):
            yp = 0.0 if side == 0 else Wd
            sg = 1.0 if side == 0 else -1.0
            den = dy - sg * KU * dz
            if sg * (oy - yp) > 0.0 and sg * dy - KU * dz < 0.0 and den != 0.0:
                t = (yp - sg * KU * (h - oz) - oy) / den
                if 0.0 < t < best:
                    z = oz + t * dz
                    x = ox + t * dx
                    dcn = geo[G_DC]
                    ssn = geo[G_SS]
                    if 0.0 <= z <= h and (dcn <= x <= L * 0.5 - ssn or L * 0.5 + ssn <= x <= L - dcn):
                        best = t
                        hit = ID_NOSE
                        nx, ny, nz = 0.0, sg * KN, -KU * KN
            ys = -cw if side == 0 else Wd + cw
            t, x = _cap_step(oy, dy, ox, dx, oz, dz, ys, sg, -cw, L + cw, h, hr)
            if 0.0 < t < best and _hole_of(x, ys, holes, liner) < 0:
                best = t
                hit = ID_CAP
                nx, ny, nz = 0.0, sg, 0.0
            for layer in range(2):
                off = rw if layer == 0 else rw - bi
                yp2 = -off if side == 0 else Wd + off
                outside = oy < yp2 if side == 0 else oy > yp2
                toward = dy > 0.0 if side == 0 else dy < 0.0
                if (outside and toward) or (layer == 1 and geo[G_LEGS] > 0.5):
                    t = (yp2 - oy) / dy
                    if 0.0 < t < best:
                        z = oz + t * dz
                        x = ox + t * dx
                        lo = za if layer == 0 else zf
                        hi = hr if layer == 0 else za
                        if (
                            lo <= z <= hi
                            and -off <= x <= L + off
                            and (layer == 0 or _body_solid(x, -off, L + off, z, za, geo))
                        ):
                            best = t
                            hit = ID_APRON if layer == 0 else ID_BODY
                            nx, ny, nz = 0.0, (-1.0 if side == 0 else 1.0), 0.0
        yw = ry0 if dy < 0.0 else ry1
        t = (yw - oy) / dy
        if 0.0 < t < best:
            best = t
            hit = ID_WALL
            nx, ny, nz = 0.0, (1.0 if dy < 0.0 else -1.0), 0.0

    if hit == ID_NONE:
        return 0.0, 0.0, 0.0, hit, best

    # ---------------- shading
    px = ox + best * dx
    py = oy + best * dy
    pz = oz + best * dz
    ar = 0.5
    ag = 0.5
    ab = 0.5
    ks = 0.0
    shin = 10.0
    receives_ball_shadow = False
    ao = 1.0
    self_ball = -1
    if hit >= ID_BALL0:
        i = aux
        self_ball = i
        nx = (px - balls[i, 0]) / br
        ny = (py - balls[i, 1]) / br
        nz = (pz - balls[i, 2]) / br
        q0 = rots[i, 0, 0] * nx + rots[i, 0, 1] * ny + rots[i, 0, 2] * nz
        q1 = rots[i, 1, 0] * nx + rots[i, 1, 1] * ny + rots[i, 1, 2] * nz
        q2 = rots[i, 2, 0] * nx + rots[i, 2, 1] * ny + rots[i, 2, 2] * nz
        ar, ag, ab = _ball_albedo(q0, q1, q2, bkinds[i], bnums[i], bcols[i], shade, digits)
        ks = shade[S_BALL_KS]
        shin = shade[S_BALL_SHIN]
        # the bottom of the ball sees less light; the cloth bounces its colour back up
        ao = 0.55 + 0.45 * nz
    elif hit in (ID_CLOTH, ID_CUSHION, ID_NOSE):
        sc = shade[S_CLOTH_SCALE]
        n1 = _sample_tex2(noise, px * sc, py * sc)
        n2 = _sample_tex2(noise, px * sc * 9.0 + 17.0, py * sc * 9.0 + 5.0)
        f = 1.0 + shade[S_CLOTH_TEX] * (0.8 * n1 + 0.2 * n2)
        ar = mats[M_CLOTH, 0] * f
        ag = mats[M_CLOTH, 1] * f
        ab = mats[M_CLOTH, 2] * f
        if hit == ID_NOSE:
            ar *= 0.8
            ag *= 0.8
            ab *= 0.8
        elif hit == ID_CUSHION:
            ar *= 0.92
            ag *= 0.92
            ab *= 0.92
        receives_ball_shadow = True
        ks = shade[S_CLOTH_NAP]
        shin = 4.0
        if hit == ID_CLOTH:
            # contact shadows / ambient occlusion from balls and the cushions
            for j in range(nb):
                ddx = px - balls[j, 0]
                ddy = py - balls[j, 1]
                d2 = (ddx * ddx + ddy * ddy) / (br * br)
                if d2 < 16.0:
                    ao *= 1.0 - shade[S_AO] * (1.0 / (1.0 + d2)) ** 1.5
            e = min(min(px, L - px), min(py, Wd - py))
            if e > 0.0:
                ao *= 1.0 - 0.35 * math.exp(-e / 0.025)
    elif hit in (ID_CAP, ID_APRON):
        along = px if (py < 0.0 or py > Wd) else py
        across = py if (py < 0.0 or py > Wd) else px
        if hit == ID_APRON:
            across = pz
        g = _sample_tex2(grain, across * 400.0, along * 60.0)
        f = 1.0 + shade[S_RAIL_TEX] * (g - 1.0)
        m = M_RAIL if hit == ID_CAP else M_APRON
        ar = mats[m, 0] * f
        ag = mats[m, 1] * f
        ab = mats[m, 2] * f
        ks = shade[S_RAIL_GLOSS]
        shin = shade[S_RAIL_SHIN]
        if hit == ID_CAP:
            receives_ball_shadow = True
    elif hit >= ID_DIAMOND0:
        ar = mats[M_DIAMOND, 0]
        ag = mats[M_DIAMOND, 1]
        ab = mats[M_DIAMOND, 2]
        ks = 0.5
        shin = 60.0
    elif hit == ID_LINER:
        ar = mats[M_LINER, 0]
        ag = mats[M_LINER, 1]
        ab = mats[M_LINER, 2]
        ks = 0.3
        shin = 30.0
    elif hit == ID_HOLE:
        hdepth = _hole_depth(ox, oy, oz, dx, dy, dz, best, holes, aux, zhb)
        f = 0.45 * math.exp(-hdepth / 0.025)
        ar = mats[M_LINER, 0] * f + 0.004
        ag = mats[M_LINER, 1] * f + 0.004
        ab = mats[M_LINER, 2] * f + 0.004
    elif hit == ID_BODY:
        ar = mats[M_BODY, 0]
        ag = mats[M_BODY, 1]
        ab = mats[M_BODY, 2]
        ao = 0.6
    elif hit == ID_FLOOR:
        fs = shade[S_FLOOR_SCALE]
        fi = math.floor(px * fs) % floor_tex.shape[0]
        fj = math.floor(py * fs) % floor_tex.shape[1]
        ar = floor_tex[fi, fj, 0] * (1.0 / 255.0)
        ag = floor_tex[fi, fj, 1] * (1.0 / 255.0)
        ab = floor_tex[fi, fj, 2] * (1.0 / 255.0)
        if abs(px - 0.5 * L) < geo[G_RUGX] and abs(py - 0.5 * Wd) < geo[G_RUGY]:
            rn = 1.0 + 0.25 * _sample_tex2(noise, px * 90.0, py * 90.0)
            border = min(geo[G_RUGX] - abs(px - 0.5 * L), geo[G_RUGY] - abs(py - 0.5 * Wd)) < 0.08
            rf = 0.5 if border else 1.0
            ar = mats[M_RUG, 0] * rn * rf + (0.3 if border else 0.0) * mats[M_RUG, 1]
            ag = mats[M_RUG, 1] * rn * rf
            ab = mats[M_RUG, 2] * rn * rf
        # shadow under the table
        ex = max(max(-rw - px, px - (L + rw)), 0.0)
        ey = max(max(-rw - py, py - (Wd + rw)), 0.0)
        e = math.sqrt(ex * ex + ey * ey)
        ao = 0.25 + 0.75 * min(1.0, e / 0.8)
        ks = 0.15
        shin = 20.0
    elif hit == ID_WALL:
        # unroll the walls so text reads left to right from inside the room
        if abs(ny) > 0.5:
            s = (rx1 - px) if ny > 0 else (rx1 - rx0) + (ry1 - ry0) + (px - rx0)
        else:
            s = (rx1 - rx0) + (ry1 - py) if nx < 0 else 2 * (rx1 - rx0) + (ry1 - ry0) + (py - ry0)
        hw = wall_tex.shape[0]
        ww = wall_tex.shape[1]
        tv = int(_clamp((zc - pz) / (zc - zf) * hw, 0.0, hw - 1.0))
        tu = int(s / perim * ww) % ww
        ar = wall_tex[tv, tu, 0] * (mats[M_WALLTINT, 0] / 255.0)
        ag = wall_tex[tv, tu, 1] * (mats[M_WALLTINT, 1] / 255.0)
        ab = wall_tex[tv, tu, 2] * (mats[M_WALLTINT, 2] / 255.0)
    elif hit == ID_CEIL:
        ar = mats[M_CEIL, 0]
        ag = mats[M_CEIL, 1]
        ab = mats[M_CEIL, 2]

    # lights
    amb = shade[S_AMB] * ao
    lr = amb * mats[M_AMBCOL, 0]
    lg = amb * mats[M_AMBCOL, 1]
    lb = amb * mats[M_AMBCOL, 2]
    sr = 0.0
    sg = 0.0
    sb = 0.0
    if hit in (ID_WALL, ID_CEIL, ID_FLOOR):
        lr += shade[S_ROOM] * mats[M_AMBCOL, 0] * ao
        lg += shade[S_ROOM] * mats[M_AMBCOL, 1] * ao
        lb += shade[S_ROOM] * mats[M_AMBCOL, 2] * ao
    for li in range(nl):
        lx = lights[li, 0] - px
        ly = lights[li, 1] - py
        lz = lights[li, 2] - pz
        d2 = lx * lx + ly * ly + lz * lz
        d = math.sqrt(d2)
        lx /= d
        ly /= d
        lz /= d
        ndl = nx * lx + ny * ly + nz * lz
        if ndl <= 0.0:
            continue
        hl = lights[li, 2]
        atten = lights[li, 3] * min(1.5, hl * hl / d2)
        vis = 1.0
        if receives_ball_shadow or hit >= ID_BALL0:
            vis = _ball_shadow(
                px, py, pz, lights[li, 0], lights[li, 1], lights[li, 2], lights[li, 7], balls, br, self_ball
            )
        e = atten * vis * (ndl if hit < ID_BALL0 else ndl * (0.8 + 0.2 * ao))
        lr += e * lights[li, 4]
        lg += e * lights[li, 5]
        lb += e * lights[li, 6]
        if ks > 0.0:
            hx = lx - dx
            hy = ly - dy
            hz = lz - dz
            hn = math.sqrt(hx * hx + hy * hy + hz * hz)
            ndh = (nx * hx + ny * hy + nz * hz) / hn
            if ndh > 0.0:
                sp = ks * ndh**shin * lights[li, 3] * vis
                sr += sp * lights[li, 4]
                sg += sp * lights[li, 5]
                sb += sp * lights[li, 6]
    cr = ar * lr + sr
    cg = ag * lg + sg
    cb = ab * lb + sb
    if hit >= ID_BALL0:
        # environment reflection: cloth below the horizon, dim room above, with Fresnel
        ddn = dx * nx + dy * ny + dz * nz
        rz = dz - 2.0 * ddn * nz
        fres = 0.04 + 0.96 * (1.0 + ddn) ** 5
        fres *= shade[S_REFL]
        if rz < 0.0:
            er = mats[M_CLOTH, 0] * shade[S_AMB] * 2.0
            eg = mats[M_CLOTH, 1] * shade[S_AMB] * 2.0
            eb = mats[M_CLOTH, 2] * shade[S_AMB] * 2.0
        else:
            er = eg = eb = shade[S_AMB] * 0.6
        cr = cr * (1.0 - fres) + er * fres
        cg = cg * (1.0 - fres) + eg * fres
        cb = cb * (1.0 - fres) + eb * fres
        # cloth bounce on the underside
        bounce = shade[S_BOUNCE] * max(0.0, -nz)
        cr += ar * mats[M_CLOTH, 0] * bounce
        cg += ag * mats[M_CLOTH, 1] * bounce
        cb += ab * mats[M_CLOTH, 2] * bounce
    return cr, cg, cb, hit, best


_pixel = njit(cache=True, inline="always")(_pixel_py)  # inlined into the main pass
_pixel_call = njit(cache=True)(_pixel_py)  # an ordinary call for the few anti-aliasing samples


@njit(cache=True)
def render_scene(
    Kinv,
    Rt,
    cam,
    width,
    height,
    geo,
    shade,
    mats,
    holes,
    diamonds,
    balls,
    rots,
    bcols,
    bkinds,
    bnums,
    bboxes,
    lights,
    digits,
    noise,
    grain,
    floor_tex,
    wall_tex,
    rgb,
    ids,
    depth,
    sil_count,
    mask,
):
    """Trace and shade the pixels where ``mask`` (H, W) is set. Writes ``rgb`` (H, W, 3), ``ids`` (H, W),
    ``depth`` (H, W): distance along the ray to the hit [m], and ``sil_count`` (n balls,): the number of
    traced pixels whose ray meets each ball's sphere at all (occluded or not). Pixels outside ``mask`` keep
    what the arrays hold.

    Pixels on object boundaries (an id differs from a 4-neighbour) get four more rays on a rotated grid
    and the mean colour (adaptive anti-aliasing); ids, depth and counts come from the centre ray.
    """
    for v in range(height):
        for u in range(width):
            if not mask[v, u]:
                continue
            r, g, b, hit, t = _pixel(
                u + 0.5,
                v + 0.5,
                True,
                Kinv,
                Rt,
                cam,
                geo,
                shade,
                mats,
                holes,
                diamonds,
                balls,
                rots,
                bcols,
                bkinds,
                bnums,
                bboxes,
                lights,
                digits,
                noise,
                grain,
                floor_tex,
                wall_tex,
                sil_count,
            )
            rgb[v, u, 0] = r
            rgb[v, u, 1] = g
            rgb[v, u, 2] = b
            ids[v, u] = hit
            depth[v, u] = t
    for v in range(height):
        for u in range(width):
            if not mask[v, u]:
                continue
            k = ids[v, u]
            edge = (
                (u > 0 and ids[v, u - 1] != k)
                or (u + 1 < width and ids[v, u + 1] != k)
                or (v > 0 and ids[v - 1, u] != k)
                or (v + 1 < height and ids[v + 1, u] != k)
            )
            if not edge:
                continue
            sr = rgb[v, u, 0]
            sg = rgb[v, u, 1]
            sb = rgb[v, u, 2]
            for j in range(4):
                r, g, b, hit, t = _pixel_call(
                    u + 0.5 + AA_OFFSETS[j, 0],
                    v + 0.5 + AA_OFFSETS[j, 1],
                    False,
                    Kinv,
                    Rt,
                    cam,
                    geo,
                    shade,
                    mats,
                    holes,
                    diamonds,
                    balls,
                    rots,
                    bcols,
                    bkinds,
                    bnums,
                    bboxes,
                    lights,
                    digits,
                    noise,
                    grain,
                    floor_tex,
                    wall_tex,
                    sil_count,
                )
                sr += r
                sg += g
                sb += b
            rgb[v, u, 0] = sr / 5.0
            rgb[v, u, 1] = sg / 5.0
            rgb[v, u, 2] = sb / 5.0


@njit(cache=True)
def object_stats(ids, occluded, n_ids):
    """Per id: visible pixel count, count hidden by 2-D occluders, and the bbox of the visible pixels.

    Returns:
        counts (n_ids,) visible pixels, hidden (n_ids,) pixels covered by ``occluded``, boxes (n_ids, 4)
        as x0, y0, x1, y1 (inclusive pixel indices; -1 when no pixel is visible).
    """
    counts = np.zeros(n_ids, np.int64)
    hidden = np.zeros(n_ids, np.int64)
    boxes = np.full((n_ids, 4), -1, np.int64)
    H, W = ids.shape
    for v in range(H):
        for u in range(W):
            k = ids[v, u]
            if k <= 0 or k >= n_ids:
                continue
            if occluded[v, u]:
                hidden[k] += 1
                continue
            if counts[k] == 0:
                boxes[k, 0] = u
                boxes[k, 1] = v
                boxes[k, 2] = u
                boxes[k, 3] = v
            else:
                if u < boxes[k, 0]:
                    boxes[k, 0] = u
                if u > boxes[k, 2]:
                    boxes[k, 2] = u
                if v < boxes[k, 1]:
                    boxes[k, 1] = v
                if v > boxes[k, 3]:
                    boxes[k, 3] = v
            counts[k] += 1
    return counts, hidden, boxes

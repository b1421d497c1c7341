"""Per-pixel ray casting of a pool table scene (numba, one core).

One primary ray per pixel is intersected with the analytic scene: spheres (balls), the cloth plane with
pocket holes, the cushion tops and noses, the rail caps with inlaid diamonds, the outer rail faces, the
table body, the floor, four room walls and a ceiling. The hit is shaded right away (Lambert + Blinn-Phong
from point lights, soft ball shadows, contact/ambient occlusion, environment reflection on the balls).

Outputs per pixel: linear-ish RGB (float32, not clipped) and an object id (int16), see ``ID_*``. The ids
make the labels exact: a ball's or diamond's visible pixels are the pixels that carry its id.

Scene parameters travel as flat arrays (``geo``, ``shade``, ``mats``) indexed by the ``G_*``, ``S_*`` and
``M_*`` constants of :mod:`pix2pockets.synth.scene_codes`, so the kernel has one fixed signature; the building
blocks are in :mod:`pix2pockets.synth.shading`.
"""

from __future__ import annotations

import math

from pix2pockets.synth import scene_codes as codes
from pix2pockets.synth.shading import (
    ball_albedo,
    ball_shadow,
    body_solid,
    box_hit,
    cap_step,
    clamp,
    coin_box_dark,
    hole_depth,
    hole_of,
    in_cushion,
    in_pocket_cut,
    in_sight,
    on_plate,
    sample_tex2,
)

PLATE_DROP = 0.05
"""How far metal pocket plates reach down the outer rail face from the cap [m]."""


def shade_ray(
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
    L = geo[codes.G_L]
    Wd = geo[codes.G_W]
    h = geo[codes.G_H]
    hr = geo[codes.G_HR]
    cw = geo[codes.G_CW]
    rw = geo[codes.G_RW]
    za = geo[codes.G_ZA]
    bi = geo[codes.G_BI]
    zf = geo[codes.G_ZF]
    zc = geo[codes.G_ZC]
    rx0 = geo[codes.G_RX0]
    rx1 = geo[codes.G_RX1]
    ry0 = geo[codes.G_RY0]
    ry1 = geo[codes.G_RY1]
    liner = geo[codes.G_LINER]
    dr = geo[codes.G_DR]
    zhb = geo[codes.G_ZHB]
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

    best = codes.INF
    hit = codes.ID_NONE
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
        rb = balls[i, 2]  # a ball rests on the cloth: its centre's height is its radius
        cq = px * px + py * py + pz * pz - rb * rb
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
            hit = codes.ID_BALL0 + i
            aux = i

    # ---------------- horizontal surfaces seen from above
    if dz < 0.0:
        # rail cap (z = hr)
        t = (hr - oz) / dz
        if 0.0 < t < best:
            x = ox + t * dx
            y = oy + t * dy
            if -rw <= x <= L + rw and -rw <= y <= Wd + rw and not (-cw < x < L + cw and -cw < y < Wd + cw):
                k = hole_of(x, y, holes, liner)
                if k >= 0:
                    if hole_of(x, y, holes, 0.0) >= 0:
                        best = t
                        hit = codes.ID_HOLE
                        aux = k
                    else:
                        best = t
                        hit = codes.ID_LINER
                        nx, ny, nz = 0.0, 0.0, 1.0
                else:
                    best = t
                    hit = codes.ID_CAP
                    nx, ny, nz = 0.0, 0.0, 1.0
                    if on_plate(x, y, holes, geo):
                        hit = codes.ID_PLATE
                    else:
                        shape = int(shade[codes.S_DIA_SHAPE] + 0.5)
                        for j in range(diamonds.shape[0]):
                            ddx = x - diamonds[j, 0]
                            ddy = y - diamonds[j, 1]
                            if in_sight(ddx, ddy, dr, shape, j < 6 or 9 <= j < 15):
                                hit = codes.ID_DIAMOND0 + j
                                aux = j
                                if shape == codes.SIGHT_PEARL:  # domed
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
            if in_cushion(x, y, geo, holes):
                best = t
                if hole_of(x, y, holes, 0.0) >= 0:
                    hit = codes.ID_HOLE
                    aux = hole_of(x, y, holes, 0.0)
                else:
                    hit = codes.ID_CUSHION
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
                k = hole_of(x, y, holes, 0.0)
                if k >= 0:
                    hit = codes.ID_HOLE
                    aux = k
                elif (x < 0.0 or x > L or y < 0.0 or y > Wd) and in_pocket_cut(x, y, holes, liner):
                    hit = codes.ID_LINER  # the rim of a rounded pocket, around its drop hole
                    nx, ny, nz = 0.0, 0.0, 1.0
                elif -cw <= x <= L + cw and -cw <= y <= Wd + cw:
                    hit = codes.ID_CLOTH
                    nx, ny, nz = 0.0, 0.0, 1.0
                else:  # the shadowed gap under a rail, seen through a pocket notch
                    hit = codes.ID_NOSE
                    nx, ny, nz = 0.0, 0.0, 1.0
        # floor
        t = (zf - oz) / dz
        if 0.0 < t < best:
            best = t
            hit = codes.ID_FLOOR
            nx, ny, nz = 0.0, 0.0, 1.0
    elif dz > 0.0:
        t = (zc - oz) / dz
        if 0.0 < t < best:
            best = t
            hit = codes.ID_CEIL
            nx, ny, nz = 0.0, 0.0, -1.0

    # ---------------- vertical faces: cushion noses (inside), apron and body (outside), walls
    # x = const faces
    if dx != 0.0:
        # undercut cushion faces below the noses at x = 0 and x = L (seen from inside the table):
        # x = x_nose - s * ku * (h - z), s = +1 at the head rail, -1 at the foot rail
        for side in range(2):
            xp = 0.0 if side == 0 else L
            sg = 1.0 if side == 0 else -1.0
            den = dx - sg * codes.KU * dz
            if sg * (ox - xp) > 0.0 and sg * dx - codes.KU * dz < 0.0 and den != 0.0:
                t = (xp - sg * codes.KU * (h - oz) - ox) / den
                if 0.0 < t < best:
                    z = oz + t * dz
                    y = oy + t * dy
                    if 0.0 <= z <= h and geo[codes.G_DC] <= y <= Wd - geo[codes.G_DC]:
                        best = t
                        hit = codes.ID_NOSE
                        nx, ny, nz = sg * codes.KN, 0.0, -codes.KU * codes.KN
            # inner step of the rail cap, from the cushion top (z = h) up to the cap (z = hr), seen from inside
            xs = -cw if side == 0 else L + cw
            t, y = cap_step(ox, dx, oy, dy, oz, dz, xs, sg, -cw, Wd + cw, h, hr)
            if 0.0 < t < best and hole_of(xs, y, holes, liner) < 0:
                best = t
                hit = codes.ID_CAP
                nx, ny, nz = sg, 0.0, 0.0
            # apron / outer rail faces and body, seen from outside
            for layer in range(2):
                off = rw if layer == 0 else rw - bi
                xp2 = -off if side == 0 else L + off
                outside = ox < xp2 if side == 0 else ox > xp2
                toward = dx > 0.0 if side == 0 else dx < 0.0
                if (outside and toward) or (layer == 1 and geo[codes.G_LEGS] > 0.5):
                    t = (xp2 - ox) / dx
                    if 0.0 < t < best:
                        z = oz + t * dz
                        y = oy + t * dy
                        lo = za if layer == 0 else zf
                        hi = hr if layer == 0 else za
                        if (
                            lo <= z <= hi
                            and -off <= y <= Wd + off
                            and (layer == 0 or body_solid(y, -off, Wd + off, z, za, geo))
                        ):
                            best = t
                            hit = codes.ID_APRON if layer == 0 else codes.ID_BODY
                            if layer == 0 and z > hr - PLATE_DROP and on_plate(xp2, y, holes, geo):
                                hit = codes.ID_PLATE
                            nx, ny, nz = (-1.0 if side == 0 else 1.0), 0.0, 0.0
        # room walls
        xw = rx0 if dx < 0.0 else rx1
        t = (xw - ox) / dx
        if 0.0 < t < best:
            best = t
            hit = codes.ID_WALL
            nx, ny, nz = (1.0 if dx < 0.0 else -1.0), 0.0, 0.0
    if dy != 0.0:
        for side in range(2):
            yp = 0.0 if side == 0 else Wd
            sg = 1.0 if side == 0 else -1.0
            den = dy - sg * codes.KU * dz
            if sg * (oy - yp) > 0.0 and sg * dy - codes.KU * dz < 0.0 and den != 0.0:
                t = (yp - sg * codes.KU * (h - oz) - oy) / den
                if 0.0 < t < best:
                    z = oz + t * dz
                    x = ox + t * dx
                    dcn = geo[codes.G_DC]
                    ssn = geo[codes.G_SS]
                    if 0.0 <= z <= h and (dcn <= x <= L * 0.5 - ssn or L * 0.5 + ssn <= x <= L - dcn):
                        best = t
                        hit = codes.ID_NOSE
                        nx, ny, nz = 0.0, sg * codes.KN, -codes.KU * codes.KN
            ys = -cw if side == 0 else Wd + cw
            t, x = cap_step(oy, dy, ox, dx, oz, dz, ys, sg, -cw, L + cw, h, hr)
            if 0.0 < t < best and hole_of(x, ys, holes, liner) < 0:
                best = t
                hit = codes.ID_CAP
                nx, ny, nz = 0.0, sg, 0.0
            for layer in range(2):
                off = rw if layer == 0 else rw - bi
                yp2 = -off if side == 0 else Wd + off
                outside = oy < yp2 if side == 0 else oy > yp2
                toward = dy > 0.0 if side == 0 else dy < 0.0
                if (outside and toward) or (layer == 1 and geo[codes.G_LEGS] > 0.5):
                    t = (yp2 - oy) / dy
                    if 0.0 < t < best:
                        z = oz + t * dz
                        x = ox + t * dx
                        lo = za if layer == 0 else zf
                        hi = hr if layer == 0 else za
                        if (
                            lo <= z <= hi
                            and -off <= x <= L + off
                            and (layer == 0 or body_solid(x, -off, L + off, z, za, geo))
                        ):
                            best = t
                            hit = codes.ID_APRON if layer == 0 else codes.ID_BODY
                            if layer == 0 and z > hr - PLATE_DROP and on_plate(x, yp2, holes, geo):
                                hit = codes.ID_PLATE
                            nx, ny, nz = 0.0, (-1.0 if side == 0 else 1.0), 0.0
        yw = ry0 if dy < 0.0 else ry1
        t = (yw - oy) / dy
        if 0.0 < t < best:
            best = t
            hit = codes.ID_WALL
            nx, ny, nz = 0.0, (1.0 if dy < 0.0 else -1.0), 0.0

    # ---------------- coin box / ball return on the foot end of a coin-op table
    box_u = 0.0
    box_v = 0.0
    if geo[codes.G_BOXW] > 0.0:
        bx0 = L + rw - bi - 0.01
        bx1 = L + rw + geo[codes.G_BOXD]
        by0 = 0.5 * Wd - geo[codes.G_BOXW]
        by1 = 0.5 * Wd + geo[codes.G_BOXW]
        t, face = box_hit(ox, oy, oz, dx, dy, dz, bx0, bx1, by0, by1, geo[codes.G_BOXZ0], geo[codes.G_BOXZ1])
        if 0.0 < t < best:
            best = t
            hit = codes.ID_BOX
            nx, ny, nz = 0.0, 0.0, 0.0
            if face == 0:
                nx = 1.0 if dx < 0.0 else -1.0
                # position on the front face: across (-1..1) and up (0..1)
                box_u = (oy + t * dy - 0.5 * Wd) / geo[codes.G_BOXW]
                box_v = (oz + t * dz - geo[codes.G_BOXZ0]) / (geo[codes.G_BOXZ1] - geo[codes.G_BOXZ0])
            elif face == 1:
                ny = 1.0 if dy < 0.0 else -1.0
            else:
                nz = 1.0 if dz < 0.0 else -1.0

    if hit == codes.ID_NONE:
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
    if hit >= codes.ID_BALL0:
        i = aux
        self_ball = i
        rb = balls[i, 2]
        nx = (px - balls[i, 0]) / rb
        ny = (py - balls[i, 1]) / rb
        nz = (pz - balls[i, 2]) / rb
        q0 = rots[i, 0, 0] * nx + rots[i, 0, 1] * ny + rots[i, 0, 2] * nz
        q1 = rots[i, 1, 0] * nx + rots[i, 1, 1] * ny + rots[i, 1, 2] * nz
        q2 = rots[i, 2, 0] * nx + rots[i, 2, 1] * ny + rots[i, 2, 2] * nz
        ar, ag, ab = ball_albedo(q0, q1, q2, bkinds[i], bnums[i], bcols[i], shade, digits)
        ks = shade[codes.S_BALL_KS]
        shin = shade[codes.S_BALL_SHIN]
        # the bottom of the ball sees less light; the cloth bounces its colour back up
        ao = 0.55 + 0.45 * nz
    elif hit in (codes.ID_CLOTH, codes.ID_CUSHION, codes.ID_NOSE):
        sc = shade[codes.S_CLOTH_SCALE]
        n1 = sample_tex2(noise, px * sc, py * sc)
        n2 = sample_tex2(noise, px * sc * 9.0 + 17.0, py * sc * 9.0 + 5.0)
        f = 1.0 + shade[codes.S_CLOTH_TEX] * (0.8 * n1 + 0.2 * n2)
        ar = mats[codes.M_CLOTH, 0] * f
        ag = mats[codes.M_CLOTH, 1] * f
        ab = mats[codes.M_CLOTH, 2] * f
        if hit == codes.ID_NOSE:
            ar *= 0.8
            ag *= 0.8
            ab *= 0.8
        elif hit == codes.ID_CUSHION:
            ar *= 0.92
            ag *= 0.92
            ab *= 0.92
        receives_ball_shadow = True
        ks = shade[codes.S_CLOTH_NAP]
        shin = 4.0
        if hit == codes.ID_CLOTH:
            # contact shadows / ambient occlusion from balls and the cushions
            for j in range(nb):
                ddx = px - balls[j, 0]
                ddy = py - balls[j, 1]
                d2 = (ddx * ddx + ddy * ddy) / (balls[j, 2] * balls[j, 2])
                if d2 < 16.0:
                    ao *= 1.0 - shade[codes.S_AO] * (1.0 / (1.0 + d2)) ** 1.5
            e = min(min(px, L - px), min(py, Wd - py))
            if e > 0.0:
                ao *= 1.0 - 0.35 * math.exp(-e / 0.025)
    elif hit in (codes.ID_CAP, codes.ID_APRON):
        along = px if (py < 0.0 or py > Wd) else py
        across = py if (py < 0.0 or py > Wd) else px
        if hit == codes.ID_APRON:
            across = pz
        g = sample_tex2(grain, across * 400.0, along * 60.0)
        f = 1.0 + shade[codes.S_RAIL_TEX] * (g - 1.0)
        m = codes.M_RAIL if hit == codes.ID_CAP else codes.M_APRON
        ar = mats[m, 0] * f
        ag = mats[m, 1] * f
        ab = mats[m, 2] * f
        ks = shade[codes.S_RAIL_GLOSS]
        shin = shade[codes.S_RAIL_SHIN]
        if hit == codes.ID_CAP:
            receives_ball_shadow = True
    elif hit >= codes.ID_DIAMOND0:
        ar = mats[codes.M_DIAMOND, 0]
        ag = mats[codes.M_DIAMOND, 1]
        ab = mats[codes.M_DIAMOND, 2]
        ks = 0.5
        shin = 60.0
    elif hit == codes.ID_PLATE:
        ar = mats[codes.M_PLATE, 0]
        ag = mats[codes.M_PLATE, 1]
        ab = mats[codes.M_PLATE, 2]
        ks = 0.9
        shin = shade[codes.S_METAL_SHIN]
    elif hit == codes.ID_BOX:
        ar = mats[codes.M_PLATE, 0]
        ag = mats[codes.M_PLATE, 1]
        ab = mats[codes.M_PLATE, 2]
        ks = 0.6
        shin = shade[codes.S_METAL_SHIN]
        if (nx > 0.5 or nx < -0.5) and coin_box_dark(box_u, box_v):
            ar = 0.02
            ag = 0.02
            ab = 0.02
            ks = 0.0
    elif hit == codes.ID_LINER:
        ar = mats[codes.M_LINER, 0]
        ag = mats[codes.M_LINER, 1]
        ab = mats[codes.M_LINER, 2]
        ks = 0.3
        shin = 30.0
    elif hit == codes.ID_HOLE:
        hdepth = hole_depth(ox, oy, oz, dx, dy, dz, best, holes, aux, zhb)
        f = 0.45 * math.exp(-hdepth / 0.025)
        ar = mats[codes.M_LINER, 0] * f + 0.004
        ag = mats[codes.M_LINER, 1] * f + 0.004
        ab = mats[codes.M_LINER, 2] * f + 0.004
    elif hit == codes.ID_BODY:
        ar = mats[codes.M_BODY, 0]
        ag = mats[codes.M_BODY, 1]
        ab = mats[codes.M_BODY, 2]
        ao = 0.6
    elif hit == codes.ID_FLOOR:
        fs = shade[codes.S_FLOOR_SCALE]
        fi = math.floor(px * fs) % floor_tex.shape[0]
        fj = math.floor(py * fs) % floor_tex.shape[1]
        ar = floor_tex[fi, fj, 0] * (1.0 / 255.0)
        ag = floor_tex[fi, fj, 1] * (1.0 / 255.0)
        ab = floor_tex[fi, fj, 2] * (1.0 / 255.0)
        if abs(px - 0.5 * L) < geo[codes.G_RUGX] and abs(py - 0.5 * Wd) < geo[codes.G_RUGY]:
            rn = 1.0 + 0.25 * sample_tex2(noise, px * 90.0, py * 90.0)
            border = min(geo[codes.G_RUGX] - abs(px - 0.5 * L), geo[codes.G_RUGY] - abs(py - 0.5 * Wd)) < 0.08
            rf = 0.5 if border else 1.0
            ar = mats[codes.M_RUG, 0] * rn * rf + (0.3 if border else 0.0) * mats[codes.M_RUG, 1]
            ag = mats[codes.M_RUG, 1] * rn * rf
            ab = mats[codes.M_RUG, 2] * rn * rf
        # shadow under the table
        ex = max(max(-rw - px, px - (L + rw)), 0.0)
        ey = max(max(-rw - py, py - (Wd + rw)), 0.0)
        e = math.sqrt(ex * ex + ey * ey)
        ao = 0.25 + 0.75 * min(1.0, e / 0.8)
        ks = 0.15
        shin = 20.0
    elif hit == codes.ID_WALL:
        # unroll the walls so text reads left to right from inside the room
        if abs(ny) > 0.5:
            s = (rx1 - px) if ny > 0 else (rx1 - rx0) + (ry1 - ry0) + (px - rx0)
        else:
            s = (rx1 - rx0) + (ry1 - py) if nx < 0 else 2 * (rx1 - rx0) + (ry1 - ry0) + (py - ry0)
        hw = wall_tex.shape[0]
        ww = wall_tex.shape[1]
        tv = int(clamp((zc - pz) / (zc - zf) * hw, 0.0, hw - 1.0))
        tu = int(s / perim * ww) % ww
        ar = wall_tex[tv, tu, 0] * (mats[codes.M_WALLTINT, 0] / 255.0)
        ag = wall_tex[tv, tu, 1] * (mats[codes.M_WALLTINT, 1] / 255.0)
        ab = wall_tex[tv, tu, 2] * (mats[codes.M_WALLTINT, 2] / 255.0)
    elif hit == codes.ID_CEIL:
        ar = mats[codes.M_CEIL, 0]
        ag = mats[codes.M_CEIL, 1]
        ab = mats[codes.M_CEIL, 2]

    # lights
    amb = shade[codes.S_AMB] * ao
    lr = amb * mats[codes.M_AMBCOL, 0]
    lg = amb * mats[codes.M_AMBCOL, 1]
    lb = amb * mats[codes.M_AMBCOL, 2]
    sr = 0.0
    sg = 0.0
    sb = 0.0
    if hit in (codes.ID_WALL, codes.ID_CEIL, codes.ID_FLOOR):
        lr += shade[codes.S_ROOM] * mats[codes.M_AMBCOL, 0] * ao
        lg += shade[codes.S_ROOM] * mats[codes.M_AMBCOL, 1] * ao
        lb += shade[codes.S_ROOM] * mats[codes.M_AMBCOL, 2] * ao
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
        if receives_ball_shadow or hit >= codes.ID_BALL0:
            vis = ball_shadow(px, py, pz, lights[li, 0], lights[li, 1], lights[li, 2], lights[li, 7], balls, self_ball)
        e = atten * vis * (ndl if hit < codes.ID_BALL0 else ndl * (0.8 + 0.2 * ao))
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
    if hit >= codes.ID_BALL0:
        # environment reflection: cloth below the horizon, dim room above, with Fresnel
        ddn = dx * nx + dy * ny + dz * nz
        rz = dz - 2.0 * ddn * nz
        fres = 0.04 + 0.96 * (1.0 + ddn) ** 5
        fres *= shade[codes.S_REFL]
        if rz < 0.0:
            er = mats[codes.M_CLOTH, 0] * shade[codes.S_AMB] * 2.0
            eg = mats[codes.M_CLOTH, 1] * shade[codes.S_AMB] * 2.0
            eb = mats[codes.M_CLOTH, 2] * shade[codes.S_AMB] * 2.0
        else:
            er = eg = eb = shade[codes.S_AMB] * 0.6
        cr = cr * (1.0 - fres) + er * fres
        cg = cg * (1.0 - fres) + eg * fres
        cb = cb * (1.0 - fres) + eb * fres
        # cloth bounce on the underside
        bounce = shade[codes.S_BOUNCE] * max(0.0, -nz)
        cr += ar * mats[codes.M_CLOTH, 0] * bounce
        cg += ag * mats[codes.M_CLOTH, 1] * bounce
        cb += ab * mats[codes.M_CLOTH, 2] * bounce
    return cr, cg, cb, hit, best

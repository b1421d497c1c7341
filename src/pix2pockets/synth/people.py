"""People and cue sticks as 3-D capsule figures, z-buffered into the rendered image.

A figure is a list of capsules (segment + radius at each end + colour) in the table frame. Capsules are
projected with the scene camera and rasterised against the ray caster's depth buffer, so a player
standing behind the table is hidden by it and a cue stick behind a ball is hidden by the ball. The
pixels a figure covers are returned as an occlusion mask for the labels.

Figures: a player leaning over the table to shoot (bridge hand on the cloth, cue along the line of aim),
people standing around the table, and a cue stick held or lying on the table.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from pix2pockets.geometry.camera import PinholeCamera

SKIN_TONES = ((0.87, 0.67, 0.53), (0.72, 0.5, 0.36), (0.45, 0.3, 0.2), (0.95, 0.8, 0.68), (0.6, 0.4, 0.28))

Capsule = tuple[np.ndarray, np.ndarray, float, float, np.ndarray]


@njit(cache=True)
def _raster_capsules(img, mask, depth, caps):
    """Draw projected capsules (m, 12): u0, v0, u1, v1, r0, r1 [px], d0, d1 [m], r, g, b, gloss."""
    H, W = depth.shape
    for c in range(caps.shape[0]):
        u0, v0, u1, v1 = caps[c, 0], caps[c, 1], caps[c, 2], caps[c, 3]
        r0, r1, d0, d1 = caps[c, 4], caps[c, 5], caps[c, 6], caps[c, 7]
        rmax = max(r0, r1)
        x_lo = max(0, int(min(u0, u1) - rmax - 1))
        x_hi = min(W - 1, int(max(u0, u1) + rmax + 1))
        y_lo = max(0, int(min(v0, v1) - rmax - 1))
        y_hi = min(H - 1, int(max(v0, v1) + rmax + 1))
        ex = u1 - u0
        ey = v1 - v0
        ll = ex * ex + ey * ey
        for v in range(y_lo, y_hi + 1):
            for u in range(x_lo, x_hi + 1):
                px = u + 0.5 - u0
                py = v + 0.5 - v0
                s = 0.0
                if ll > 1e-9:
                    s = (px * ex + py * ey) / ll
                    s = min(1.0, max(0.0, s))
                qx = px - s * ex
                qy = py - s * ey
                d = math.sqrt(qx * qx + qy * qy)
                r = r0 + s * (r1 - r0)
                if r <= 0.3 or d >= r:
                    continue
                z = d0 + s * (d1 - d0)
                if z >= depth[v, u]:
                    continue
                k = d / r
                # cylinder shading: light from the top of the image, a little from the left
                nz = math.sqrt(max(0.0, 1.0 - k * k))
                nxs = qx / r
                nys = qy / r
                lam = max(0.0, 0.55 * nz - 0.6 * nys - 0.25 * nxs)
                b = 0.35 + 0.75 * lam
                spec = caps[c, 11] * max(0.0, nz - 0.8) * 4.0
                img[v, u, 0] = min(1.0, caps[c, 8] * b + spec)
                img[v, u, 1] = min(1.0, caps[c, 9] * b + spec)
                img[v, u, 2] = min(1.0, caps[c, 10] * b + spec)
                depth[v, u] = z
                mask[v, u] = True


def draw_figure(
    img: np.ndarray,
    mask: np.ndarray,
    depth: np.ndarray,
    cam: PinholeCamera,
    capsules: list[Capsule],
    gloss: float = 0.0,
) -> None:
    """Project ``capsules`` with ``cam`` and z-buffer them into ``img`` (in place), marking ``mask``."""
    near = 0.05
    rows = []
    for p0, p1, r0, r1, colour in capsules:
        c0, c1 = cam.world_to_camera(p0), cam.world_to_camera(p1)
        if c0[2] < near and c1[2] < near:
            continue
        if c0[2] < near or c1[2] < near:  # clip the segment at the near plane
            s = (near - c0[2]) / (c1[2] - c0[2])
            cut = c0 + s * (c1 - c0)
            rc_ = r0 + s * (r1 - r0)
            if c0[2] < near:
                c0, r0 = cut, rc_
            else:
                c1, r1 = cut, rc_
        uv0 = cam.K @ c0
        uv1 = cam.K @ c1
        f = cam.focal_px
        row = [uv0[0] / uv0[2], uv0[1] / uv0[2], uv1[0] / uv1[2], uv1[1] / uv1[2], f * r0 / c0[2], f * r1 / c1[2]]
        if max(abs(x) for x in row[:4]) > 1e5:
            continue
        rows.append([*row, float(np.linalg.norm(c0)), float(np.linalg.norm(c1)), *colour, gloss])
    if rows:
        _raster_capsules(img, mask, depth, np.array(rows, dtype=np.float64))


def _unit(v: np.ndarray) -> np.ndarray:
    return v / (np.linalg.norm(v) + 1e-12)


def _clothes(rng: np.random.Generator) -> dict[str, np.ndarray]:
    skin = np.array(SKIN_TONES[int(rng.integers(len(SKIN_TONES)))]) * rng.uniform(0.9, 1.05)
    formal = rng.random() < 0.4  # pro players: black waistcoat, white or coloured shirt
    shirt = np.array([0.9, 0.9, 0.88]) if formal and rng.random() < 0.6 else rng.uniform(0.03, 0.85, 3) ** 1.3
    torso = np.array([0.04, 0.04, 0.05]) if formal else shirt
    trousers = rng.uniform(0.02, 0.25, 3) if rng.random() < 0.8 else rng.uniform(0.2, 0.6, 3) * [0.6, 0.7, 1.0]
    hair = rng.uniform(0.02, 0.3, 3) if rng.random() < 0.85 else np.array([0.75, 0.65, 0.45])
    return {"skin": skin, "sleeve": shirt, "torso": torso, "legs": trousers, "hair": hair}


def _body(
    rng: np.random.Generator,
    hip: np.ndarray,
    shoulder_mid: np.ndarray,
    head: np.ndarray,
    side: np.ndarray,
    feet: tuple[np.ndarray, np.ndarray],
    hands: tuple[np.ndarray, np.ndarray],
    scale: float,
    cl: dict[str, np.ndarray],
) -> list[Capsule]:
    """Capsules of a person from key points (all [m], table frame)."""
    caps: list[Capsule] = []
    sh = [shoulder_mid + side * 0.19 * scale, shoulder_mid - side * 0.19 * scale]
    hp = [hip + side * 0.1 * scale, hip - side * 0.1 * scale]
    # torso: a fat capsule plus shoulders
    caps.append((hip, shoulder_mid, 0.17 * scale, 0.15 * scale, cl["torso"]))
    caps.append((sh[0], sh[1], 0.07 * scale, 0.07 * scale, cl["torso"]))
    neck = shoulder_mid + _unit(head - shoulder_mid) * 0.1 * scale
    caps.append((shoulder_mid, neck, 0.055 * scale, 0.05 * scale, cl["skin"]))
    caps.append((head, head, 0.105 * scale, 0.105 * scale, cl["skin"]))
    up = _unit(head - shoulder_mid)
    if rng.random() < 0.9:  # hair on the back/top of the head
        caps.append((head + up * 0.03 * scale, head + up * 0.03 * scale, 0.1 * scale, 0.1 * scale, cl["hair"]))
    for i in range(2):
        knee = (hp[i] + feet[i]) / 2 + rng.normal(0, 0.04, 3) * [1, 1, 0]
        caps.append((hp[i], knee, 0.085 * scale, 0.065 * scale, cl["legs"]))
        caps.append((knee, feet[i], 0.06 * scale, 0.05 * scale, cl["legs"]))
        caps.append((feet[i], feet[i] + np.array([0.0, 0.0, 0.0]), 0.055 * scale, 0.05 * scale, cl["legs"] * 0.4))
        hand = hands[i]
        reach = np.linalg.norm(hand - sh[i])
        mid = (sh[i] + hand) / 2
        # bend the elbow outward/downward when the hand is close to the shoulder
        bend = max(0.0, 0.55 * scale - reach) * 0.8
        elbow = mid + (side if i == 0 else -side) * bend * 0.6 - np.array([0, 0, bend * 0.6])
        caps.append((sh[i], elbow, 0.055 * scale, 0.048 * scale, cl["sleeve"]))
        fore = cl["skin"] if rng.random() < 0.4 else cl["sleeve"]
        caps.append((elbow, hand, 0.045 * scale, 0.035 * scale, fore))
        caps.append((hand, hand, 0.045 * scale, 0.045 * scale, cl["skin"]))
    return caps


def standing_person(
    rng: np.random.Generator, spec_size: np.ndarray, rail: float, floor_z: float, near: float = 2.5
) -> list[Capsule]:
    """A person standing around the table, 0.1-``near`` m from the rail, facing it roughly."""
    L, W = spec_size
    ang = rng.uniform(-math.pi, math.pi)
    reach = rng.uniform(0.15, near)
    pos = np.array([L / 2, W / 2]) + (np.array([L / 2, W / 2]) + rail + reach) * np.array(
        [math.cos(ang), math.sin(ang)]
    )
    pos = np.clip(pos, [-rail - near, -rail - near], [L + rail + near, W + rail + near])
    face = _unit(np.array([L / 2, W / 2]) - pos + rng.normal(0, 0.6, 2))
    fwd = np.array([face[0], face[1], 0.0])
    side = np.array([-face[1], face[0], 0.0])
    scale = rng.uniform(0.9, 1.08)
    height = 1.75 * scale
    base = np.array([pos[0], pos[1], floor_z])
    hip = base + np.array([0, 0, 0.52 * height])
    shoulder = base + np.array([0, 0, 0.81 * height]) + fwd * rng.normal(0.0, 0.03)
    head = base + np.array([0, 0, 0.93 * height]) + fwd * 0.02
    feet = (base + side * 0.12 + fwd * rng.normal(0, 0.1), base - side * 0.12 + fwd * rng.normal(0, 0.1))
    hands = []
    for sgn in (1, -1):
        u = rng.random()
        sh = shoulder + side * sgn * 0.19 * scale
        if u < 0.5:  # hanging
            hands.append(sh + np.array([0, 0, -0.58 * scale]) + fwd * rng.uniform(0, 0.1) + side * sgn * 0.05)
        elif u < 0.8:  # holding a cue upright / hand on hip / chalking
            hands.append(sh + fwd * rng.uniform(0.2, 0.4) + np.array([0, 0, rng.uniform(-0.35, 0.05)]))
        else:  # pointing at the table
            hands.append(sh + fwd * 0.55 * scale + np.array([0, 0, rng.uniform(-0.3, 0.0)]))
    return _body(rng, hip, shoulder, head, side, feet, (hands[0], hands[1]), scale, _clothes(rng))


def cue_capsules(
    rng: np.random.Generator, tip: np.ndarray, aim: np.ndarray, rise: float, length: float = 1.47
) -> list[Capsule]:
    """A cue stick from ``tip`` back along ``-aim`` (unit, horizontal), butt raised by ``rise`` [m]."""
    back = np.array([-aim[0], -aim[1], 0.0]) * length + np.array([0, 0, rise])
    wood = np.array([0.8, 0.62, 0.4]) * rng.uniform(0.75, 1.1)
    butt_col = rng.uniform(0.02, 0.4, 3) if rng.random() < 0.8 else wood * 0.5
    wrap = rng.uniform(0.0, 0.15, 3)

    def at(s: float) -> np.ndarray:
        return tip + back * s

    def rad(s: float) -> float:
        return 0.0065 + (0.0145 - 0.0065) * s

    parts = [
        (0.0, 0.008, np.array([0.15, 0.3, 0.65])),  # chalked tip
        (0.008, 0.025, np.array([0.95, 0.95, 0.92])),  # ferrule
        (0.025, 0.5, wood),
        (0.5, 0.62, butt_col),
        (0.62, 0.85, wrap),
        (0.85, 1.0, butt_col),
    ]
    return [(at(a), at(b), rad(a), rad(b), col) for a, b, col in parts]


def shooting_player(
    rng: np.random.Generator,
    ball_xy: np.ndarray,
    spec_size: np.ndarray,
    rail: float,
    floor_z: float,
    ball_radius: float,
) -> tuple[list[Capsule], list[Capsule]]:
    """A player down on a shot at the ball at ``ball_xy`` from the nearest rail: (body capsules, cue capsules)."""
    L, W = spec_size
    x, y = ball_xy
    dists = np.array([y, L - x, W - y, x])  # to the bottom, foot, top, head rails
    k = int(np.argmin(dists + rng.uniform(0, 0.3, 4)))
    normals = [np.array([0.0, 1.0]), np.array([-1.0, 0.0]), np.array([0.0, -1.0]), np.array([1.0, 0.0])]
    a = normals[k]  # aim direction: away from the rail the player stands at
    rot = rng.normal(0, 0.45)
    c, s = math.cos(rot), math.sin(rot)
    aim = np.array([c * a[0] - s * a[1], s * a[0] + c * a[1]])
    aim3 = np.array([aim[0], aim[1], 0.0])
    side = np.array([-aim[1], aim[0], 0.0])
    ball = np.array([x, y, ball_radius])
    tip = ball - aim3 * rng.uniform(0.02, 0.12)
    bridge_d = rng.uniform(0.15, 0.3)
    bridge = np.array([tip[0], tip[1], 0.025]) - aim3 * bridge_d
    rise = rng.uniform(0.1, 0.3)
    cue = cue_capsules(rng, tip, aim, rise)
    # where the player stands: behind the rail, on the line of aim
    dist_to_rail = float(dists[k]) + rail
    hip_back = max(dist_to_rail + 0.25, 0.75)
    hip = ball - aim3 * hip_back
    hip[2] = floor_z + 0.95
    head = bridge - aim3 * rng.uniform(0.25, 0.45) + np.array([0, 0, rng.uniform(0.22, 0.4)])
    head += side * rng.normal(0, 0.03)
    shoulder = head - aim3 * 0.18 + np.array([0, 0, -0.12])
    feet = (
        np.array([hip[0], hip[1], floor_z]) - aim3 * 0.25 + side * 0.2,
        np.array([hip[0], hip[1], floor_z]) - aim3 * 0.45 - side * 0.15,
    )
    grip = tip - aim3 * rng.uniform(1.05, 1.2) + np.array([0, 0, rise * 0.75])
    hands = (bridge + side * 0.02, grip) if rng.random() < 0.8 else (grip, bridge)
    body = _body(rng, hip, shoulder, head, side, feet, hands, rng.uniform(0.92, 1.05), _clothes(rng))
    return body, cue

"""Props around the table as capsule figures: hanging lamp shades, bar stools, a triangle rack, and glasses,
bottles and phones on the rails.

They add the clutter real photos have (and ball-like distractors such as glasses seen from above); they
are z-buffered like people (see :mod:`pix2pockets.synth.people`).
"""

from __future__ import annotations

import math

import numpy as np

from pix2pockets.synth.people import Capsule

SHADE_COLOURS = ((0.05, 0.25, 0.1), (0.03, 0.03, 0.03), (0.5, 0.06, 0.05), (0.7, 0.55, 0.2), (0.6, 0.6, 0.62))


def lamp_shades(rng: np.random.Generator, lights: np.ndarray, ceiling_z: float) -> list[Capsule]:
    """A shade over each light (tube or dome), its bright underside and the cord to the ceiling."""
    caps: list[Capsule] = []
    colour = np.array(SHADE_COLOURS[int(rng.integers(len(SHADE_COLOURS)))]) * rng.uniform(0.8, 1.2)
    tube = rng.random() < 0.5
    for x, y, z, *_ in lights:
        centre = np.array([x, y, z + 0.06])
        if tube:
            half = rng.uniform(0.12, 0.3)
            a, b = centre - np.array([half, 0, 0]), centre + np.array([half, 0, 0])
            r = rng.uniform(0.07, 0.12)
        else:
            a, b = centre, centre + np.array([0, 0, 0.05])
            r = rng.uniform(0.12, 0.22)
        caps.append((a, b, r, r, colour))
        glow = np.array([1.0, 0.97, 0.9])
        caps.append((a - np.array([0, 0, r * 0.55]), b - np.array([0, 0, r * 0.55]), r * 0.6, r * 0.6, glow))
        top = max(ceiling_z, z + 0.3)
        caps.append((centre + np.array([0, 0, r]), np.array([x, y, top]), 0.006, 0.006, np.array([0.05, 0.05, 0.05])))
    return caps


def bar_stool(rng: np.random.Generator, xy: np.ndarray, floor_z: float) -> list[Capsule]:
    """A bar stool or chair standing on the floor at ``xy``."""
    seat_h = rng.uniform(0.45, 0.78)
    r = rng.uniform(0.15, 0.22)
    wood = rng.random() < 0.5
    leg_col = np.array([0.35, 0.2, 0.1]) * rng.uniform(0.6, 1.3) if wood else rng.uniform(0.05, 0.6, 3)
    seat_col = leg_col * 1.2 if rng.random() < 0.5 else rng.uniform(0.02, 0.7, 3)
    seat = np.array([xy[0], xy[1], floor_z + seat_h])
    caps: list[Capsule] = [(seat, seat + np.array([0, 0, 0.04]), r, r, seat_col)]
    a0 = rng.uniform(0, 2 * math.pi)
    for k in range(4):
        a = a0 + k * math.pi / 2
        foot = np.array([xy[0] + 1.2 * r * math.cos(a), xy[1] + 1.2 * r * math.sin(a), floor_z])
        top = seat + np.array([0.7 * r * math.cos(a), 0.7 * r * math.sin(a), 0.0])
        caps.append((foot, top, 0.02, 0.02, leg_col))
    if rng.random() < 0.4:  # a backrest
        a = a0 + math.pi / 4
        b0 = seat + np.array([r * math.cos(a), r * math.sin(a), 0.0])
        caps.append((b0, b0 + np.array([0, 0, 0.4]), 0.03, 0.03, leg_col))
    return caps


def triangle_rack(rng: np.random.Generator, xy: np.ndarray, z: float, side: float) -> list[Capsule]:
    """A triangle rack (three bars) lying flat at ``xy``, height ``z`` [m]."""
    a = rng.uniform(0, 2 * math.pi)
    col = rng.uniform(0.02, 0.5, 3) if rng.random() < 0.6 else np.array([0.45, 0.28, 0.12])
    pts = []
    for k in range(3):
        t = a + k * 2 * math.pi / 3
        pts.append(np.array([xy[0] + side / math.sqrt(3) * math.cos(t), xy[1] + side / math.sqrt(3) * math.sin(t), z]))
    return [(pts[k], pts[(k + 1) % 3], 0.012, 0.012, col) for k in range(3)]


def glass(rng: np.random.Generator, xyz: np.ndarray) -> list[Capsule]:
    """A pint glass or bottle standing at ``xyz``."""
    beer = rng.random() < 0.6
    col = np.array([0.75, 0.45, 0.1]) if beer else rng.uniform(0.05, 0.5, 3)
    r = rng.uniform(0.03, 0.045)
    h = rng.uniform(0.1, 0.16)
    caps: list[Capsule] = [(xyz + np.array([0, 0, r]), xyz + np.array([0, 0, h]), r, r * 1.1, col)]
    if beer:
        caps.append(
            (
                xyz + np.array([0, 0, h]),
                xyz + np.array([0, 0, h + 0.015]),
                r * 1.1,
                r * 1.1,
                np.array([0.95, 0.93, 0.85]),
            )
        )
    return caps


def bottle(rng: np.random.Generator, xyz: np.ndarray) -> list[Capsule]:
    """A beer or soft-drink bottle standing at ``xyz``: body, shoulder and neck."""
    col = np.array([0.2, 0.35, 0.1]) if rng.random() < 0.4 else np.array([0.35, 0.18, 0.05]) * rng.uniform(0.6, 1.3)
    r = rng.uniform(0.028, 0.034)
    h = rng.uniform(0.13, 0.17)
    neck = xyz + np.array([0, 0, h + 0.045])
    return [
        (xyz + np.array([0, 0, r]), xyz + np.array([0, 0, h]), r, r, col),
        (xyz + np.array([0, 0, h]), neck, r * 0.9, 0.012, col),
        (neck, neck + np.array([0, 0, 0.035]), 0.012, 0.012, col),
    ]


def phone(rng: np.random.Generator, xyz: np.ndarray) -> list[Capsule]:
    """A phone lying flat at ``xyz`` (a slab of thin capsules side by side), dark glass or a coloured case."""
    a = rng.uniform(0, 2 * math.pi)
    along = np.array([math.cos(a), math.sin(a), 0.0]) * rng.uniform(0.07, 0.08)
    across = np.array([-math.sin(a), math.cos(a), 0.0])
    col = np.array([0.03, 0.03, 0.04]) if rng.random() < 0.6 else rng.uniform(0.05, 0.8, 3)
    r = 0.0045
    centre = xyz + np.array([0, 0, r])
    return [(centre + across * o - along, centre + across * o + along, r, r, col) for o in np.linspace(-0.03, 0.03, 5)]


RAIL_CLUTTER = {"glass": glass, "bottle": bottle, "phone": phone}
"""Things people put down on the rails, by name."""

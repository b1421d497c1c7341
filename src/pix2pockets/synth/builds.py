"""Table builds as people own them: pool-hall and tournament tables, pub / coin-op tables and home tables.

A build sets what a table looks like around the same playing surface (the :class:`TableSpec` stays the preset, so
pockets, corners and sights keep their table coordinates): the sights (none, or one of several shapes), the
pocket cut (jaw-cut or small rounded pockets with visible drop holes), metal corner caps and side-pocket plates,
the cabinet or legs, a coin box with a ball-return opening on the foot end, and the mix of cloths and rails.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pix2pockets.geometry.table import TableSpec
from pix2pockets.synth import scene_codes as sc
from pix2pockets.synth.palette import CLOTH_WEIGHTS, RAIL_WEIGHTS, weighted_choice

BUILD_WEIGHTS: dict[str, dict[str, float]] = {
    "9ft": {"hall": 0.8, "home": 0.12, "pub": 0.08},
    "8ft": {"hall": 0.35, "home": 0.45, "pub": 0.2},
    "7ft": {"hall": 0.1, "home": 0.25, "pub": 0.65},
    "6ft": {"hall": 0.0, "home": 0.6, "pub": 0.4},
    "uk7": {"hall": 0.05, "home": 0.2, "pub": 0.75},
    "uk6": {"hall": 0.0, "home": 0.5, "pub": 0.5},
}
"""Build probabilities by table size: 9-ft tables stand in halls and arenas, 7-ft bar boxes and UK tables in pubs."""

NO_SIGHTS: dict[str, float] = {"hall": 0.05, "home": 0.45, "pub": 0.65}
"""Share of tables of each build with plain rails (no sights)."""

SIGHT_SHAPES: dict[str, dict[str, float]] = {
    "hall": {"round": 0.45, "rhombus": 0.25, "pearl": 0.15, "square": 0.05, "dot": 0.05, "oval": 0.05},
    "home": {"round": 0.3, "rhombus": 0.15, "pearl": 0.1, "square": 0.15, "dot": 0.2, "oval": 0.1},
    "pub": {"round": 0.25, "dot": 0.5, "square": 0.15, "oval": 0.1},
}
"""Sight shapes of the tables that have sights, by build."""

SIGHT_CODES = {
    "round": sc.SIGHT_ROUND,
    "dot": sc.SIGHT_ROUND,
    "rhombus": sc.SIGHT_RHOMBUS,
    "pearl": sc.SIGHT_PEARL,
    "square": sc.SIGHT_SQUARE,
    "oval": sc.SIGHT_OVAL,
}
SIGHT_SIZES = {"dot": (0.003, 0.0045)}
"""Sight size ``G_DR`` ranges [m] where they differ from the default (0.0055-0.0085)."""

CLOTH_WEIGHTS_BY_BUILD: dict[str, dict[str, float]] = {
    "hall": CLOTH_WEIGHTS,
    "pub": {
        "tournament_blue": 2.0, "electric_blue": 1.0, "green": 3.0, "english_green": 3.0, "teal": 0.5, "red": 2.0,
        "burgundy": 1.5, "grey": 0.6, "purple": 0.5, "black": 0.7, "tan": 0.2,
    },
    "home": {
        "tournament_blue": 2.0, "electric_blue": 1.0, "green": 2.5, "english_green": 1.0, "teal": 0.7, "red": 2.0,
        "burgundy": 1.5, "grey": 1.5, "purple": 1.2, "black": 1.5, "tan": 0.8,
    },
}  # fmt: skip
"""Cloth colour weights by build (names of ``palette.CLOTH_COLOURS``)."""

RAIL_WEIGHTS_BY_BUILD: dict[str, dict[str, float]] = {
    "hall": RAIL_WEIGHTS,
    "pub": {"dark_wood": 2.0, "mid_wood": 1.5, "light_wood": 1.0, "black": 2.0, "grey": 0.5, "white": 2.0,
            "silver": 0.3},
    "home": {"dark_wood": 3.0, "mid_wood": 3.0, "light_wood": 2.0, "black": 1.5, "grey": 0.7, "white": 1.0,
             "silver": 0.3},
}  # fmt: skip
"""Rail material weights by build (names of ``palette.RAIL_MATERIALS``; white and black are laminates)."""

LIGHTING_BY_BUILD: dict[str, dict[str, float]] = {
    "hall": {"broadcast": 0.5, "pub_lamps": 0.35, "warm_pub": 0.15},
    "pub": {"pub_lamps": 0.55, "warm_pub": 0.35, "home": 0.1},
    "home": {"home": 0.6, "pub_lamps": 0.3, "warm_pub": 0.1},
}
"""Lighting kinds by build (``scene.LIGHTING_KINDS`` names)."""

PLATE_COLOURS = ((0.72, 0.72, 0.74), (0.8, 0.66, 0.35), (0.45, 0.45, 0.47), (0.06, 0.06, 0.06))
"""Pocket plates and coin boxes: chrome, brass, brushed steel, black plastic."""
PLATES: dict[str, float] = {"hall": 0.0, "pub": 0.8, "home": 0.2}
"""Share of tables of each build with metal corner caps and side-pocket plates."""
ROUNDED_POCKETS: dict[str, float] = {"hall": 0.0, "pub": 1.0, "home": 0.3}
"""Share of tables of each build with small rounded pockets (round cut, drop hole in view)."""
COIN_BOX = 0.85
"""Share of pub tables with a coin box and ball-return opening on the foot end."""


@dataclass(frozen=True, slots=True)
class Build:
    """The drawn build of one table (names for the label file; numbers go into the scene arrays).

    Attributes:
        name: hall, pub or home.
        sights: sight shape name, or ``"none"`` (plain rails).
        rounded: small rounded pockets.
        plates: ``"none"``, ``"round"`` or ``"square"`` metal pocket plates.
        coin_box: a coin box / ball-return front on the foot end.
    """

    name: str
    sights: str
    rounded: bool
    plates: str
    coin_box: bool

    @property
    def has_sights(self) -> bool:
        return self.sights != "none"


def sample_build(rng: np.random.Generator, spec: TableSpec) -> Build:
    """Draw a build for a table of ``spec``'s size (unknown sizes use the 8-ft mix)."""
    name = weighted_choice(rng, {k: v for k, v in BUILD_WEIGHTS.get(spec.name, BUILD_WEIGHTS["8ft"]).items() if v})
    sights = "none" if rng.random() < NO_SIGHTS[name] else weighted_choice(rng, SIGHT_SHAPES[name])
    rounded = bool(rng.random() < ROUNDED_POCKETS[name])
    plates = "none"
    if rng.random() < PLATES[name]:
        plates = "square" if rng.random() < 0.5 else "round"
    coin_box = name == "pub" and bool(rng.random() < COIN_BOX)
    return Build(name, sights, rounded, plates, coin_box)


def pocket_holes(rng: np.random.Generator, spec: TableSpec, rounded: bool) -> np.ndarray:
    """Pocket holes (6, 4) in ``spec.pockets`` order: centre x, y [m], hole radius [m], and the radius of the round
    cut in the cushion ends [m] (0: jaw-cut pockets).

    Jaw-cut pockets sit behind the mouth; rounded pockets cut the cushion ends along a circle through both jaw points
    (so the jaw points, and the spec's mouth, stay where the spec puts them) around a drop hole that reaches about to
    the mouth line; behind the mouth line the cut shows the pocket's rim (the liner) around the hole.
    """
    L, W = spec.length, spec.width
    holes = np.zeros((6, 4))
    for k, pocket in enumerate(spec.pockets):
        if pocket.kind.value == "corner":
            corner = np.round(pocket.jaws.mean(axis=0) / spec.size) * spec.size
            out = np.sign(corner - spec.size / 2) / math.sqrt(2)
            if rounded:
                holes[k, :2] = corner + out * rng.uniform(0.0, 0.015)
            else:
                holes[k, :2] = corner + out * rng.uniform(0.035, 0.05)
                holes[k, 2] = rng.uniform(0.058, 0.068)
        else:
            out = -1.0 if pocket.aim[1] < W / 2 else 1.0
            if rounded:
                holes[k, :2] = [L / 2, pocket.aim[1] + out * rng.uniform(0.03, 0.045)]
            else:
                holes[k, :2] = [L / 2, pocket.aim[1] + out * rng.uniform(0.045, 0.058)]
                holes[k, 2] = rng.uniform(0.055, 0.064)
        if rounded:  # the drop hole reaches about to the mouth line
            cut = float(np.linalg.norm(pocket.jaws[0] - holes[k, :2]))
            to_mouth = float(np.linalg.norm(pocket.aim - holes[k, :2]))
            holes[k, 3] = cut
            holes[k, 2] = np.clip(to_mouth + rng.uniform(-0.01, 0.006), 0.048, cut - 0.004)
    return holes


def apply_build(
    rng: np.random.Generator, build: Build, holes: np.ndarray, geo: np.ndarray, shade: np.ndarray, mats: np.ndarray
) -> None:
    """Write the build's cabinet, pocket rims, plates, coin box and sights into the scene arrays (in place)."""
    rw = float(geo[sc.G_RW])
    if build.name == "pub":  # a wide laminate cabinet down to the floor
        geo[sc.G_LEGS] = 0.0
        geo[sc.G_BI] = rng.uniform(0.0, 0.04)
        geo[sc.G_ZA] = -rng.uniform(0.15, 0.28)
        mats[sc.M_BODY] = mats[sc.M_APRON] * rng.uniform(0.75, 1.0)
    elif build.name == "home":
        geo[sc.G_LEGS] = float(rng.choice([0, 4, 6], p=[0.25, 0.5, 0.25]))
        if geo[sc.G_LEGS] > 0:
            geo[sc.G_BI] = rng.uniform(0.03, 0.12)
    colour = np.array(PLATE_COLOURS[int(rng.integers(len(PLATE_COLOURS)))])
    mats[sc.M_PLATE] = np.clip(colour * rng.uniform(0.9, 1.1), 0.0, 1.0)
    shade[sc.S_METAL_SHIN] = rng.uniform(30.0, 150.0)
    if build.plates != "none":
        geo[sc.G_PLATE] = rw + rng.uniform(0.0, 0.035)
        geo[sc.G_PLATE_SQ] = float(build.plates == "square")
    if build.coin_box:
        za, zf = float(geo[sc.G_ZA]), float(geo[sc.G_ZF])
        top = za - rng.uniform(0.01, 0.06)
        geo[sc.G_BOXW] = rng.uniform(0.12, 0.25)
        geo[sc.G_BOXD] = rng.uniform(0.02, 0.07)
        geo[sc.G_BOXZ1] = top
        geo[sc.G_BOXZ0] = max(top - rng.uniform(0.12, 0.26), zf + 0.08)
    if build.rounded:  # the rim on the rail cap opens as wide as the cut in the cushions
        geo[sc.G_LINER] = float(np.max(holes[:, 3] - holes[:, 2])) + rng.uniform(0.003, 0.015)
    if build.has_sights:
        shade[sc.S_DIA_SHAPE] = float(SIGHT_CODES[build.sights])
        lo, hi = SIGHT_SIZES.get(build.sights, (0.0055, 0.0085))
        geo[sc.G_DR] = rng.uniform(lo, hi)

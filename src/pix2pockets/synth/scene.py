"""A renderable scene: table build, materials, lights, room and balls (everything but the camera).

:func:`sample_scene` draws all appearance choices from one ``np.random.Generator``; the result packs them
into the flat arrays :func:`pix2pockets.synth.render_pass.render_scene` takes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pix2pockets.geometry.table import TableSpec
from pix2pockets.state.ball_set import BallSet
from pix2pockets.state.layout import TableLayout
from pix2pockets.synth import scene_codes as sc
from pix2pockets.synth.builds import (
    CLOTH_WEIGHTS_BY_BUILD,
    LIGHTING_BY_BUILD,
    RAIL_WEIGHTS_BY_BUILD,
    apply_build,
    pocket_holes,
    sample_build,
)
from pix2pockets.synth.palette import (
    ALT_BALL_COLOURS,
    BALL_COLOURS,
    BLACKBALL_COLOURS,
    BLACKBALL_NUMBERED_BLACK,
    CLOTH_COLOURS,
    DARK_DIAMOND_COLOURS,
    DARK_DIAMONDS_ON_LIGHT_RAILS,
    DIAMOND_COLOURS,
    LIGHT_RAILS,
    LINER_COLOURS,
    PUB_LINER_COLOURS,
    RAIL_MATERIALS,
    RAIL_WEIGHTS,
    STRIPE_WHITE,
    WOOD_RAILS,
    jitter,
    weighted_choice,
)
from pix2pockets.synth.textures import TEXTURE_VARIANTS, cached_floor, cached_grain, cached_noise, cached_wall

ROOM_FOR_LIGHTING = {"broadcast": "arena", "pub_lamps": "pub", "warm_pub": "pub", "home": "home"}
HALL_IN_HOME_ROOM = 0.15
"""Share of lamp-lit hall tables that stand in a home room instead of a pub or hall."""


@dataclass(frozen=True, eq=False)
class Scene:
    """Everything needed to render a table except the camera.

    Attributes:
        spec: the table (playing-surface size, pockets, diamonds).
        layout: balls and their centres in the table frame [m].
        rotations: per-ball rotation world -> ball frame (n, 3, 3) (orients numbers and stripe bands).
        geo, shade, mats: flat parameter arrays (see ``scene_codes.G_*``, ``S_*``, ``M_*``).
        holes: pocket holes (6, 4): centre x, y [m], radius [m] and the round cut of the cushion ends around it [m]
            (0: jaw-cut pockets), see :func:`pix2pockets.synth.builds.pocket_holes`.
        lights: point lights (m, 8): x, y, z [m], intensity, r, g, b, radius [m].
        noise, grain: float tiles; floor_tex, wall_tex: uint8 RGB textures (shared, read-only caches).
        style: names of the drawn choices (build, sights, cloth, rails, lighting, room, ...) for the label file.
    """

    spec: TableSpec
    layout: TableLayout
    rotations: np.ndarray
    geo: np.ndarray
    shade: np.ndarray
    mats: np.ndarray
    holes: np.ndarray
    lights: np.ndarray
    noise: np.ndarray
    grain: np.ndarray
    floor_tex: np.ndarray
    wall_tex: np.ndarray
    style: dict = field(default_factory=dict)

    @property
    def ball_centres(self) -> np.ndarray:
        """Ball centres in 3-D [m], shape (n, 3): on the cloth, so z = each ball's radius (a UK set's cue ball is
        smaller, :attr:`TableLayout.radii`)."""
        return np.column_stack([self.layout.positions, self.layout.radii])

    @property
    def has_sights(self) -> bool:
        """Whether the rail caps carry sights (diamonds); plain rails have none."""
        return self.style.get("sights", "round") != "none"

    @property
    def sights(self) -> np.ndarray:
        """Sight centres on the rail caps (18, 2) [m], or (0, 2) for plain rails."""
        return self.spec.diamonds if self.has_sights else np.zeros((0, 2))

    @property
    def rail_width(self) -> float:
        return float(self.geo[sc.G_RW])

    @property
    def floor_z(self) -> float:
        return float(self.geo[sc.G_ZF])

    @property
    def ball_set(self) -> BallSet:
        """The set on the table: American numbered balls, or a blackball set (7 reds, 7 yellows)."""
        return BallSet(self.style.get("ball_set", BallSet.AMERICAN))

    def ball_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Band/base colours (n, 3), kinds (n,) and numbers (n,) of the balls for the ray caster.

        In a blackball set numbers 1-7 are the reds and 9-15 the yellows, drawn plain; the black keeps its 8 when
        the set's style says so."""
        jit = self.style.get("ball_jitter", {})
        blackball = self.ball_set is BallSet.BLACKBALL
        cols, kinds, nums = [], [], []
        for ball in self.layout.balls:
            n = int(ball.number)
            base = n - 8 if n > 8 else n
            if blackball and n not in (0, 8):
                cols.append(jit["red" if n < 8 else "yellow"])
                kinds.append(sc.BALL_PLAIN)
            else:
                cols.append(jit.get(base, BALL_COLOURS[base]))
                plain_black = blackball and n == 8 and not self.style.get("numbered_black", True)
                kind = sc.BALL_CUE if n == 0 else sc.BALL_STRIPE if n > 8 else sc.BALL_SOLID
                kinds.append(sc.BALL_PLAIN if plain_black else kind)
            nums.append(n)
        return (
            np.array(cols, dtype=np.float64).reshape(-1, 3),
            np.array(kinds, dtype=np.int64),
            np.array(nums, dtype=np.int64),
        )


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A uniformly random rotation matrix (3, 3)."""
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def _jaw_slope(angle: float) -> float:
    """How far a cushion end moves toward the pocket per metre behind the nose, for a jaw angle [rad]."""
    return -math.cos(angle) / math.sin(angle)


def _lights(rng: np.random.Generator, kind: str, spec: TableSpec) -> np.ndarray:
    L, W = spec.length, spec.width
    rows = []
    if kind == "broadcast":
        n = int(rng.integers(2, 5))
        z = rng.uniform(2.5, 5.0)
        for i in range(n):
            x = L * (i + 0.5) / n + rng.normal(0, 0.1)
            for y in (W * 0.3, W * 0.7) if rng.random() < 0.5 else (W / 2,):
                rows.append([x, y + rng.normal(0, 0.1), z, 1.0, 1.0, 1.0, 1.0, rng.uniform(0.2, 0.6)])
    elif kind in ("pub_lamps", "warm_pub"):
        n = int(rng.integers(1, 4))
        z = rng.uniform(0.75, 1.3)
        colour = (1.0, 0.86, 0.62) if kind == "warm_pub" else jitter(rng, (1.0, 0.97, 0.92), 0.03)
        for i in range(n):
            x = L * (i + 0.5) / n + rng.normal(0, 0.05)
            rows.append([x, W / 2 + rng.normal(0, 0.05), z, 1.0, *colour, rng.uniform(0.04, 0.25)])
    else:  # home: a big soft window/ceiling light off to one side, plus a weak lamp
        side = rng.choice([-1.0, 1.0])
        rows.append([L * rng.uniform(0.2, 0.8), W / 2 + side * rng.uniform(1.0, 3.0), rng.uniform(1.5, 2.5), 1.2,
                     *jitter(rng, (0.95, 0.97, 1.0), 0.03), rng.uniform(0.5, 1.2)])  # fmt: skip
        if rng.random() < 0.6:
            rows.append([L / 2, W / 2, rng.uniform(1.2, 2.0), 0.5, 1.0, 0.92, 0.8, 0.2])
    arr = np.array(rows, dtype=np.float64)
    arr[:, 3] /= arr[:, 3].sum() ** 0.7  # several lights: brighter, but not linearly
    return arr


def _diamond_colour(rng: np.random.Generator, rail_name: str) -> tuple[float, float, float]:
    """Diamond inlay colour: light inlays, or often dark ones on light rails."""
    if rail_name in LIGHT_RAILS and rng.random() < DARK_DIAMONDS_ON_LIGHT_RAILS:
        return DARK_DIAMOND_COLOURS[int(rng.integers(len(DARK_DIAMOND_COLOURS)))]
    return DIAMOND_COLOURS[int(rng.integers(len(DIAMOND_COLOURS)))]


def sample_scene(
    rng: np.random.Generator,
    layout: TableLayout,
    spec: TableSpec | None = None,
    ball_set: BallSet | str = BallSet.AMERICAN,
) -> Scene:
    """Draw table build, materials, lighting and room for ``layout`` (its own spec unless ``spec``), with an American
    or a blackball set of balls."""
    spec = spec or layout.spec
    L, W = spec.length, spec.width
    build = sample_build(rng, spec)
    lighting = weighted_choice(rng, LIGHTING_BY_BUILD[build.name])
    room = ROOM_FOR_LIGHTING[lighting]
    if build.name == "home" or (build.name == "hall" and room == "pub" and rng.random() < HALL_IN_HOME_ROOM):
        room = "home"
    cloth_name = weighted_choice(rng, CLOTH_WEIGHTS_BY_BUILD[build.name])
    rail_name = weighted_choice(rng, RAIL_WEIGHTS_BY_BUILD[build.name])

    geo = np.zeros(sc.N_GEO)
    geo[sc.G_L], geo[sc.G_W] = L, W
    geo[sc.G_H] = spec.cushion_height
    geo[sc.G_HR] = spec.cushion_height + rng.uniform(0.003, 0.012)
    geo[sc.G_CW] = rng.uniform(0.04, 0.055)
    rw = float(np.clip(spec.rail_width * rng.uniform(0.9, 1.45), spec.diamond_setback + 0.025, 0.22))
    geo[sc.G_RW] = rw
    geo[sc.G_ZA] = -rng.uniform(0.1, 0.3)
    geo[sc.G_BI] = rng.uniform(0.02, 0.3)
    zf = -rng.uniform(0.74, 0.80)
    geo[sc.G_ZF] = zf
    geo[sc.G_ZC] = zf + rng.uniform(2.5, 4.0)
    geo[sc.G_RX0] = -rw - rng.uniform(1.0, 4.0)
    geo[sc.G_RX1] = L + rw + rng.uniform(1.0, 4.0)
    geo[sc.G_RY0] = -rw - rng.uniform(1.0, 4.0)
    geo[sc.G_RY1] = W + rw + rng.uniform(1.0, 4.0)
    geo[sc.G_LINER] = rng.uniform(0.006, 0.025)
    geo[sc.G_DR] = rng.uniform(0.0055, 0.0085)
    geo[sc.G_KC] = _jaw_slope(spec.corner_jaw_angle)
    geo[sc.G_KS] = _jaw_slope(spec.side_jaw_angle)
    geo[sc.G_DC] = spec.corner_mouth / math.sqrt(2)
    geo[sc.G_SS] = spec.side_mouth / 2
    geo[sc.G_ZHB] = -0.12
    geo[sc.G_LEGS] = float(rng.choice([0, 4, 6], p=[0.45, 0.35, 0.2]))
    geo[sc.G_LEGW] = rng.uniform(0.1, 0.25)
    geo[sc.G_SKIRT] = rng.uniform(0.06, 0.2)
    if geo[sc.G_LEGS] > 0:  # legged tables sit under a shallower apron, legs just inside the rail
        geo[sc.G_BI] = rng.uniform(0.03, 0.12)

    holes = pocket_holes(rng, spec, build.rounded)

    is_wood = rail_name in WOOD_RAILS
    shade = np.zeros(sc.N_SHADE)
    shade[sc.S_AMB] = {"broadcast": 0.35, "pub_lamps": 0.2, "warm_pub": 0.12, "home": 0.45}[lighting] * rng.uniform(
        0.7, 1.3
    )
    shade[sc.S_CLOTH_TEX] = rng.uniform(0.02, 0.09)
    shade[sc.S_CLOTH_SCALE] = rng.uniform(60, 250)
    shade[sc.S_RAIL_TEX] = rng.uniform(0.6, 1.0) if is_wood else rng.uniform(0.0, 0.15)
    shade[sc.S_RAIL_GLOSS] = rng.uniform(0.05, 0.5)
    shade[sc.S_RAIL_SHIN] = rng.uniform(15, 80)
    shade[sc.S_BALL_KS] = rng.uniform(0.5, 1.3)
    shade[sc.S_BALL_SHIN] = rng.uniform(60, 500)
    shade[sc.S_FLOOR_SCALE] = rng.uniform(60, 200)
    shade[sc.S_BOUNCE] = rng.uniform(0.1, 0.4)
    shade[sc.S_CUE_DOTS] = float(rng.random() < 0.2)
    shade[sc.S_BAND] = rng.uniform(0.42, 0.6)
    shade[sc.S_NUMR] = math.cos(rng.uniform(0.33, 0.45))
    shade[sc.S_REFL] = rng.uniform(0.3, 1.0)
    shade[sc.S_ROOM] = {"arena": rng.uniform(0.0, 0.1), "pub": rng.uniform(0.05, 0.3), "home": rng.uniform(0.2, 0.6)}[
        room
    ]
    shade[sc.S_CLOTH_NAP] = rng.uniform(0.0, 0.06)
    shade[sc.S_AO] = rng.uniform(0.35, 0.75)

    mats = np.zeros((sc.N_MATS, 3))
    mats[sc.M_CLOTH] = jitter(rng, CLOTH_COLOURS[cloth_name], 0.12)
    mats[sc.M_RAIL] = jitter(rng, RAIL_MATERIALS[rail_name], 0.1)
    mats[sc.M_APRON] = (
        mats[sc.M_RAIL] * rng.uniform(0.6, 1.0)
        if rng.random() < 0.7
        else jitter(rng, RAIL_MATERIALS[weighted_choice(rng, RAIL_WEIGHTS)], 0.1)
    )
    mats[sc.M_BODY] = mats[sc.M_APRON] * rng.uniform(0.3, 0.8)
    liners = PUB_LINER_COLOURS if build.rounded else LINER_COLOURS
    mats[sc.M_LINER] = jitter(rng, liners[int(rng.integers(len(liners)))], 0.1)
    mats[sc.M_DIAMOND] = jitter(rng, _diamond_colour(rng, rail_name), 0.03)
    mats[sc.M_CEIL] = jitter(rng, (0.3, 0.3, 0.3) if room != "arena" else (0.02, 0.02, 0.03), 0.3)
    amb_col = {"warm_pub": (1.0, 0.85, 0.65), "home": (0.95, 0.97, 1.0)}.get(lighting, (1.0, 1.0, 1.0))
    mats[sc.M_AMBCOL] = jitter(rng, amb_col, 0.03)
    mats[sc.M_WALLTINT] = jitter(rng, (1.0, 1.0, 1.0), 0.05)
    mats[sc.M_RUG] = rng.uniform(0.05, 0.6, 3) ** 1.3
    if room != "arena" and rng.random() < 0.3:  # a rug under the table
        geo[sc.G_RUGX] = L / 2 + rw + rng.uniform(0.2, 1.0)
        geo[sc.G_RUGY] = W / 2 + rw + rng.uniform(0.2, 1.0)

    apply_build(rng, build, holes, geo, shade, mats)

    base_colours = dict(BALL_COLOURS)
    for n, alts in ALT_BALL_COLOURS.items():
        if rng.random() < 0.2:
            base_colours[n] = alts[int(rng.integers(len(alts)))]
    ball_jitter = {n: tuple(jitter(rng, c, 0.07)) for n, c in base_colours.items()}
    ball_jitter[0] = tuple(jitter(rng, STRIPE_WHITE, 0.02))
    ball_set = BallSet(ball_set)
    numbered_black = True
    if ball_set is BallSet.BLACKBALL:  # drawn last: an American scene's draws stay as they are
        for group, shades in BLACKBALL_COLOURS.items():
            ball_jitter[group] = tuple(jitter(rng, shades[int(rng.integers(len(shades)))], 0.05))
        numbered_black = bool(rng.random() < BLACKBALL_NUMBERED_BLACK)

    n = len(layout)
    rotations = np.array([random_rotation(rng) for _ in range(n)]).reshape(n, 3, 3)
    style = {
        "cloth": cloth_name,
        "rail": rail_name,
        "lighting": lighting,
        "room": room,
        "build": build.name,
        "sights": build.sights,
        "diamond_shape": build.sights,
        "pockets": "rounded" if build.rounded else "jaw_cut",
        "plates": build.plates,
        "coin_box": build.coin_box,
        "ball_jitter": ball_jitter,
        "ball_set": ball_set.value,
        "numbered_black": numbered_black,
    }
    return Scene(
        spec=spec,
        layout=layout,
        rotations=rotations,
        geo=geo,
        shade=shade,
        mats=mats,
        holes=holes,
        lights=_lights(rng, lighting, spec),
        noise=cached_noise(int(rng.integers(TEXTURE_VARIANTS))),
        grain=cached_grain(int(rng.integers(TEXTURE_VARIANTS))),
        floor_tex=cached_floor(int(rng.integers(TEXTURE_VARIANTS))),
        wall_tex=cached_wall(room, int(rng.integers(TEXTURE_VARIANTS))),
        style=style,
    )

"""Colours of the things on and around a pool table (RGB in [0, 1], display space).

Every palette entry is a base colour; scenes jitter it (see :func:`jitter`) so no two ball sets, cloths or
rails look exactly alike.
"""

from __future__ import annotations

import numpy as np

BALL_COLOURS: dict[int, tuple[float, float, float]] = {
    0: (0.93, 0.92, 0.86),  # cue: off-white
    1: (0.98, 0.76, 0.04),  # yellow
    2: (0.05, 0.16, 0.62),  # blue
    3: (0.86, 0.07, 0.05),  # red
    4: (0.33, 0.10, 0.52),  # purple
    5: (0.98, 0.40, 0.04),  # orange
    6: (0.02, 0.42, 0.18),  # green
    7: (0.47, 0.06, 0.07),  # maroon
    8: (0.025, 0.025, 0.03),  # black
}
"""Standard ball colours by number (stripes 9-15 use the colour of ``number - 8`` as their band)."""

ALT_BALL_COLOURS: dict[int, tuple[tuple[float, float, float], ...]] = {
    2: ((0.1, 0.3, 0.8), (0.02, 0.08, 0.4)),  # lighter / navy blue
    4: ((0.8, 0.25, 0.55), (0.2, 0.08, 0.45)),  # pink / dark violet (cheap and TV sets)
    5: ((0.95, 0.55, 0.1),),
    6: ((0.1, 0.55, 0.25), (0.0, 0.3, 0.2)),
    7: ((0.4, 0.18, 0.08), (0.6, 0.1, 0.1)),  # brown / dark red
}
"""Alternative shades seen in other ball sets; a scene swaps some in."""

STRIPE_WHITE = (0.92, 0.91, 0.85)

BLACKBALL_COLOURS: dict[str, tuple[tuple[float, float, float], ...]] = {
    "red": ((0.80, 0.05, 0.05), (0.68, 0.03, 0.06), (0.88, 0.12, 0.08)),
    "yellow": ((0.98, 0.80, 0.08), (0.98, 0.70, 0.05), (0.95, 0.86, 0.20)),
}
"""Shades of a UK blackball set's reds and yellows (plain balls, no numbers); a scene draws one shade of each."""
BLACKBALL_NUMBERED_BLACK = 0.6
"""Share of blackball sets whose black carries an 8 (the others are plain)."""

CLOTH_COLOURS: dict[str, tuple[float, float, float]] = {
    "tournament_blue": (0.07, 0.30, 0.62),
    "electric_blue": (0.05, 0.38, 0.75),
    "green": (0.06, 0.40, 0.16),
    "english_green": (0.10, 0.45, 0.12),
    "teal": (0.04, 0.40, 0.42),
    "red": (0.55, 0.06, 0.07),
    "burgundy": (0.36, 0.05, 0.10),
    "grey": (0.36, 0.38, 0.40),
    "purple": (0.30, 0.12, 0.42),
    "black": (0.08, 0.08, 0.09),
    "tan": (0.55, 0.45, 0.30),
}
CLOTH_WEIGHTS = {
    "tournament_blue": 4.0,
    "electric_blue": 1.5,
    "green": 4.0,
    "english_green": 1.5,
    "teal": 1.0,
    "red": 1.5,
    "burgundy": 1.0,
    "grey": 1.0,
    "purple": 0.6,
    "black": 0.3,
    "tan": 0.3,
}

RAIL_MATERIALS: dict[str, tuple[float, float, float]] = {
    "dark_wood": (0.22, 0.11, 0.05),
    "mid_wood": (0.42, 0.24, 0.11),
    "light_wood": (0.62, 0.45, 0.27),
    "black": (0.05, 0.05, 0.055),
    "grey": (0.38, 0.39, 0.40),
    "white": (0.88, 0.88, 0.86),
    "silver": (0.62, 0.63, 0.65),
}
RAIL_WEIGHTS = {
    "dark_wood": 3.0,
    "mid_wood": 2.0,
    "light_wood": 1.0,
    "black": 3.0,
    "grey": 1.0,
    "white": 1.2,
    "silver": 0.6,
}
WOOD_RAILS = ("dark_wood", "mid_wood", "light_wood")

LINER_COLOURS = (
    (0.03, 0.03, 0.03),  # black rubber / plastic
    (0.20, 0.11, 0.05),  # brown leather
    (0.55, 0.55, 0.56),  # chrome/plastic corner caps
    (0.10, 0.10, 0.10),
)

PUB_LINER_COLOURS = (
    (0.03, 0.03, 0.03),  # black plastic pocket rims
    (0.62, 0.62, 0.64),  # chrome
    (0.75, 0.6, 0.3),  # brass
)
"""Rims of rounded (pub) pockets."""

DIAMOND_COLOURS = (
    (0.95, 0.95, 0.92),  # white plastic
    (0.92, 0.89, 0.80),  # mother of pearl
    (0.80, 0.78, 0.72),  # ivory
    (0.85, 0.75, 0.45),  # brass
)
DARK_DIAMOND_COLOURS = (
    (0.04, 0.04, 0.04),  # black plastic, common on white and silver rails
    (0.10, 0.12, 0.25),  # navy
    (0.30, 0.05, 0.05),  # maroon
)
LIGHT_RAILS = ("white", "silver")
DARK_DIAMONDS_ON_LIGHT_RAILS = 0.6
"""Chance that a white or silver rail gets dark diamonds (white diamonds on a white rail are nearly invisible)."""


def weighted_choice(rng: np.random.Generator, weights: dict[str, float]) -> str:
    """One key of ``weights`` drawn with probability proportional to its weight."""
    keys = list(weights)
    p = np.array([weights[k] for k in keys], dtype=float)
    return keys[int(rng.choice(len(keys), p=p / p.sum()))]


def jitter(rng: np.random.Generator, colour: tuple[float, float, float], amount: float) -> np.ndarray:
    """``colour`` with per-channel multiplicative jitter of relative size ``amount`` and a brightness change."""
    c = np.asarray(colour, dtype=float)
    c = c * (1.0 + amount * rng.normal(0.0, 1.0, 3)) * (1.0 + 0.5 * amount * rng.normal())
    return np.clip(c, 0.0, 1.0)

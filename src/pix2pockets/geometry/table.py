"""Table specification: sizes, pockets, cushions, diamonds, in one table frame.

Table frame (defined once, used everywhere):
    * origin at the **head-left corner of the playing surface**, i.e. where the head cushion nose line
      meets the lower long cushion nose line;
    * ``+x`` runs along the long axis from the **head rail** (``x = 0``) to the **foot rail**
      (``x = length``);
    * ``+y`` runs across the table from the lower long rail (``y = 0``) to the upper one
      (``y = width``); ``+z`` points up out of the cloth (right-handed frame);
    * units are metres; angles are radians, counter-clockwise from ``+x``.

The playing surface is the rectangle between the cushion noses, ``[0, length] x [0, width]``.

References:
    WPA equipment specifications (table, pockets, sights); see ``docs/geometry.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np

INCH = 0.0254  # [m]


class Rail(StrEnum):
    """The four rails, named in the table frame."""

    BOTTOM = "bottom"  # y = 0, long rail
    FOOT = "foot"  # x = length, short rail
    TOP = "top"  # y = width, long rail
    HEAD = "head"  # x = 0, short rail


class PocketKind(StrEnum):
    CORNER = "corner"
    SIDE = "side"


@dataclass(frozen=True, slots=True)
class Pocket:
    """One pocket.

    Attributes:
        name: short name, e.g. ``"bottom-left"``.
        kind: corner or side.
        jaws: the two jaw points (cushion-nose ends) [m], shape (2, 2).
        centre: centre of the capture circle [m], shape (2,).
        capture_radius: a ball whose centre enters this circle drops [m].
        aim: point a shot at this pocket should aim for: the middle of the mouth [m], shape (2,).
    """

    name: str
    kind: PocketKind
    jaws: np.ndarray
    centre: np.ndarray
    capture_radius: float
    aim: np.ndarray

    @property
    def mouth_width(self) -> float:
        """Distance between the jaw points [m]."""
        return float(np.linalg.norm(self.jaws[1] - self.jaws[0]))


@dataclass(frozen=True, slots=True)
class TableSpec:
    """A pool table in SI units (metres, radians). Immutable; make variants with ``dataclasses.replace``.

    Attributes:
        name: preset name.
        length: playing-surface length between cushion noses, head to foot [m].
        width: playing-surface width between cushion noses [m].
        ball_radius: ball radius [m] (57.15 mm diameter balls).
        ball_mass: ball mass [kg].
        cue_ball_radius: the cue ball's radius [m] where it differs from the object balls' (a UK set's 1 7/8 in cue
            ball); ``None``: ``ball_radius``.
        cue_ball_mass: the cue ball's mass [kg] where it differs; ``None``: ``ball_mass``.
        corner_mouth: corner pocket mouth, jaw point to jaw point [m].
        side_mouth: side pocket mouth, jaw point to jaw point [m].
        corner_jaw_angle: angle between cushion nose and jaw face at a corner pocket [rad].
        side_jaw_angle: angle between cushion nose and jaw face at a side pocket [rad].
        jaw_depth: length of a jaw face from the jaw point into the rail [m].
        corner_pocket_setback: capture centre distance outward from the corner along the diagonal [m].
        corner_capture_radius: corner capture-circle radius [m].
        side_pocket_setback: capture centre distance outward from the long cushion nose line [m].
        side_capture_radius: side capture-circle radius [m].
        diamond_setback: sight centre distance behind the cushion nose, on the rail cap [m].
        rail_width: cushion nose to outer edge of the rail [m] (rendering only).
        cushion_height: height of the cushion nose above the cloth [m].
    """

    name: str = "9ft"
    length: float = 100 * INCH
    width: float = 50 * INCH
    ball_radius: float = 0.05715 / 2
    ball_mass: float = 0.170
    corner_mouth: float = 4.5 * INCH
    side_mouth: float = 5.0 * INCH
    corner_jaw_angle: float = math.radians(142.0)
    side_jaw_angle: float = math.radians(104.0)
    jaw_depth: float = 0.05
    corner_pocket_setback: float = 0.02
    corner_capture_radius: float = 0.075
    side_pocket_setback: float = 0.03
    side_capture_radius: float = 0.065
    diamond_setback: float = 3.6875 * INCH
    rail_width: float = 5.5 * INCH
    cushion_height: float = 0.635 * 0.05715
    cue_ball_radius: float | None = None
    cue_ball_mass: float | None = None
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False, hash=False)

    def __post_init__(self) -> None:
        positive = [
            "length",
            "width",
            "ball_radius",
            "ball_mass",
            "corner_mouth",
            "side_mouth",
            "jaw_depth",
            "corner_capture_radius",
            "side_capture_radius",
            "diamond_setback",
            "rail_width",
            "cushion_height",
        ]
        for name in positive:
            if not getattr(self, name) > 0:
                raise ValueError(f"TableSpec.{name} must be positive, got {getattr(self, name)!r}")
        for name in ("cue_ball_radius", "cue_ball_mass"):
            value = getattr(self, name)
            if value is not None and not value > 0:
                raise ValueError(f"TableSpec.{name} must be positive or None, got {value!r}")
        if self.cue_ball_radius is not None and not self.cue_radius < self.cushion_height < 2 * self.cue_radius:
            raise ValueError(
                f"TableSpec.cue_ball_radius {self.cue_radius!r} m must put the cushion nose "
                f"({self.cushion_height!r} m) between the cue ball's equator and its top"
            )
        if self.width >= self.length:
            raise ValueError(f"TableSpec width ({self.width} m) must be less than length ({self.length} m)")
        if self.side_mouth >= self.length / 2 or self.corner_mouth >= self.width / 2:
            raise ValueError("TableSpec pocket mouths are too wide for the table")
        for name in ("corner_jaw_angle", "side_jaw_angle"):
            angle = getattr(self, name)
            if not math.radians(60) < angle < math.radians(170):
                raise ValueError(f"TableSpec.{name} must be between 60 and 170 degrees, got {math.degrees(angle):.1f}")

    # ------------------------------------------------------------------ balls
    @property
    def cue_radius(self) -> float:
        """The cue ball's radius [m]."""
        return self.ball_radius if self.cue_ball_radius is None else self.cue_ball_radius

    @property
    def cue_mass(self) -> float:
        """The cue ball's mass [kg]."""
        return self.ball_mass if self.cue_ball_mass is None else self.cue_ball_mass

    @property
    def cue_contact_distance(self) -> float:
        """Centre distance of the cue ball touching an object ball [m]."""
        return self.cue_radius + self.ball_radius

    # ------------------------------------------------------------------ frame
    @property
    def size(self) -> np.ndarray:
        """(length, width) [m]."""
        return np.array([self.length, self.width])

    @property
    def diagonal(self) -> float:
        """Length of the playing-surface diagonal [m]."""
        return math.hypot(self.length, self.width)

    @property
    def head_string_x(self) -> float:
        """x of the head string (a quarter of the length from the head cushion) [m]."""
        return self.length / 4

    @property
    def baulk_line_x(self) -> float:
        """x of the baulk line of blackball (a fifth of the length from the head cushion, the one farthest from the
        spot; WEPF rules) [m]."""
        return self.length / 5

    @property
    def foot_spot(self) -> np.ndarray:
        """The foot spot, where the rack's apex ball sits [m]."""
        return np.array([0.75 * self.length, 0.5 * self.width])

    @property
    def head_spot(self) -> np.ndarray:
        """The head spot [m]."""
        return np.array([0.25 * self.length, 0.5 * self.width])

    def contains(self, xy: np.ndarray, margin: float = 0.0) -> np.ndarray:
        """Whether points lie on the playing surface shrunk by ``margin`` [m] on each side.

        Args:
            xy: points [m], shape (..., 2).
            margin: inset from the cushion noses [m]; ``ball_radius`` tests ball centres.
        """
        xy = np.asarray(xy, dtype=float)
        return (
            (xy[..., 0] >= margin)
            & (xy[..., 0] <= self.length - margin)
            & (xy[..., 1] >= margin)
            & (xy[..., 1] <= self.width - margin)
        )

    # ---------------------------------------------------------------- pockets
    @property
    def pockets(self) -> tuple[Pocket, ...]:
        """The six pockets in fixed order: bottom-left, bottom-side, bottom-right, top-right, top-side,
        top-left ("left" = head end, x = 0)."""
        if "pockets" not in self._cache:
            self._cache["pockets"] = self._build_pockets()
        return self._cache["pockets"]

    def _build_pockets(self) -> tuple[Pocket, ...]:
        L, W = self.length, self.width
        d = self.corner_mouth / math.sqrt(2)  # jaw point distance from the corner along each rail
        s = self.side_mouth / 2
        corners = {
            "bottom-left": (np.array([0.0, 0.0]), np.array([-1.0, -1.0])),
            "bottom-right": (np.array([L, 0.0]), np.array([1.0, -1.0])),
            "top-right": (np.array([L, W]), np.array([1.0, 1.0])),
            "top-left": (np.array([0.0, W]), np.array([-1.0, 1.0])),
        }

        def corner(name: str) -> Pocket:
            c, out = corners[name]
            out = out / np.linalg.norm(out)
            sx, sy = np.sign(-out)  # direction from the corner into the table along each rail
            jaws = np.array([c + np.array([sx * d, 0.0]), c + np.array([0.0, sy * d])])
            return Pocket(
                name,
                PocketKind.CORNER,
                jaws,
                c + out * self.corner_pocket_setback,
                self.corner_capture_radius,
                jaws.mean(axis=0),
            )

        def side(name: str, y: float, out_y: float) -> Pocket:
            jaws = np.array([[L / 2 - s, y], [L / 2 + s, y]])
            centre = np.array([L / 2, y + out_y * self.side_pocket_setback])
            return Pocket(name, PocketKind.SIDE, jaws, centre, self.side_capture_radius, jaws.mean(axis=0))

        return (
            corner("bottom-left"),
            side("bottom-side", 0.0, -1.0),
            corner("bottom-right"),
            corner("top-right"),
            side("top-side", W, 1.0),
            corner("top-left"),
        )

    def pocket_index(self, name: str) -> int:
        """The index in :attr:`pockets` of the pocket named ``name``.

        Raises:
            ValueError: no pocket of that name.
        """
        for k, pocket in enumerate(self.pockets):
            if pocket.name == name:
                return k
        raise ValueError(f"no pocket named {name!r}: pockets are {', '.join(p.name for p in self.pockets)}")

    @property
    def pocket_centres(self) -> np.ndarray:
        """Capture-circle centres of the six pockets [m], shape (6, 2)."""
        return np.array([p.centre for p in self.pockets])

    @property
    def pocket_aims(self) -> np.ndarray:
        """Mouth midpoints of the six pockets [m], shape (6, 2)."""
        return np.array([p.aim for p in self.pockets])

    # --------------------------------------------------------------- cushions
    @property
    def cushion_segments(self) -> np.ndarray:
        """Cushion nose segments between the pockets [m], shape (6, 2, 2): start and end point.

        Order: bottom head-half, bottom foot-half, foot, top foot-half, top head-half, head.
        A ball's centre stays at least ``ball_radius`` away from every segment.
        """
        if "cushions" not in self._cache:
            L, W = self.length, self.width
            d = self.corner_mouth / math.sqrt(2)
            s = self.side_mouth / 2
            self._cache["cushions"] = np.array(
                [
                    [[d, 0.0], [L / 2 - s, 0.0]],
                    [[L / 2 + s, 0.0], [L - d, 0.0]],
                    [[L, d], [L, W - d]],
                    [[L - d, W], [L / 2 + s, W]],
                    [[L / 2 - s, W], [d, W]],
                    [[0.0, W - d], [0.0, d]],
                ]
            )
        return self._cache["cushions"]

    @property
    def jaw_segments(self) -> np.ndarray:
        """Jaw faces [m], shape (12, 2, 2): from each jaw point back into the rail.

        Two per pocket in ``pockets`` order. The angle between the cushion nose (pointing away from the
        pocket) and the jaw face is ``corner_jaw_angle`` / ``side_jaw_angle``.
        """
        if "jaws" not in self._cache:
            segs = []
            for pocket in self.pockets:
                angle = self.corner_jaw_angle if pocket.kind is PocketKind.CORNER else self.side_jaw_angle
                for i, jaw in enumerate(pocket.jaws):
                    other = pocket.jaws[1 - i]
                    along = _nose_direction_away_from_pocket(self, jaw, other, pocket)
                    outward = _outward_normal(self, jaw)
                    # rotate `along` by `angle` toward `outward`
                    cross = along[0] * outward[1] - along[1] * outward[0]
                    theta = angle if cross > 0 else -angle
                    c, s_ = math.cos(theta), math.sin(theta)
                    direction = np.array([c * along[0] - s_ * along[1], s_ * along[0] + c * along[1]])
                    segs.append([jaw, jaw + self.jaw_depth * direction])
            self._cache["jaws"] = np.array(segs)
        return self._cache["jaws"]

    # --------------------------------------------------------------- diamonds
    @property
    def diamonds(self) -> np.ndarray:
        """The 18 sights (diamonds) on the rail caps [m], shape (18, 2), in the fixed order below.

        Counter-clockwise around the table seen from above, starting at the head end of the bottom rail:
            0-5:   bottom rail (y = -setback), x = 1/8, 2/8, 3/8, 5/8, 6/8, 7/8 of the length;
            6-8:   foot rail (x = length + setback), y = 1/4, 2/4, 3/4 of the width;
            9-14:  top rail (y = width + setback), x = 7/8 ... 1/8 of the length;
            15-17: head rail (x = -setback), y = 3/4, 2/4, 1/4 of the width.
        """
        if "diamonds" not in self._cache:
            L, W, b = self.length, self.width, self.diamond_setback
            long_fracs = [1, 2, 3, 5, 6, 7]
            pts = [[L * k / 8, -b] for k in long_fracs]
            pts += [[L + b, W * k / 4] for k in (1, 2, 3)]
            pts += [[L * k / 8, W + b] for k in reversed(long_fracs)]
            pts += [[-b, W * k / 4] for k in (3, 2, 1)]
            self._cache["diamonds"] = np.array(pts, dtype=float)
        return self._cache["diamonds"]

    @property
    def corners(self) -> np.ndarray:
        """The 4 playing-surface corners (cushion nose lines) [m], shape (4, 2):
        (0, 0), (length, 0), (length, width), (0, width) - counter-clockwise from the head-bottom corner."""
        return np.array([[0.0, 0.0], [self.length, 0.0], [self.length, self.width], [0.0, self.width]])

    @property
    def reference_points(self) -> np.ndarray:
        """The 22 points vision matches: 18 diamonds then 4 corners [m], shape (22, 2)."""
        return np.vstack([self.diamonds, self.corners])

    @staticmethod
    def diamond_rails() -> tuple[Rail, ...]:
        """Rail of each of the 18 diamonds, in ``diamonds`` order."""
        return (Rail.BOTTOM,) * 6 + (Rail.FOOT,) * 3 + (Rail.TOP,) * 6 + (Rail.HEAD,) * 3


def _outward_normal(spec: TableSpec, point: np.ndarray) -> np.ndarray:
    """Outward normal of the rail a jaw point lies on."""
    x, y = point
    eps = 1e-9
    if abs(y) < eps:
        return np.array([0.0, -1.0])
    if abs(y - spec.width) < eps:
        return np.array([0.0, 1.0])
    if abs(x) < eps:
        return np.array([-1.0, 0.0])
    return np.array([1.0, 0.0])


def _nose_direction_away_from_pocket(
    spec: TableSpec, jaw: np.ndarray, other_jaw: np.ndarray, pocket: Pocket
) -> np.ndarray:
    """Unit vector along the cushion nose at ``jaw``, pointing away from the pocket mouth."""
    normal = _outward_normal(spec, jaw)
    tangent = np.array([-normal[1], normal[0]])
    toward_pocket = pocket.aim - jaw
    if pocket.kind is PocketKind.CORNER:
        toward_pocket = pocket.centre - jaw
    return tangent if np.dot(tangent, toward_pocket) < 0 else -tangent


def _preset(name: str, length_in: float, width_in: float) -> TableSpec:
    return TableSpec(name=name, length=length_in * INCH, width=width_in * INCH)


UK_BALL_RADIUS = 1.0 * INCH
"""Object balls of a UK blackball set: 2 in (50.8 mm) across (WEPF equipment specification)."""
UK_BALL_MASS = 0.116
"""Object ball mass of a UK set [kg] (WEPF: 116 g +- 2 g)."""
UK_CUE_BALL_RADIUS = 0.9375 * INCH
"""The cue ball of a UK set: 1 7/8 in (47.6 mm) across (WEPF)."""
UK_CUE_BALL_MASS = 0.094
"""The cue ball's mass in a UK set [kg] (WEPF: 94 g +- 2 g)."""


def _uk_preset(name: str, length_in: float, width_in: float) -> TableSpec:
    """A UK pub table for a blackball set: 2 in balls and small, rounded pockets. The WEPF fixes the balls and
    the playing surface; the pocket openings follow its templates, which are not published, so the mouths here are
    estimates scaled from the balls (corner 1.75 and middle 1.9 ball diameters, 3.5 and 3.8 in), as are the
    cushion height (the same 0.635 of a ball as American cushions) and the rail."""
    d = 2 * UK_BALL_RADIUS
    return TableSpec(
        name=name,
        length=length_in * INCH,
        width=width_in * INCH,
        ball_radius=UK_BALL_RADIUS,
        ball_mass=UK_BALL_MASS,
        cue_ball_radius=UK_CUE_BALL_RADIUS,
        cue_ball_mass=UK_CUE_BALL_MASS,
        corner_mouth=1.75 * d,
        side_mouth=1.9 * d,
        corner_capture_radius=0.06,
        side_capture_radius=0.055,
        diamond_setback=3.0 * INCH,
        rail_width=4.5 * INCH,
        cushion_height=0.635 * d,
    )


TABLE_PRESETS: dict[str, TableSpec] = {
    "9ft": TableSpec(),
    "8ft": _preset("8ft", 92.0, 46.0),
    "7ft": _preset("7ft", 78.0, 39.0),
    "6ft": _preset("6ft", 66.0, 33.0),
    "uk7": _uk_preset("uk7", 84.0, 42.0),
    "uk6": _uk_preset("uk6", 72.0, 36.0),
}
"""Presets by name, playing surface between the cushion noses: 9-foot 100 x 50 in (the default, ``TableSpec()``),
8-foot 92 x 46 in, 7-foot (bar box) 78 x 39 in, 6-foot (home) 66 x 33 in; UK blackball tables for 2 in balls, 7-foot
84 x 42 in and 6-foot 72 x 36 in (the WEPF's largest and smallest playing surfaces, 7 ft x 3 ft 6 in and
6 ft x 3 ft)."""


def same_balls(a: TableSpec, b: TableSpec) -> bool:
    """Whether two tables are played with balls of one size (American 2 1/4 in, UK 2 in)."""
    return abs(a.ball_radius - b.ball_radius) < 1e-6


def table_preset(name: str) -> TableSpec:
    """Return the preset table called ``name`` (``"9ft"``, ``"8ft"``, ``"7ft"``, ``"6ft"``, ``"uk7"``, ``"uk6"``)."""
    try:
        return TABLE_PRESETS[name]
    except KeyError:
        raise ValueError(f"unknown table preset {name!r}; choose one of {sorted(TABLE_PRESETS)}") from None

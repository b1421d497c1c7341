"""What the photo pipeline returns: located balls, the fitted table and the suggested shot.

``Suggestion.to_dict()`` is the JSON written by ``pix2pockets suggest --json`` (documented in the README
and ``docs/pipeline.md``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.table import TableSpec
from pix2pockets.pipeline.unseen_pockets import pockets_in_photo
from pix2pockets.planner.chance import Chance, format_chance
from pix2pockets.state.layout import TableLayout
from pix2pockets.state.shot import Shot

MIN_SPEED = 0.2  # [m/s] power level 1 (the environment's ActionConfig.min_speed)
MAX_SPEED = 8.0  # [m/s] power level 30 (ActionConfig.max_speed)
N_POWER_LEVELS = 30
SURE_NUMBER_CHANCE = 0.5
WHOLE_TABLE_IN_VIEW = 0.98
"""Share of the playing surface in the photo from which the whole table counts as seen."""
"""A ball is named and drawn by its number when the reader's chance of it is at least this (the JSON always
holds the number and its chance)."""


def power_level(speed: float) -> int:
    """The paper's power level (1-30) closest to a cue-ball speed [m/s]."""
    frac = (speed - MIN_SPEED) / (MAX_SPEED - MIN_SPEED)
    return int(np.clip(round(frac * (N_POWER_LEVELS - 1)) + 1, 1, N_POWER_LEVELS))


@dataclass(frozen=True, slots=True)
class LocatedBall:
    """One ball found in the photo.

    Attributes:
        ball_class: ``cue``, ``black``, ``solid`` or ``stripe`` (``red`` or ``yellow`` in a blackball set).
        confidence: detector score in [0, 1].
        bbox_px: box ``x1, y1, x2, y2`` [px].
        contact_px: where the ball touches the cloth, in the image [px].
        table_xy_m: ball centre in the table frame [m].
        env_xy_px: the same in the paper's environment pixels (735 x 410 window, see
            :func:`pix2pockets.geometry.raster.table_to_env_pixels`).
        number: the ball's number 0-15 as read from the photo (:mod:`pix2pockets.vision.stages.ball_numbers`), ``None``
            when not read.
        number_chance: the reader's chance of that number among the numbers of the ball's class.
        position_sigma_m: how far the ball may be from ``table_xy_m`` along its worst direction (one standard
            deviation) [m], from the camera and the fit's error (:mod:`pix2pockets.vision.locate.position_error`);
            ``None`` when unknown.
        in_hand: the cue ball put there by ball in hand (not seen in the photo: its box and contact point are where it
            would be seen).
    """

    ball_class: str
    confidence: float
    bbox_px: tuple[float, float, float, float]
    contact_px: tuple[float, float]
    table_xy_m: tuple[float, float]
    env_xy_px: tuple[float, float] = (float("nan"), float("nan"))
    number: int | None = None
    number_chance: float | None = None
    position_sigma_m: float | None = None
    in_hand: bool = False

    @property
    def sure_number(self) -> int | None:
        """The number when the reader is fairly sure of it (chance >= :data:`SURE_NUMBER_CHANCE`), else None."""
        if self.number is None or (self.number_chance is not None and self.number_chance < SURE_NUMBER_CHANCE):
            return None
        return self.number

    def scaled(self, sx: float, sy: float) -> LocatedBall:
        """The same ball in the photo resized by ``sx`` across and ``sy`` down (its box and contact point)."""
        x1, y1, x2, y2 = self.bbox_px
        u, v = self.contact_px
        return replace(self, bbox_px=(x1 * sx, y1 * sy, x2 * sx, y2 * sy), contact_px=(u * sx, v * sy))

    @property
    def name(self) -> str:
        """How a player calls the ball: ``3 ball (solid)`` when its number is read with some certainty, else
        ``solid ball``."""
        number = self.sure_number
        return f"{self.ball_class} ball" if number is None else f"{number} ball ({self.ball_class})"

    def to_dict(self) -> dict:
        return {
            "class": self.ball_class,
            "number": self.number,
            "number_chance": None if self.number_chance is None else round(self.number_chance, 4),
            "confidence": round(self.confidence, 4),
            "bbox_px": [round(v, 2) for v in self.bbox_px],
            "contact_px": [round(v, 2) for v in self.contact_px],
            "table_xy_m": [round(v, 4) for v in self.table_xy_m],
            "env_xy_px": [round(v, 2) for v in self.env_xy_px],
            "position_sigma_m": self.position_sigma_m,
            "in_hand": self.in_hand,
        }


@dataclass(frozen=True, slots=True, eq=False)
class ShotAdvice:
    """The suggested shot, in the table frame.

    Attributes:
        target_ball: index into ``Suggestion.balls`` of the object ball (``None`` for a safety).
        pocket: pocket name (``TableSpec.pockets``), or ``None``.
        kind: ``direct``, ``bank``, ``kick`` or ``break`` (a racked table; ``None`` for a safety).
        cue_angle: stroke direction [rad], counter-clockwise from +x.
        speed: cue-ball speed [m/s].
        success_probability: the chance in [0, 1]: the measured fraction ``chance`` when there is one, else the
            planner's estimate (``None`` when it gives none).
        group: the group the shot was planned for.
        cue_path: the cue ball's planned path [m], (k, 2): cue ball, (cushion,) ghost ball.
        object_path: the object ball's planned path [m], (k, 2): ball, (cushion,) pocket.
        ghost: ghost-ball centre [m] (``None`` for a safety).
        safety: no pocketable shot was found; this is the planner's safe play.
        stroke: the full stroke (with tip offsets), for replaying in a simulator.
        chance: how ``success_probability`` was measured (successes, samples, noise, position error), or
            ``None`` for a planner's own estimate.
        chance_exact_positions: the same measurement with the balls exactly where they were located (the
            stroke's own risk, without the photo's position error), or ``None``.
        cue_after: where the cue ball goes once it meets the first ball, played exactly as planned [m], (k, 2): from
            that meeting point along the curves it runs (sampled every few centimetres) to where it stops, or drops
            when ``cue_pocketed``; ``None`` when the planner does not simulate.
        cue_pocketed: the planned stroke drops the cue ball (``cue_after`` ends at its pocket).
    """

    target_ball: int | None
    pocket: str | None
    kind: str | None
    cue_angle: float
    speed: float
    success_probability: float | None
    group: str
    cue_path: np.ndarray
    object_path: np.ndarray
    ghost: np.ndarray | None
    safety: bool = False
    stroke: Shot | None = None
    chance: Chance | None = None
    chance_exact_positions: Chance | None = None
    cue_after: np.ndarray | None = None
    cue_pocketed: bool = False

    @property
    def power_level(self) -> int:
        return power_level(self.speed)

    def to_dict(self) -> dict:
        p = self.success_probability
        return {
            "target_ball": self.target_ball,
            "pocket": self.pocket,
            "kind": self.kind,
            "cue_angle_deg": round(math.degrees(self.cue_angle) % 360.0, 3),
            "speed_mps": round(self.speed, 3),
            "power_level": self.power_level,
            "success_probability": None if p is None else round(p, 4),
            "success_text": self.chance_text,
            "success_chance": None if self.chance is None else self.chance.to_dict(),
            "success_chance_exact_positions": None
            if self.chance_exact_positions is None
            else self.chance_exact_positions.to_dict(),
            "group": self.group,
            "safety": self.safety,
            "tip_offset": None
            if self.stroke is None
            else {"side": round(self.stroke.side, 3), "height": round(self.stroke.height, 3)},
            "cue_ball_after": None
            if self.cue_after is None
            else {"path_m": np.round(self.cue_after, 4).tolist(), "pocketed": self.cue_pocketed},
        }

    @property
    def chance_text(self) -> str | None:
        """The chance for people (``">99%"``, ``"73%"``, ``"<1%"``; never 100% or 0%), ``None`` without one."""
        if self.chance is not None:
            return self.chance.text
        return None if self.success_probability is None else format_chance(self.success_probability)

    def describe(self, balls: tuple[LocatedBall, ...]) -> str:
        """One line for people: ball, pocket, kind, power, success chance (with its sample size when measured)."""
        chance = "" if self.chance_text is None else f", {self.chance_text} chance"
        if self.chance is not None:
            chance += f" (of {self.chance.samples} sampled strokes, {self.chance.noise})"
        if self.safety or self.target_ball is None:
            return f"No good pot for {self.group}: safe shot at power {self.power_level}/30{chance}"
        ball = balls[self.target_ball]
        x, y = ball.table_xy_m
        if self.kind == "break":
            potted = chance.replace(" chance", " chance to pot a ball and not the cue ball", 1)
            where = f"({x:.2f}, {y:.2f}) m"
            return f"Break: the cue ball full into the {ball.name} at {where}, power {self.power_level}/30{potted}"
        return (
            f"{ball.name} at ({x:.2f}, {y:.2f}) m -> {self.pocket} pocket, {self.kind}, "
            f"power {self.power_level}/30{chance} ({self.group})"
        )


@dataclass(frozen=True, slots=True, eq=False)
class Suggestion:
    """The photo pipeline's answer (``pix2pockets.suggest``).

    Not to be confused with :class:`pix2pockets.planner.Suggestion` (one planner candidate): this one
    holds everything found in the photo plus the chosen shot.

    Attributes:
        image_size: (width, height) [px].
        corners_px: the 4 playing-surface corners (cushion-nose rectangle on the cloth) [px], (4, 2), in
            ``TableSpec.corners`` order; NaN (JSON ``null``) for a corner behind the camera.
        homography: image pixels -> table metres on the cloth (3, 3).
        balls: the located balls.
        shot: the suggested shot.
        layout: the located layout (balls in ``balls`` order).
        camera: the recovered camera (for drawing in perspective).
        timings: seconds per stage.
        diamond_height_m: height of the diamond plane (rail cap) above the cloth used [m].
        diamond_height_measured: whether that height was measured from the photo (else assumed).
        table_source: what the table was fitted to: ``surface`` (the table model's playing surface), ``diamonds``,
            ``diamonds+surface`` (both, agreeing), ``cloth`` or ``diamonds+cloth``.
        size_source: where the table's size came from: ``given`` (the caller's table), ``balls`` (the balls'
            apparent size), ``diamonds`` or ``default`` (9-foot, nothing measured it).
        fit_error_px: root-mean-square reprojection error of the points the table was fitted to [px].
        ball_set: ``american`` (cue, solids, 8, stripes) or ``blackball`` (cue, reds, yellows, black); the balls'
            classes and the shot's group are named in it.
        evidence: the cues behind the fit: ``diamonds`` matched, the table model's ``corners`` and ``side_pockets``
            and the ``cushion_lines`` seen (0 without a surface), and the ``cloth_edges``: sides of the table's cloth
            outline moved onto the cloth's edge in the photo.
        table_in_view: share of the fitted playing surface inside the photo; below :data:`WHOLE_TABLE_IN_VIEW` the
            text says that part of the table (and any ball there) is not seen.
        ball_in_hand: ``table`` or ``baulk`` when the cue ball was in hand and placed by the planner (the last of
            ``balls``, ``in_hand`` set), ``None`` when it is played from where it lies.
    """

    image_size: tuple[int, int]
    corners_px: np.ndarray
    homography: np.ndarray
    balls: tuple[LocatedBall, ...]
    shot: ShotAdvice
    layout: TableLayout
    camera: PinholeCamera
    timings: dict = field(default_factory=dict)
    diamond_height_m: float | None = None
    diamond_height_measured: bool = False
    table_source: str = "diamonds"
    size_source: str = "given"
    fit_error_px: float | None = None
    evidence: dict = field(default_factory=dict)
    ball_set: str = "american"
    table_in_view: float = 1.0
    ball_in_hand: str | None = None

    def scaled(self, sx: float, sy: float, image_size: tuple[int, int]) -> Suggestion:
        """The same answer for the photo resized by ``sx`` across and ``sy`` down to ``image_size`` [px] (what is in
        pixels moves; the table, the balls on it and the shot stay)."""
        to_old = np.diag([1.0 / sx, 1.0 / sy, 1.0])  # new pixels -> the photo's
        homography = np.asarray(self.homography, dtype=float) @ to_old
        return replace(
            self,
            image_size=(int(image_size[0]), int(image_size[1])),
            corners_px=np.asarray(self.corners_px, dtype=float) * np.array([sx, sy]),
            homography=homography / homography[2, 2],
            balls=tuple(ball.scaled(sx, sy) for ball in self.balls),
            camera=self.camera.scaled(sx, sy, image_size),
        )

    @property
    def spec(self) -> TableSpec:
        return self.layout.spec

    @property
    def pixel_aspect(self) -> float:
        """Width over height of one pixel as the table fit found it: 1 for a photo as taken, 0.5625 for a 16:9
        frame stretched to a square."""
        K = getattr(self.camera, "K", None)
        return 1.0 if K is None else float(K[0, 0] / K[1, 1])

    @property
    def text(self) -> str:
        """One-line description of the shot."""
        text = self.shot.describe(self.balls)
        if self.ball_in_hand is not None:
            x, y = self.balls[-1].table_xy_m
            text = f"Ball in hand: cue ball at ({x:.2f}, {y:.2f}) m; {text}"
        if self.table_in_view < WHOLE_TABLE_IN_VIEW:
            out = 100 * (1 - self.table_in_view)
            text += f"; {out:.0f}% of the table is out of the photo: balls there are not seen"
            if self.pocket_in_view is False:
                text += ", and the pocket lies there, where the fit is least sure"
        return text

    @property
    def pocket_in_view(self) -> bool | None:
        """Whether the shot's pocket lies inside the photo (``None`` for a shot without one). A table cut by the frame
        is fitted well where the photo shows it and poorly where it does not (``benchmarks/cut_table_fit.py``: its
        unseen corners 0.15 m off, median), so a pocket out of the photo is the least sure part of a shot (its chance
        is measured with that error, :mod:`pix2pockets.pipeline.unseen_pockets`)."""
        if self.shot.pocket is None:
            return None
        return bool(pockets_in_photo(self.camera, self.spec, self.image_size)[self.spec.pocket_index(self.shot.pocket)])

    def to_dict(self) -> dict:
        """The JSON document of ``pix2pockets suggest --json``."""
        return {
            "image": {"width": int(self.image_size[0]), "height": int(self.image_size[1])},
            "table": {
                "spec": self.spec.name,
                "size": {
                    "name": self.spec.name,
                    "length_m": round(self.spec.length, 4),
                    "width_m": round(self.spec.width, 4),
                },
                "size_source": self.size_source,
                "source": self.table_source,
                "evidence": dict(self.evidence),
                "fit_error_px": None if self.fit_error_px is None else round(float(self.fit_error_px), 2),
                "corners_px": [
                    [round(float(v), 2) for v in c] if np.all(np.isfinite(c)) else None for c in self.corners_px
                ],
                "homography": [[float(v) for v in row] for row in self.homography],
                "diamond_height_m": None if self.diamond_height_m is None else round(float(self.diamond_height_m), 5),
                "diamond_height_measured": bool(self.diamond_height_measured),
                "pixel_aspect": round(self.pixel_aspect, 4),
                "in_view": round(float(self.table_in_view), 3),
            },
            "ball_set": self.ball_set,
            "ball_in_hand": self.ball_in_hand,
            "balls": [b.to_dict() for b in self.balls],
            "suggestion": {**self.shot.to_dict(), "pocket_in_view": self.pocket_in_view},
            "text": self.text,
        }

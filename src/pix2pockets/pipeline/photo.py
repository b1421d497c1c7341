"""Photo -> suggestion: detect, post-process, fit the table, locate the balls, plan.

Example:
    >>> import pix2pockets
    >>> s = pix2pockets.suggest("table.jpg", group="auto")  # doctest: +SKIP
    >>> s.text  # doctest: +SKIP
    '3 ball (solid) at (1.92, 0.41) m -> top-right pocket, direct, power 12/30, 81% chance (solids)'
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.raster import table_to_env_pixels
from pix2pockets.geometry.table import TableSpec, table_preset
from pix2pockets.pipeline.break_shot import OPEN_TABLE, behind_break_line, racked_balls
from pix2pockets.pipeline.planning import ShotPlanner, default_planner, place_in_hand, plan_shot, planner_for_set
from pix2pockets.pipeline.result import LocatedBall, Suggestion
from pix2pockets.pipeline.unseen_pockets import pocket_sigmas
from pix2pockets.rules import InHand
from pix2pockets.state.ball import BallClass
from pix2pockets.state.ball_set import BallSet, class_name, group_name, parse_ball_set, parse_group, set_of_group
from pix2pockets.state.layout import TableLayout
from pix2pockets.vision.classes import DETECTION_CAPS, ONE_PER_TABLE, ball_class_of
from pix2pockets.vision.detect.base import Detector
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.postprocess import DEFAULT_NMS_IOU, apply_caps, box_iou, resolve_ball_classes
from pix2pockets.vision.image_io import capped_size, read_image_rgb
from pix2pockets.vision.locate.balls import LocatedBalls, LocateMethod, locate_balls, on_the_table, sphere_boxes
from pix2pockets.vision.locate.position_error import position_covariances, position_sigmas
from pix2pockets.vision.locate.visibility import unexplained_shortfall
from pix2pockets.vision.stages.ball_classifier import NUMBER_PROBS
from pix2pockets.vision.stages.ball_colours import BALL_COLOUR, RED, YELLOW, blackball_classes, read_ball_set
from pix2pockets.vision.stages.ball_numbers import BallNumberReader, assign_numbers
from pix2pockets.vision.table.errors import TableFitError, photo_pixels
from pix2pockets.vision.table.estimate import estimate_table, outline_used
from pix2pockets.vision.table.fit import TableFit
from pix2pockets.vision.table.keypoints import TableCues, TableModel
from pix2pockets.vision.table.pixel_aspect import EXPORT_ASPECTS, snapped_aspect
from pix2pockets.vision.table.quad_geometry import share_in_frame
from pix2pockets.vision.table.rail_height import refine_fit_height
from pix2pockets.vision.table.surface import SurfaceOutline, surface_outline

MIN_IMAGE_SIDE = 64  # [px]
MIN_TABLE_IN_VIEW = 0.5
"""A table fit with less than this share of its playing surface inside the photo is refused: half the table or more
is out of frame, and no one could place it from what shows."""
# Minimum confidence per class id (cue, black, solid, stripe, diamond). Cue and black are capped at one
# detection each by post-processing, so a lower bar costs at most one false ball and keeps a faint cue.
MIN_CONFIDENCE = np.array([0.15, 0.15, 0.3, 0.3, 0.25])
SURE_BALL_SCORE = 0.45
"""A ball whose "any ball" score (``Detections.ball_score``) reaches this is kept whatever its class scores: on real
photos the detector's class heads and the ball classifier often disagree about a ball (a real 8 the classifier is
sure of, the black head not), and their joint class score then falls under :data:`MIN_CONFIDENCE` although the ball
is plainly there (``docs/benchmarks-detector.md``)."""
SET_VOTE_MARGIN = 0.0075
"""How far off the table model's playing surface a ball still reads the ball set, as a share of the photo's longer side
(a ball on the cushion's edge, or the surface read a little short)."""
LOOSE_OBJECT_CAPS = (*DETECTION_CAPS[:2], 14, 14, *DETECTION_CAPS[4:])
"""Caps while a blackball set's object balls are still to be named by colour: room for all 14 in either class."""
COLOURED_BALL_SCORE = 0.15
"""In a blackball set a detection this sure whose middle is clearly red or yellow is a ball: its colour is the
evidence the detector's solid and stripe heads lack for a plain red or yellow ball."""
FIT_MAX_SIDE = 1920
"""Longer side [px] of the copy of a larger photo that the table is found on: the fit's pixel steps and tolerances
hold from 640 px to 1080p, and a 12 MP photo is fitted as fast as a 1080p frame."""


@functools.lru_cache(maxsize=1)
def default_detector() -> Detector:
    """The bundled ONNX detector, loaded once per process.

    Raises:
        ValueError: when the model file is missing or unreadable.
    """
    from pix2pockets.vision.detect.onnx_detector import OnnxDetector

    try:
        return OnnxDetector.from_default()
    except ValueError as err:
        raise ValueError(
            f"{err} (pass a model with --model / detector=, or train one: pix2pockets train-detector)"
        ) from None


@functools.lru_cache(maxsize=1)
def default_number_reader() -> BallNumberReader | None:
    """The bundled ball-number reader, loaded once per process; None in a checkout without its weights (the
    suggestion then names balls by class only)."""

    return BallNumberReader.from_option(None)


def load_image(image: str | Path | np.ndarray) -> np.ndarray:
    """An RGB uint8 image (H, W, 3) from a path or an array, with clear errors."""
    if isinstance(image, (str, Path)):
        rgb = read_image_rgb(image)
    else:
        rgb = np.asarray(image)
        if rgb.ndim == 2:
            rgb = np.repeat(rgb[:, :, None], 3, axis=2)
        if rgb.dtype != np.uint8 or rgb.ndim != 3 or rgb.shape[2] not in (3, 4):
            raise ValueError(f"expected an RGB uint8 image (H, W, 3), got {rgb.dtype} {rgb.shape}")
        rgb = rgb[:, :, :3]
    h, w = rgb.shape[:2]
    if min(h, w) < MIN_IMAGE_SIDE:
        raise ValueError(f"image is too small ({w}x{h} px); need at least {MIN_IMAGE_SIDE} px per side")
    return np.ascontiguousarray(rgb)


def clean_detections(raw: Detections) -> Detections:
    """Post-process raw detections (class-aware grouping, NMS, caps), then per-class confidence thresholds.

    A ball is kept by its best raw score of any class: a ball that lost the cue to a surer ball keeps a low
    stripe score, but it is still a ball on the table (and an obstacle to plan around). A ball whose "any ball"
    score reaches :data:`SURE_BALL_SCORE` is kept whatever its class scores.
    """
    return _confident(resolve_ball_classes(raw), raw)


def clean_detections_for_set(
    raw: Detections, rgb: np.ndarray, ball_set: BallSet | str = "auto", surface_mask: np.ndarray | None = None
) -> tuple[Detections, BallSet]:
    """:func:`clean_detections` for a ball set, or the set read from the photo (``auto``).

    A blackball set's 14 object balls may all look solid to the detector: they are grouped with room for all of
    them, named red or yellow by colour (:mod:`pix2pockets.vision.stages.ball_colours`) and only then capped at 7
    of each; a clearly red or yellow ball is kept from a lower score (:data:`COLOURED_BALL_SCORE`). With the table
    model's ``surface_mask`` (H, W) (:func:`playing_surface`), only the balls on the playing surface (within
    :data:`SET_VOTE_MARGIN`) read the set: chalk on the rails, balls in a ball return and things beside the table
    do not. Returns the detections and the set.
    """
    if ball_set != "auto" and parse_ball_set(ball_set) is BallSet.AMERICAN:
        return clean_detections(raw), BallSet.AMERICAN
    loose = resolve_ball_classes(raw, caps=LOOSE_OBJECT_CAPS)
    if ball_set == "auto":
        voters = loose if surface_mask is None else loose[~loose.is_ball | on_surface(loose.centres, surface_mask)]
        chosen = read_ball_set(rgb, voters)
    else:
        chosen = BallSet.BLACKBALL
    if chosen is BallSet.AMERICAN:
        return clean_detections(raw), chosen
    named = apply_caps(blackball_classes(rgb, loose))
    coloured = np.isin(named.data[BALL_COLOUR], (RED, YELLOW)) & (named.confidence >= COLOURED_BALL_SCORE)
    return _confident(named, raw, coloured), chosen


def _confident(det: Detections, raw: Detections, keep: np.ndarray | None = None) -> Detections:
    """The resolved detections whose score (a ball's best raw score of any class) passes its class's floor, and
    those ``keep`` (n,) marks."""
    score = det.confidence
    balls = raw[raw.is_ball]
    if len(det) and len(balls):
        overlap = box_iou(det.boxes, balls.boxes) >= DEFAULT_NMS_IOU
        best_raw = np.where(overlap, balls.own_score[None, :], 0.0).max(axis=1)
        score = np.where(det.is_ball, np.maximum(score, best_raw), score)
    sure_ball = det.is_ball & (np.nan_to_num(det.ball_score, nan=0.0) >= SURE_BALL_SCORE)
    if keep is not None:
        sure_ball |= keep
    return det[(score >= MIN_CONFIDENCE[det.class_id]) | sure_ball]


@functools.lru_cache(maxsize=1)
def default_table_model() -> TableModel | None:
    """The bundled table model, loaded once per process; None in a checkout without its weights."""
    return TableModel.from_option(None)


def table_cues(rgb: np.ndarray, table_model: TableModel | bool | None) -> TableCues | None:
    """What the table model reads in the photo (None without a model: ``False`` or ``None``, or a checkout without
    its weights; ``True``: the bundled one)."""
    model = default_table_model() if table_model is True else table_model or None
    return None if model is None else model.read(rgb)


def playing_surface(rgb: np.ndarray, table_model: TableModel | bool | None) -> np.ndarray | None:
    """The table model's playing-surface mask (H, W) uint8 of the photo (None without a model)."""
    cues = table_cues(rgb, table_model)
    return None if cues is None else cues.surface_mask()


def on_surface(centres: np.ndarray, surface_mask: np.ndarray) -> np.ndarray:
    """Which points (n, 2) [px] lie on the surface mask (H, W) grown by :data:`SET_VOTE_MARGIN` of its longer side."""
    h, w = surface_mask.shape
    k = 2 * max(1, round(SET_VOTE_MARGIN * max(w, h))) + 1
    grown = cv2.dilate(np.asarray(surface_mask, dtype=np.uint8), np.ones((k, k), np.uint8))
    xy = np.round(np.asarray(centres, dtype=float).reshape(-1, 2)).astype(int)
    inside = (xy[:, 0] >= 0) & (xy[:, 0] < w) & (xy[:, 1] >= 0) & (xy[:, 1] < h)
    out = np.zeros(len(xy), dtype=bool)
    out[inside] = grown[xy[inside, 1], xy[inside, 0]] > 0
    return out


def read_surface(
    rgb: np.ndarray, det: Detections, table_model: TableModel | bool | None, cues: TableCues | None = None
) -> SurfaceOutline | None:
    """The playing surface the table model sees (None without a model or without a surface in the photo); ``cues``:
    the model's reading of the photo when it was read before."""
    cues = cues if cues is not None else table_cues(rgb, table_model)
    if cues is None:
        return None
    try:
        return surface_outline(cues, det[det.is_ball].centres)
    except TableFitError:
        return None


def fit_evidence(fit: TableFit, surface: SurfaceOutline | None) -> dict[str, int]:
    """The cues behind a table fit: diamonds matched, and the table model's corners, side pockets and cushion
    lines when the fit used its surface, with the sides moved onto the cloth's edge in the photo."""
    used = surface is not None and "surface" in fit.source
    if used:
        surface = outline_used(fit, surface)
    return {
        "diamonds": int(fit.n_matched),
        "corners": int(surface.from_peak.sum()) if used else 0,
        "side_pockets": int((surface.side_pocket >= 0.5).sum()) if used else 0,
        "cushion_lines": int(surface.seen.sum()) if used else 0,
        "cloth_edges": int(fit.cloth_edges),
    }


def read_numbers(
    rgb: np.ndarray, balls: Detections, number_reader: BallNumberReader | bool | None
) -> list[tuple[int | None, float | None]]:
    """Each ball's number (0-15) and its chance, ``(None, None)`` where unknown.

    ``number_reader`` True reads what the detector measured (``data["number_probs"]``) or, when it measured no
    numbers, the bundled reader; a reader reads the balls itself; False or None names no numbers.
    """
    numbers = chances = None
    probs = balls.data.get(NUMBER_PROBS)
    if number_reader is True and probs is not None and len(balls) and np.all(np.isfinite(probs)):
        numbers, chances = assign_numbers(probs, balls.class_id)
    else:
        reader = default_number_reader() if number_reader is True else number_reader or None
        if reader is not None and len(balls):
            numbers, chances = reader.numbers(rgb, balls.boxes, balls.class_id, balls.pixel_aspect)
    if numbers is None:
        return [(None, None)] * len(balls)
    return [(int(n), float(c)) if n >= 0 else (None, None) for n, c in zip(numbers, chances, strict=True)]


def fit_copy(rgb: np.ndarray, pixel_aspect: float | None = None) -> tuple[np.ndarray, float, float]:
    """The photo the table is fitted on, with the scales across and down from the photo to it: the photo itself, or
    a copy. A photo squashed by an export (``pixel_aspect``, as the balls show it, one of the usual export stretches)
    is stretched back along its squashed side, so that the table model sees the table as the camera did; a copy
    longer than :data:`FIT_MAX_SIDE` is then shrunk to that."""
    h, w = rgb.shape[:2]
    width, height = float(w), float(h)
    aspect = snapped_aspect(float(pixel_aspect)) if pixel_aspect else 1.0
    if aspect in EXPORT_ASPECTS and aspect != 1.0:  # balls read narrower than tall: the width was squashed
        width, height = (width / aspect, height) if aspect < 1.0 else (width, height * aspect)
    size = capped_size(width, height, FIT_MAX_SIDE)
    if size == (w, h):
        return rgb, 1.0, 1.0
    larger = size[0] * size[1] > w * h
    copy = cv2.resize(rgb, size, interpolation=cv2.INTER_CUBIC if larger else cv2.INTER_AREA)
    return copy, size[0] / w, size[1] / h


def measure_diamond_height(rgb: np.ndarray, fit: TableFit, ball_boxes: np.ndarray) -> tuple[TableFit, bool]:
    """The fit with its diamond-plane height measured from the cushion noses in the photo (:func:`refine_fit_height`,
    on the copy the table was fitted on), and whether it was measured (else the fit as it was)."""
    small, sx, sy = fit_copy(rgb)
    size = (small.shape[1], small.shape[0])
    _, est = refine_fit_height(small, fit.scaled(sx, sy, size), ball_boxes * np.array([sx, sy, sx, sy]))
    return (fit.with_diamond_z(est.diamond_z), True) if est.measured else (fit, False)


def find_table(
    rgb: np.ndarray,
    raw: Detections,
    spec: TableSpec | None = None,
    table_model: TableModel | bool | None = True,
    ball_set: BallSet | str = "auto",
) -> tuple[Detections, BallSet, SurfaceOutline | None, TableFit]:
    """The photo's balls post-processed for its ball set, the set, the playing surface the table model sees and the
    table fitted to them, as :func:`suggest` finds them.

    Args:
        rgb: the photo, RGB uint8 (H, W, 3).
        raw: the detector's raw detections of it.
        spec: the table; ``None`` measures its size from the balls (a blackball set's 2 in balls measure a UK table).
        table_model: as in :func:`suggest`.
        ball_set: ``american``, ``blackball`` or ``auto`` (read from the balls' colours).

    The table is searched on :func:`fit_copy` of the photo (a squashed export stretched back, a photo larger than
    :data:`FIT_MAX_SIDE` shrunk to that), and what is found there is scaled back to the photo's pixels, as are the
    lengths an error gives.

    Raises:
        TableFitError: no table found in the photo (a ``ValueError``).
    """
    h, w = rgb.shape[:2]
    copy, sx, sy = fit_copy(rgb, raw.pixel_aspect)
    if copy is rgb:
        return _find_table(rgb, raw, spec, table_model, ball_set)
    with photo_pixels(1 / math.sqrt(sx * sy)):  # the reasons for no table give the photo's own pixels
        det, chosen, surface, fit = _find_table(copy, raw.scaled(sx, sy), spec, table_model, ball_set)
    surface = None if surface is None else surface.scaled(1 / sx, 1 / sy, (w, h))
    return det.scaled(1 / sx, 1 / sy), chosen, surface, fit.scaled(1 / sx, 1 / sy, (w, h))


def _find_table(
    rgb: np.ndarray,
    raw: Detections,
    spec: TableSpec | None,
    table_model: TableModel | bool | None,
    ball_set: BallSet | str,
) -> tuple[Detections, BallSet, SurfaceOutline | None, TableFit]:
    """:func:`find_table` at the photo's own resolution."""
    h, w = rgb.shape[:2]
    cues = table_cues(rgb, table_model)
    det, chosen = clean_detections_for_set(raw, rgb, ball_set, None if cues is None else cues.surface_mask())
    surface = read_surface(rgb, det, table_model, cues)
    base = table_preset("uk7") if chosen is BallSet.BLACKBALL else None  # 2 in balls measure a UK table
    fit = estimate_table(rgb, det, (w, h), spec, pixel_aspect=det.pixel_aspect, surface=surface, base=base)
    return det, chosen, surface, fit


def suggest(
    image: str | Path | np.ndarray,
    group: str = "auto",
    detector: Detector | None = None,
    planner: ShotPlanner | None = None,
    spec: TableSpec | None = None,
    locate_method: LocateMethod | str = LocateMethod.SPHERE,
    rng: np.random.Generator | None = None,
    measure_rail_height: bool = True,
    number_reader: BallNumberReader | bool | None = True,
    skill: str = "pro",
    table_model: TableModel | bool | None = True,
    ball_set: BallSet | str = "auto",
    ball_in_hand: InHand | str | None = None,
) -> Suggestion:
    """The best shot for a photo of a pool table.

    Args:
        image: a path to an image file, or an RGB uint8 array (H, W, 3).
        group: ``solids``, ``stripes``, ``reds``, ``yellows`` or ``auto`` (the group with the better shot).
        detector: the detector (default: the bundled ONNX model).
        planner: the shot planner (default: :func:`pix2pockets.pipeline.planning.default_planner`).
        spec: the table; ``None`` (default) measures its size from the balls when the table is found without
            diamonds (``table.size_source`` in the JSON says how it was found), else 9-foot.
        locate_method: ball location method (``sphere``, ``contact`` or ``linear``).
        rng: randomness for the planner (a fixed seed when ``None``).
        measure_rail_height: measure the diamond-plane height above the cloth from the cushion noses
            (:mod:`pix2pockets.vision.table.rail_height`); otherwise the typical height is assumed.
        number_reader: reads each ball's number (``True``: the numbers the detector read, like the bundled ONNX
            detector, else the bundled reader when present; a reader: that reader; ``False`` or ``None``: balls are
            named by class only).
        skill: the player's skill level the default planner plans for and measures the chance with (``pro``,
            ``club``, ``beginner`` or a noise ``FILE.json``; ignored when ``planner`` is given).
        table_model: finds the playing surface, its corners and side pockets (``True``: the bundled model when
            present; ``False`` or ``None``: the table is fitted to the diamonds and the cloth's colour only).
        ball_set: ``american``, ``blackball`` or ``auto`` (read from the balls' colours; a group of one set, such as
            ``reds``, names the set).
        ball_in_hand: ``table`` or ``baulk``: the player has the cue ball in hand (after a foul) and may put it
            anywhere free on the table, or behind the baulk line; the photo's cue ball, if any, is picked up and the
            planner places it (:func:`~pix2pockets.pipeline.planning.place_in_hand`). ``None`` or ``none``: the cue
            ball is played from where it lies in the photo; a rack is broken from hand when the photo's cue ball is
            not where the break is played from (:func:`breaks_from_hand`).

    Raises:
        ValueError: unreadable image, no table found, too few table points, no cue ball, no balls of the
            group, an unknown ``ball_in_hand`` (with a one-line reason).
    """
    in_hand = parse_in_hand(ball_in_hand)
    given_spec = spec is not None
    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    rgb = load_image(image)
    h, w = rgb.shape[:2]
    timings["load"] = time.perf_counter() - t0

    t = time.perf_counter()
    detector = detector or default_detector()
    raw = detector.detect(rgb)
    timings["detect"] = time.perf_counter() - t

    t = time.perf_counter()
    if ball_set == "auto":  # a group of one set names the set
        ball_set = set_of_group(group) or ball_set
    det, chosen, surface, fit = find_table(rgb, raw, spec, table_model, ball_set)
    wanted = parse_group(group, chosen)
    spec = fit.spec
    in_view = share_in_frame(fit.corners_px, (w, h))
    if in_view < MIN_TABLE_IN_VIEW:
        raise ValueError(
            f"no table found: only {100 * in_view:.0f}% of the table fitted to the photo lies in it, so the fit is "
            "a guess (show the whole table: its cloth with the four cushions and pockets)"
        )
    timings["fit"] = time.perf_counter() - t

    t = time.perf_counter()
    measured = False
    if measure_rail_height and fit.source.startswith("diamonds"):  # the cloth lies below the diamonds: how far
        fit, measured = measure_diamond_height(rgb, fit, det[det.is_ball].boxes)
    timings["rail_height"] = time.perf_counter() - t

    t = time.perf_counter()
    located = balls_in_play(raw, det, rgb, chosen, fit, locate_method)
    layout = located.to_layout(spec)
    kept = located.detections
    contact_px = located.contact_px
    if not len(layout):
        raise ValueError(
            "no balls found on the table: the table was found but no ball lies on it (photograph it with the balls "
            "in play, or racked for the break)"
        )
    if in_hand is InHand.NONE and breaks_from_hand(layout, chosen):
        in_hand = break_area(chosen)
    if in_hand is not InHand.NONE and layout.cue_index is not None:  # picked up, to be placed
        seen = [i for i in range(len(layout)) if i != layout.cue_index]
        layout, kept, contact_px = layout.without([layout.cue_index]), kept[np.array(seen, dtype=int)], contact_px[seen]
    if layout.cue_index is None and in_hand is InHand.NONE:
        raise ValueError(no_cue_ball_reason(det))
    timings["locate"] = time.perf_counter() - t

    t = time.perf_counter()
    read = read_numbers(rgb, kept, number_reader if chosen is BallSet.AMERICAN else None)
    timings["numbers"] = time.perf_counter() - t

    t = time.perf_counter()
    planner = planner_for_set(planner or default_planner(skill=skill), chosen)
    group_asked = wanted if wanted == "auto" else wanted.value
    shortfall = unexplained_shortfall(fit.camera, kept.boxes, layout.positions[: len(kept)], spec.ball_radius, spec)
    position_cov = position_covariances(fit.camera, layout.positions, spec.ball_radius, fit.rms_px, shortfall)
    if in_hand is not InHand.NONE:  # placed for the better group when asked for either: the shot is for that one
        layout, placed_for = place_in_hand(layout, group_asked, planner, in_hand, rng)
        group_asked = placed_for.value
        position_cov = np.concatenate([position_cov.reshape(-1, 2, 2), np.zeros((1, 2, 2))])  # put there exactly
    unseen = pocket_sigmas(fit.camera, spec, (w, h))
    advice = plan_shot(layout, group_asked, planner, rng, position_sigma=position_cov, pocket_sigma=unseen)
    if advice.group != OPEN_TABLE:
        advice = replace(advice, group=group_name(advice.group, chosen))
    timings["plan"] = time.perf_counter() - t

    balls = tuple(
        LocatedBall(
            class_name(ball_class_of(int(c)), chosen),
            float(conf),
            tuple(float(v) for v in box),
            tuple(float(v) for v in contact),
            tuple(float(v) for v in xy),
            tuple(float(v) for v in table_to_env_pixels(xy, spec)),
            number,
            chance,
            round(float(sigma), 4),
        )
        for c, conf, box, contact, xy, (number, chance), sigma in zip(
            kept.class_id,
            kept.confidence,
            kept.boxes,
            contact_px,
            layout.positions[: len(kept)],  # a cue ball in hand, placed last, is no detection
            read,
            position_sigmas(position_cov)[: len(kept)],
            strict=True,
        )
    )
    if in_hand is not InHand.NONE:
        balls = (*balls, placed_cue_ball(fit.camera, layout.positions[-1], spec))
    timings["total"] = time.perf_counter() - t0
    return Suggestion(
        (w, h),
        fit.corners_px,
        fit.homography,
        balls,
        advice,
        layout,
        fit.camera,
        timings,
        fit.diamond_z if fit.source.startswith("diamonds") else None,
        measured,
        fit.source,
        "given" if given_spec else fit.size_source,
        float(fit.rms_px) if np.isfinite(fit.rms_px) else None,
        fit_evidence(fit, surface),
        chosen.value,
        in_view,
        None if in_hand is InHand.NONE else in_hand.value,
    )


def parse_in_hand(ball_in_hand: InHand | str | None) -> InHand:
    """Where the cue ball may be put: ``table`` or ``baulk`` (ball in hand), ``none``/``None`` (where it lies).

    Raises:
        ValueError: another name.
    """
    if ball_in_hand is None:
        return InHand.NONE
    try:
        return InHand(str(ball_in_hand).strip().lower())
    except ValueError:
        choices = ", ".join(a.value for a in InHand)
        raise ValueError(f"unknown ball in hand {str(ball_in_hand)[:40]!r}; choose {choices}") from None


def breaks_from_hand(layout: TableLayout, ball_set: BallSet) -> bool:
    """Whether the photo's balls are a rack broken with the cue ball in hand: no cue ball on the table (the breaker
    holds it), or one outside the area the break is played from (:func:`break_area`), which the breaker picks up."""
    if not len(racked_balls(layout)):
        return False
    cue = layout.cue_index
    return cue is None or not behind_break_line(layout, layout.positions[cue], break_area(ball_set))


def break_area(ball_set: BallSet) -> InHand:
    """Where the cue ball is put by hand for the break: behind the baulk line for a blackball set (WEPF / EPA), on
    the head string otherwise (the kitchen of American 8-ball; :func:`~pix2pockets.pipeline.break_shot.break_spot`
    puts it on the head string for ``InHand.TABLE``)."""
    return InHand.BAULK if ball_set is BallSet.BLACKBALL else InHand.TABLE


def placed_cue_ball(camera: PinholeCamera, xy: np.ndarray, spec: TableSpec) -> LocatedBall:
    """The cue ball put at ``xy`` [m] by ball in hand, as a located ball: its box and contact point where it would
    be seen in the photo."""
    r = spec.cue_radius
    box = sphere_boxes(camera, np.array([xy[0], xy[1], r]), r)[0]
    return LocatedBall(
        "cue",
        1.0,
        tuple(float(v) for v in box),
        tuple(float(v) for v in camera.project_table(xy, 0.0)),
        tuple(float(v) for v in xy),
        tuple(float(v) for v in table_to_env_pixels(xy, spec)),
        0,
        1.0,
        0.0,
        in_hand=True,
    )


def balls_in_play(
    raw: Detections,
    det: Detections,
    rgb: np.ndarray,
    ball_set: BallSet,
    fit: TableFit,
    method: LocateMethod | str = LocateMethod.SPHERE,
    drop_small: bool = True,
) -> LocatedBalls:
    """The balls on a fitted table, located (:func:`locate_balls`; ``drop_small`` as there).

    The raw detections on its playing surface (:func:`on_the_table`) are post-processed again for the ball set
    (:func:`clean_detections_for_set`), so that the cue ball and the 8 are claimed among the balls in play: a
    pocket's mouth or a ball on a rail takes neither from them. Where that names a cue ball or an 8 less surely than
    its class's floor (:data:`MIN_CONFIDENCE`: the claim would rest on nothing), the photo's balls as post-processed
    before the fit (``det``) are located instead.
    """
    spec = fit.spec
    on_table = on_the_table(fit.camera, raw, spec, method, diamond_z=fit.diamond_z)
    in_play, _ = clean_detections_for_set(raw[on_table], rgb, ball_set.value)
    one_per_table = in_play.is_ball & np.isin(in_play.class_id, ONE_PER_TABLE)
    if np.any(one_per_table & (in_play.confidence < MIN_CONFIDENCE[in_play.class_id])):
        in_play = det
    return locate_balls(fit.camera, in_play, spec, method, diamond_z=fit.diamond_z, drop_small=drop_small)


def no_cue_ball_reason(detections: Detections) -> str:
    """Why a photo's balls hold no cue ball on the fitted table, and what to do: none detected, or one detected off
    the table the fit found (or in a pocket)."""
    balls = detections[detections.is_ball]
    if not any(ball_class_of(int(c)) is BallClass.CUE for c in balls.class_id):
        return (
            "no cue ball found on the table: none was seen in the photo (is it in view, not hidden by a player? With "
            "the cue ball in hand, ask for ball in hand)"
        )
    return (
        "no cue ball found on the table: the cue ball seen in the photo lies off the table found there, or in a "
        "pocket (the table fit may be off: show the whole table with its four cushions, or give the table's size)"
    )

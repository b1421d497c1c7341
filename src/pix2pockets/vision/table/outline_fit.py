"""The table from its cloth outline: which sides are the long rails, the camera, the table's size.

The cloth outline's corners give a camera (:mod:`pix2pockets.vision.table.outline_camera`: the outline is a
rectangle ``CUSHION_WIDTH`` outside the playing surface at the cushion height). Four corners do not say which sides
are the long rails. Both assignments are tried and scored by
:func:`~pix2pockets.vision.table.outline_camera.rectangle_cost`: a camera must see the sides at right angles and in
the table's proportions (the two rotation constraints of a plane homography must agree for a plausible focal
length). Side pockets (a dark notch in the middle of a long cushion), diamonds, the balls (on the table, of the right
size when the table is given) and the cloth region itself add evidence. The 180-degree ambiguity is settled by the
head-rail convention of :mod:`pix2pockets.vision.table.fit`.

A table cut by the frame edge shows three cushions. Three lines and a focal length fix the camera too
(:func:`~pix2pockets.vision.table.outline_camera.complete_three_lines`): the two side lines meet at the vanishing
point of their direction, the middle line holds the other direction, at right angles to it through the camera, and
the table's known proportions place the missing side. The focal length then comes from a prior, the balls (all on
the table) and the cloth (inside it).

A close view across the table shows only its two long cushions. Their lines, the side pockets on them and a corner
fix the table too (:func:`fit_two_cushions`, through
:func:`~pix2pockets.vision.table.two_cushions.complete_two_long_cushions`): two pockets and a corner fix the focal
length as well; with two marks it comes from the same prior, the balls and the cloth.

Without diamonds a photo fixes the table only up to scale: its size comes from the balls
(:mod:`pix2pockets.vision.table.table_size`).

Photos squashed by an export (a 16:9 frame stretched to 640x640) are fitted with the pixel aspect the balls show, or
with each usual export stretch on a square photo, weighed by the ball boxes' shape.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import cv2
import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.homography import camera_tilt
from pix2pockets.geometry.table import TableSpec
from pix2pockets.vision.table.errors import TableFitError, counted, in_photo_px
from pix2pockets.vision.table.fit import TableFit, diamond_height, validate_corners
from pix2pockets.vision.table.outline_camera import (
    CUSHION_WIDTH,
    FOCAL_RANGE,
    camera_from_outline,
    complete_three_lines,
    head_rail_convention,
    outline_rectangle,
    quick_camera,
    stretched,
)
from pix2pockets.vision.table.pixel_aspect import EXPORT_ASPECTS, median_box_aspect
from pix2pockets.vision.table.quad_geometry import line_through, quad_mask
from pix2pockets.vision.table.table_size import size_from_balls, spec_of_length
from pix2pockets.vision.table.two_cushions import CushionMark, complete_two_long_cushions

THREE_LINE_FOCALS = (0.55, 0.7, 0.9, 1.15, 1.5, 2.0)
"""Focal lengths tried with three cushions, as multiples of the larger (unstretched) image side."""
THREE_LINE_FOCAL_SIGMA = 0.35  # prior on the log focal length (around 0.9 image sides) when only three cushions show
THREE_LINE_FOCAL = 0.9
MIN_CAMERA_HEIGHT = 0.05
"""Least height of the fitted camera above the cushion tops [m]: a phone held at the rail's height (a low view along
the table, the lens 5-20 cm over the cloth) still sees the playing surface."""
TOP_VIEW_DEG = 20.0
"""Camera tilts from straight down below this are top views ..."""
TOP_VIEW_BALLS = 3
"""... which need this many balls on the table to be believed."""
MAX_TRIED = 4  # best hypotheses checked for a plausible camera before giving up
MAX_RECTANGLE_COST = 40.0
"""Largest :func:`rectangle_cost` of an accepted outline (a quadrilateral no camera sees as a table: a window, a
picture, a wall)."""
POCKET_WEIGHT = 0.15  # cost per unit of side-pocket darkness difference (Lab lightness) between the two assignments
BALL_SIZE_SIGMA = 0.15  # expected error of the log table scale from the balls
ASPECT_SIGMA = 0.12  # expected error of the log pixel aspect read from the ball boxes
UNSEEN_ASPECT_COST = 3.0  # prior cost of an export stretch on a square photo whose balls do not show it
BALL_OFF_COST = 4.0  # cost of each ball the table would leave off its playing surface
FILL_SIGMA = 0.08  # expected shortfall of the cloth region filling the table's outline (occluders, pockets)
SPILL_SIGMA = 0.03  # expected share of the cloth region outside the table's outline
COVERAGE_SIDE = 96  # [px] longer side of the grid the cloth region is compared with the outline on


# ----------------------------------------------------------------------------- evidence
def _aspect_hypotheses(
    pixel_aspect: float | None, image_size: tuple[int, int], boxes: np.ndarray
) -> list[tuple[float, float]]:
    """Pixel aspects to try, each with its prior cost: the given one alone; else, for a square photo (the shape
    exports squash to), the usual export stretches weighed by the ball boxes' median aspect."""
    if pixel_aspect is not None:
        return [(float(pixel_aspect), 0.0)]
    w, h = image_size
    if abs(w - h) > 0.01 * max(w, h):
        return [(1.0, 0.0)]
    measured = median_box_aspect(boxes) if len(boxes) >= 3 else None
    if measured is not None:
        return [(a, (math.log(a / measured) / ASPECT_SIGMA) ** 2) for a in EXPORT_ASPECTS]
    return [(a, 0.0 if a == 1.0 else UNSEEN_ASPECT_COST) for a in EXPORT_ASPECTS]


@dataclass(frozen=True, slots=True)
class _Evidence:
    """What the photo offers besides the outline, in the unstretched frame of one pixel-aspect hypothesis."""

    ball_centres: np.ndarray  # (n, 2) [px]
    boxes: np.ndarray  # (n, 4) [px], the photo's own frame
    image_size: tuple[int, int]  # the photo's own (width, height) [px]
    diamonds: np.ndarray  # (m, 2) [px]
    darkness: np.ndarray | None  # (4,) per cloth side
    coverage: np.ndarray | None  # cloth region on a small grid, float 0-1
    grid_scale: tuple[float, float]  # unstretched px -> grid px


def _coverage_cost(quad: np.ndarray, ev: _Evidence) -> float:
    """How badly the cloth region and the table's outline ``quad`` [px] disagree: the outline's part inside the photo
    must be filled by the cloth, and the cloth must lie inside the outline."""
    if ev.coverage is None:
        return 0.0
    grid = ev.coverage
    poly = quad * np.array(ev.grid_scale)
    if not np.all(np.isfinite(poly)) or np.abs(poly).max() > 1e5:
        return math.inf
    inside = quad_mask(poly, grid.shape)
    area = float(inside.sum())
    cloth = float(grid.sum())
    if area <= 0 or cloth <= 0:
        return math.inf
    fill = float(grid[inside].sum()) / area
    spill = float(grid[~inside].sum()) / cloth
    return (max(0.0, 0.9 - fill) / FILL_SIGMA) ** 2 + (spill / SPILL_SIGMA) ** 2


def _balls_off(camera: PinholeCamera, centres: np.ndarray, spec: TableSpec) -> int:
    if not len(centres):
        return 0
    H = np.linalg.inv(camera.table_homography(spec.ball_radius))
    xy = centres @ H[:, :2].T + H[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        xy = xy[:, :2] / xy[:, 2:]
    on = np.all(np.isfinite(xy), axis=1) & spec.contains(np.nan_to_num(xy, nan=-1e9), margin=-0.03)
    return int((~on).sum())


def _diamond_matches(camera: PinholeCamera, diamonds: np.ndarray, spec: TableSpec, tol_px: float) -> int:
    if not len(diamonds):
        return 0
    proj = camera.project_table(spec.diamonds, diamond_height(spec))
    d = np.linalg.norm(diamonds[:, None, :] - proj[None], axis=-1)
    return int(np.sum(np.min(np.nan_to_num(d, nan=np.inf), axis=1) < tol_px))


@dataclass(frozen=True, slots=True)
class _Hypothesis:
    cost: float
    rect_cost: float
    quad: np.ndarray  # table corner order, unstretched px
    aspect: float
    camera: PinholeCamera  # unstretched
    three_lines: bool


def _score(
    quad: np.ndarray,
    camera: PinholeCamera,
    rect_cost: float,
    long_sides_first: bool,
    spec: TableSpec,
    given: bool,
    ev: _Evidence,
    aspect: float,
    tol: float,
) -> float:
    """The evidence cost of one hypothesis (lower is better)."""
    cost = rect_cost + BALL_OFF_COST * _balls_off(camera, ev.ball_centres, spec)
    if ev.darkness is not None:
        d = ev.darkness if long_sides_first else np.roll(ev.darkness, -1)
        cost -= POCKET_WEIGHT * float(np.clip(d[0] + d[2] - d[1] - d[3], -40, 40))
    if given and len(ev.boxes):
        k = size_from_balls(stretched(camera, aspect, ev.image_size), ev.boxes, spec, aspect)
        if k is not None:
            cost += (math.log(k) / BALL_SIZE_SIGMA) ** 2
    cost -= 2.0 * _diamond_matches(camera, ev.diamonds, spec, tol)
    return cost + _coverage_cost(quad, ev)


def _hypotheses(
    corners: np.ndarray,
    seen: np.ndarray,
    image_size: tuple[int, int],
    spec: TableSpec,
    given: bool,
    aspects: list[tuple[float, float]],
    ev_of: dict[float, _Evidence],
    offset: float,
    plane_z: float | None = None,
) -> list[_Hypothesis]:
    out = []
    tol = 0.01 * math.hypot(*image_size)
    world = outline_rectangle(spec, offset)
    lengths = (world[1, 0] - world[0, 0], world[2, 1] - world[1, 1])  # (long, short) outline sides
    for aspect, aspect_cost in aspects:
        size = (image_size[0] / aspect, image_size[1])
        q = corners / np.array([aspect, 1.0])
        ev = ev_of[aspect]
        if seen.all():
            for shift in (0, 1):
                quad = np.roll(q, -shift, axis=0)  # quad[k] is the table's corner k
                quick = quick_camera(quad, size, spec, offset, plane_z=plane_z)
                if quick is None:
                    continue
                camera, rect = quick
                cost = aspect_cost + _score(quad, camera, rect, shift == 0, spec, given, ev, aspect, tol)
                out.append(_Hypothesis(cost, rect, quad, aspect, camera, False))
            continue
        unseen = int(np.flatnonzero(~seen)[0])
        mid = (unseen + 2) % 4
        lines = np.array([line_through(q[k], q[(k + 1) % 4]) for k in range(4)])
        three = lines[[(mid - 1) % 4, mid, (mid + 1) % 4]]
        inner = q[[(mid - 1) % 4, mid, (mid + 1) % 4, (mid + 2) % 4]].mean(axis=0)
        for mid_long in (True, False):
            mid_len, side_len = lengths if mid_long else lengths[::-1]
            for factor in THREE_LINE_FOCALS:
                f = factor * max(size)
                made = complete_three_lines(three, f, size, mid_len, side_len, inner)
                if made is None:
                    continue
                # made[0], made[1] are the cloth corners mid, mid + 1; the table's corner 0 starts a long side
                quad = made if mid_long else np.roll(made, 1, axis=0)
                quick = quick_camera(quad, size, spec, offset, focal=f, plane_z=plane_z)
                if quick is None:
                    continue
                camera, rect = quick
                prior = (math.log(factor / THREE_LINE_FOCAL) / THREE_LINE_FOCAL_SIGMA) ** 2
                long_first = mid_long == (mid % 2 == 0)  # cloth sides 0, 2 long
                score = _score(quad, camera, rect, long_first, spec, given, ev, aspect, tol)
                out.append(_Hypothesis(aspect_cost + prior + score, rect, quad, aspect, camera, True))
    return out


def _evidence(
    aspect: float,
    image_size: tuple[int, int],
    boxes: np.ndarray,
    diamonds: np.ndarray,
    darkness: np.ndarray | None,
    cloth_mask: np.ndarray | None,
) -> _Evidence:
    unstretch = np.array([aspect, 1.0])
    centres = (boxes[:, :2] + boxes[:, 2:]) / 2 / unstretch if len(boxes) else np.zeros((0, 2))
    coverage, scale = None, (1.0, 1.0)
    if cloth_mask is not None:
        h, w = cloth_mask.shape
        s = COVERAGE_SIDE / max(w, h)
        gw, gh = max(round(w * s), 4), max(round(h * s), 4)
        coverage = cv2.resize(cloth_mask.astype(np.float32), (gw, gh), interpolation=cv2.INTER_AREA)
        scale = (gw / w * aspect, gh / h)
    return _Evidence(centres, boxes, image_size, diamonds / unstretch, darkness, coverage, scale)


# ----------------------------------------------------------------------------- entry point
def fit_outline(
    corners_px: np.ndarray,
    image_size: tuple[int, int],
    spec: TableSpec | None = None,
    *,
    seen: np.ndarray | None = None,
    ball_boxes: np.ndarray | None = None,
    diamonds: np.ndarray | None = None,
    pocket_darkness: np.ndarray | None = None,
    cloth_mask: np.ndarray | None = None,
    pixel_aspect: float | None = None,
    offset: float = CUSHION_WIDTH,
    plane_z: float | None = None,
    max_rectangle_cost: float | None = None,
    base: TableSpec | None = None,
    top_view_balls: int = TOP_VIEW_BALLS,
) -> TableFit:
    """Fit the table from its cloth outline.

    Args:
        corners_px: the outline's corners [px] (4, 2), in order around it (as
            :attr:`~pix2pockets.vision.table.cloth.ClothOutline.corners_px`); which is which table corner is found here.
        image_size: (width, height) [px].
        spec: the table; ``None`` measures its size from the balls (snapped to the nearest preset when close; 9-foot
            without balls).
        seen: for each side (side ``k`` from corner ``k`` to ``k + 1``), whether the photo shows it; with one side
            unseen (cut by the frame edge), the table is completed from the other three.
        ball_boxes: ball boxes (n, 4) [px]: on the table, they measure its size and weigh the hypotheses.
        diamonds: diamond centres (m, 2) [px] (evidence for the long rails).
        pocket_darkness: per side, how dark its middle is (side pockets mark the long rails).
        cloth_mask: the cloth region (H, W) bool: it must fill the table's outline and lie inside it.
        pixel_aspect: width over height of one pixel; ``None`` tries the usual export stretches on a square photo.
        offset: cushion width: how far the outline lies outside the playing surface [m].
        plane_z: height of the outline above the cloth [m] (default: the cushion-nose height; 0 for the playing
            surface's own corners on the cloth).
        max_rectangle_cost: largest rectangle error accepted (default :data:`MAX_RECTANGLE_COST`); outlines whose
            corners are read more surely (the table model's) may allow more.
        base: without ``spec``, the table whose balls measure the size and whose presets it snaps to (default
            9-foot, American balls; a UK preset for a blackball set).
        top_view_balls: balls a view from straight above needs on the table to be believed (a rectangle seen square
            on is more often a window or a picture); 0 where other cues already show a table.

    Returns:
        A :class:`TableFit` with ``source="cloth"``, no matched diamonds, ``rms_px`` the corners' error.

    Raises:
        TableFitError: fewer than three sides, or no plausible camera and table.
    """
    corners = np.asarray(corners_px, dtype=float).reshape(4, 2)
    seen = np.ones(4, dtype=bool) if seen is None else np.asarray(seen, dtype=bool).reshape(4)
    if seen.sum() < 3:
        n = counted(int(seen.sum()), "cushion")
        raise TableFitError(f"no table found: only {n} of the table in view, 3 are needed")
    if not np.all(np.isfinite(corners)):
        raise TableFitError("no table found: the cloth outline has no four corners")
    # a camera above the table shows the table frame's corner order with a negative signed area in (u, v)
    area = float(np.dot(corners[:, 0], np.roll(corners[:, 1], -1)) - np.dot(corners[:, 1], np.roll(corners[:, 0], -1)))
    if area > 0:
        corners, seen = corners[::-1].copy(), seen[[2, 1, 0, 3]]
        pocket_darkness = None if pocket_darkness is None else np.asarray(pocket_darkness)[[2, 1, 0, 3]]
    boxes = np.zeros((0, 4)) if ball_boxes is None else np.asarray(ball_boxes, dtype=float).reshape(-1, 4)
    dots = np.zeros((0, 2)) if diamonds is None else np.asarray(diamonds, dtype=float).reshape(-1, 2)
    dark = None if pocket_darkness is None else np.asarray(pocket_darkness, dtype=float)
    base = spec or base or TableSpec()
    aspects = _aspect_hypotheses(pixel_aspect, image_size, boxes)
    ev_of = {a: _evidence(a, image_size, boxes, dots, dark, cloth_mask) for a, _ in aspects}
    hyps = _hypotheses(corners, seen, image_size, base, spec is not None, aspects, ev_of, offset, plane_z)
    return _best_fit(
        hyps, image_size, spec, base, boxes, len(dots), offset, plane_z, top_view_balls, max_rectangle_cost
    )


def _best_fit(
    hyps: list[_Hypothesis],
    image_size: tuple[int, int],
    spec: TableSpec | None,
    base: TableSpec,
    boxes: np.ndarray,
    n_diamonds: int,
    offset: float,
    plane_z: float | None,
    top_view_balls: int,
    max_rectangle_cost: float | None,
) -> TableFit:
    """The fit of the cheapest of the hypotheses that gives a plausible camera (of the :data:`MAX_TRIED` cheapest)."""
    hyps = sorted((h for h in hyps if np.isfinite(h.cost)), key=lambda h: h.cost)
    if not hyps:
        raise TableFitError("no table found: the cloth outline gives no camera")
    error: TableFitError | None = None
    limit = MAX_RECTANGLE_COST if max_rectangle_cost is None else max_rectangle_cost
    for best in hyps[:MAX_TRIED]:
        if best.rect_cost > limit:
            error = error or TableFitError(
                "no table found: the cloth outline is not a table seen by a camera (its four sides are no 2:1 "
                f"rectangle in perspective: mismatch {best.rect_cost:.0f}, at most {limit:.0f} accepted)"
            )
            continue
        try:
            return _final_fit(best, image_size, spec, base, boxes, n_diamonds, offset, plane_z, top_view_balls)
        except TableFitError as err:
            error = error or err
    raise error or TableFitError("no table found")


def fit_two_cushions(
    lines: np.ndarray,
    marks: list[CushionMark],
    image_size: tuple[int, int],
    spec: TableSpec | None = None,
    *,
    ball_boxes: np.ndarray | None = None,
    cloth_mask: np.ndarray | None = None,
    pixel_aspect: float | None = None,
    offset: float = CUSHION_WIDTH,
    plane_z: float | None = None,
    base: TableSpec | None = None,
) -> TableFit:
    """Fit the table from its two long cushions (:mod:`pix2pockets.vision.table.two_cushions`).

    Args:
        lines: (2, 3) the two long cushion lines ``a u + b v + c = 0`` [px] (the outline's, ``offset`` outside the
            playing surface at ``plane_z``).
        marks: side pockets and corners seen on them (:class:`~pix2pockets.vision.table.two_cushions.CushionMark`;
            at least a side pocket and one more).
        image_size, spec, ball_boxes, cloth_mask, pixel_aspect, offset, plane_z, base: as for :func:`fit_outline`.

    Returns:
        A :class:`TableFit` with ``source="cloth"``.

    Raises:
        TableFitError: too few marks, or no table they place that the balls and the cloth agree with.
    """
    if not any(m.kind == "pocket" for m in marks) or len(marks) < 2:
        raise TableFitError(
            "no table found: two cushions fix the table only with a side pocket on one and a corner or a second "
            "side pocket"
        )
    boxes = np.zeros((0, 4)) if ball_boxes is None else np.asarray(ball_boxes, dtype=float).reshape(-1, 4)
    base = spec or base or TableSpec()
    aspects = _aspect_hypotheses(pixel_aspect, image_size, boxes)
    world = outline_rectangle(base, offset)
    length, width = world[1, 0] - world[0, 0], world[2, 1] - world[1, 1]
    tol = 0.01 * math.hypot(*image_size)
    hyps: list[_Hypothesis] = []
    for aspect, aspect_cost in aspects:
        size = (image_size[0] / aspect, image_size[1])
        unstretch = np.diag([aspect, 1.0, 1.0])  # a line in stretched pixels, seen in unstretched ones
        line0, line1 = (np.asarray(line, dtype=float) @ unstretch for line in lines)
        flat = [replace(m, px=np.asarray(m.px, dtype=float) / np.array([aspect, 1.0])) for m in marks]
        ev = _evidence(aspect, image_size, boxes, np.zeros((0, 2)), None, cloth_mask)
        for factor in THREE_LINE_FOCALS:
            for table in complete_two_long_cushions(
                line0, line1, flat, factor * max(size), size, length, width, free_focal=len(marks) >= 3
            ):
                quad = table.quad
                area = float(np.dot(quad[:, 0], np.roll(quad[:, 1], -1)) - np.dot(quad[:, 1], np.roll(quad[:, 0], -1)))
                if area > 0:  # a camera above the table sees its corner order with a negative signed area
                    quad = quad[[1, 0, 3, 2]]
                quick = quick_camera(quad, size, base, offset, focal=table.focal, plane_z=plane_z)
                if quick is None:
                    continue
                camera, rect = quick
                prior = (math.log(table.focal / (THREE_LINE_FOCAL * max(size))) / THREE_LINE_FOCAL_SIGMA) ** 2
                score = _score(quad, camera, rect, True, base, spec is not None, ev, aspect, tol)
                hyps.append(_Hypothesis(aspect_cost + prior + table.cost + score, rect, quad, aspect, camera, True))
    return _best_fit(hyps, image_size, spec, base, boxes, 0, offset, plane_z, TOP_VIEW_BALLS, None)


def _final_fit(
    best: _Hypothesis,
    image_size: tuple[int, int],
    spec: TableSpec | None,
    base: TableSpec,
    boxes: np.ndarray,
    n_diamonds: int,
    offset: float,
    plane_z: float | None = None,
    top_view_balls: int = TOP_VIEW_BALLS,
) -> TableFit:
    """The fit of one hypothesis: the camera refined on its corners, the table's size from the balls."""
    aspect = best.aspect
    quad = best.quad * np.array([aspect, 1.0])
    focal = best.camera.K[1, 1] if best.three_lines else None
    longest = FOCAL_RANGE[1] * max(image_size)

    def fitted(table: TableSpec) -> tuple[PinholeCamera, float]:
        camera, _, rms = camera_from_outline(quad, image_size, table, aspect, offset, focal, plane_z)
        if focal is None and camera.K[1, 1] > longest:  # seen square on: the corners hardly fix the focal length
            camera, _, rms = camera_from_outline(quad, image_size, table, aspect, offset, longest, plane_z, 1e-3)
        return camera, rms

    camera, rms = fitted(base)
    final, size_source = base, "given"
    if spec is None:
        size_source = "default"
        k = size_from_balls(camera, boxes, base, aspect) if len(boxes) else None
        if k is not None:
            final = spec_of_length(k * (base.length + 2 * offset) - 2 * offset, base)
            size_source = "balls"
            if final is not base:
                camera, rms = fitted(final)
    _check_camera(camera, final, image_size)
    on_table = len(boxes) - _balls_off(camera, (boxes[:, :2] + boxes[:, 2:]) / 2, final) if len(boxes) else 0
    if camera_tilt(camera) < math.radians(TOP_VIEW_DEG) and on_table < top_view_balls:
        # a rectangle seen square on is more often a window, a door or a picture than a table from above
        raise TableFitError(f"no table found: a view from straight above needs {top_view_balls} balls on the table")
    camera = head_rail_convention(camera, final)
    return TableFit(
        final,
        camera,
        np.full(n_diamonds, -1),
        np.full((4, 2), np.nan),
        rms,
        0,
        diamond_height(final),
        source="cloth",
        size_source=size_source,
    )


def _check_camera(camera: PinholeCamera, spec: TableSpec, image_size: tuple[int, int]) -> None:
    """Raise :class:`TableFitError` for a camera below the rails, a table behind it or an implausible focal length."""
    if not np.all(np.isfinite(camera.position)) or camera.position[2] < spec.cushion_height + MIN_CAMERA_HEIGHT:
        raise TableFitError("no table found: the fitted camera is not above the table")
    validate_corners(camera.project_table(spec.corners, 0.0), image_size)
    f = camera.K[1, 1]
    if not 0.9 * FOCAL_RANGE[0] * max(image_size) < f < 1.1 * FOCAL_RANGE[1] * max(image_size):
        raise TableFitError(f"no table found: implausible camera (focal length {in_photo_px(f)})")

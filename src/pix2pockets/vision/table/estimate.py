"""One table estimate from every cue a photo offers: the playing surface, the diamonds, the cloth and the balls.

The table model's playing surface (:mod:`pix2pockets.vision.table.keypoints`, outlined by
:func:`~pix2pockets.vision.table.surface.surface_outline`: corners read to about a pixel, side pockets marking the
long rails) gives a fit of its own, at the cushion noses on the cloth, which is then moved onto the cloth's edge in
the photo (:func:`~pix2pockets.vision.table.cloth_edge.snap_fit`). Where the outline has a second hypothesis (its
``alternative``, the corner peaks' own outline), both are fitted and the one more of the cloth's edges confirm wins
(:func:`better_surface_fit`). Where the diamond fit agrees with it (its corners within
:data:`CORNER_TOLERANCE`), the diamond fit is kept (``"diamonds+surface"``). Where they disagree, a diamond fit whose
playing surface overlaps the model's surface region far less (:data:`SURFACE_OVERLAP_MARGIN`) loses, else the fit that
explains more diamonds and balls wins (``"diamonds"`` or ``"surface"``). A surface fit that holds none of three or more
sure balls (:data:`MIN_BALLS_HELD`) is refused. Where the outline gives no fit, a close view across the table may still
show the two long cushions with their side pockets (:func:`~pix2pockets.vision.table.surface.long_cushion_pair`), which
fix the table on their own (:func:`~pix2pockets.vision.table.outline_fit.fit_two_cushions`).

Without a surface, :func:`estimate_table` fits the table from the diamonds
(:func:`~pix2pockets.vision.table.fit.fit_table`, the rail sights) and from the cloth
(:func:`~pix2pockets.vision.table.cloth.find_cloth` and
:func:`~pix2pockets.vision.table.outline_fit.fit_outline`, for the many tables with no sights or with sights too
small to see). Where both give a table, the one that explains more of the cues wins (:func:`explained_cues`): the
diamonds it reprojects within a tolerance, the cloth outline corners it lands on, and the balls it puts on the
playing surface. Agreeing fits keep the diamond fit (its points are sharper than the cloth's edges), marked
``"diamonds+cloth"``.

Example:
    >>> fit = estimate_table(rgb, detections, (w, h))  # doctest: +SKIP
    >>> fit.source, fit.size_source  # doctest: +SKIP
    ('cloth', 'balls')
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from pix2pockets.geometry.table import TableSpec
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.table.cloth import ClothOutline, find_cloth
from pix2pockets.vision.table.cloth_edge import side_contrasts, snap_fit
from pix2pockets.vision.table.errors import TableFitError
from pix2pockets.vision.table.fit import TableFit, diamond_height, fit_table
from pix2pockets.vision.table.outline_camera import CUSHION_WIDTH, outline_rectangle
from pix2pockets.vision.table.outline_fit import fit_outline, fit_two_cushions
from pix2pockets.vision.table.pixel_aspect import pixel_aspect_of_balls, pixel_aspect_of_photo, snapped_aspect
from pix2pockets.vision.table.quad_geometry import corner_gap, quad_mask
from pix2pockets.vision.table.surface import SurfaceOutline, long_cushion_pair

CUES = ("diamonds", "cloth", "surface", "all")
"""What :func:`estimate_table` may fit the table to."""
MIN_BALL_SCORE = 0.3  # balls at least this sure seed the cloth colour and measure the table
CORNER_TOLERANCE = 0.03
"""A fit lands on a cloth corner within this fraction of the image diagonal."""
SURE_SIDE_POCKET = 0.5
"""Side-pocket peak score that counts as a side pocket seen (:func:`shows_a_table`)."""
SURFACE_OVERLAP_MARGIN = 0.05
"""A diamond fit that disagrees with the surface's loses when its playing surface overlaps the model's surface region
(intersection over union) by this much less than the surface fit's does: false diamonds (a rack triangle, balls in a
row) or diamonds matched a sight off. On 345 renders with sights (seeds 6000-6499) it sets aside 11 diamond fits:
9 of them 3-90 % of the table's length off (their surface fits 0.4-8.9 %), two nearly right (0.8 and 2.1 %, their
surface fits 2.0 and 4.3 %)."""
DIAMOND_TOLERANCE = 0.01
"""A fit explains a diamond within this fraction of the image diagonal."""
MIN_BALLS = 2
"""A cloth fit with fewer balls on its table must rest on a clear outline: ..."""
MIN_CONFIDENCE_WITHOUT_BALLS = 0.3
"""... all four cushions seen and a region this table-like (walls, floors and furniture make rectangles too)."""
MIN_BALLS_HELD = 3
"""A surface fit on none of the photo's balls is refused when there are at least this many (a sliver of a table
fitted to one cushion seen close up)."""
EDGE_CONTRAST = 1.0
"""Colour contrast across a side (:func:`~pix2pockets.vision.table.cloth_edge.line_contrast`) that puts it on the
cloth's edge (on the real photos labelled, sides on the edge read 1.1-5.8, sides of a region that leaked onto a
rail 0-0.8)."""
SIDE_POCKET_DARKNESS = 40.0
"""A side-pocket peak of the table model weighs as a side this much darker mid-way (Lab lightness) in the outline
fit's choice of the long rails."""
SURFACE_MAX_RECTANGLE_COST = 150.0
"""Largest rectangle error of an accepted surface outline: its corners are the model's, read more surely than the
colour region's edges (on the 80 real phone photos 48 fits at 150, 43 at the colour outline's 40, all right by
eye but the ones listed in ``docs/benchmarks-vision.md``)."""


@dataclass(frozen=True, slots=True)
class CueScore:
    """The cues a fitted table explains (:func:`explained_cues`).

    Attributes:
        diamonds: detected diamonds within :data:`DIAMOND_TOLERANCE` of a projected diamond.
        corners: cloth-outline corners within :data:`CORNER_TOLERANCE` of the fit's outline corners.
        balls: ball detections whose centres fall on the playing surface.
    """

    diamonds: int
    corners: int
    balls: int

    @property
    def total(self) -> float:
        """One number to rank fits: a ball and a cloth corner count one each, a diamond one and a half (a diamond
        fit has passed stricter checks than a cloth outline)."""
        return 1.5 * self.diamonds + self.corners + self.balls


def explained_cues(
    fit: TableFit, diamonds: np.ndarray, cloth: ClothOutline | None, ball_centres: np.ndarray
) -> CueScore:
    """How many of the photo's cues ``fit`` explains: diamonds (m, 2) [px], the cloth outline's corners and the
    ball box centres (n, 2) [px]."""
    diag = math.hypot(*fit.camera.image_size)
    spec = fit.spec
    n_diamonds = 0
    if len(diamonds):
        proj = fit.camera.project_table(spec.diamonds, diamond_height(spec))
        d = np.linalg.norm(diamonds[:, None, :] - proj[None], axis=-1)
        n_diamonds = int(np.sum(np.min(np.nan_to_num(d, nan=np.inf), axis=1) < DIAMOND_TOLERANCE * diag))
    n_corners = 0
    if cloth is not None:
        outline = fit.camera.project_table(outline_rectangle(spec, CUSHION_WIDTH), spec.cushion_height)
        d = np.linalg.norm(cloth.corners_px[:, None, :] - outline[None], axis=-1)
        n_corners = int(np.sum(np.min(np.nan_to_num(d, nan=np.inf), axis=1) < CORNER_TOLERANCE * diag))
    return CueScore(n_diamonds, n_corners, balls_on_table(fit, ball_centres))


def balls_on_table(fit: TableFit, ball_centres: np.ndarray) -> int:
    """How many ball box centres (n, 2) [px] ``fit`` puts on its playing surface."""
    if not len(ball_centres):
        return 0
    spec = fit.spec
    xy = fit.image_to_table(ball_centres, spec.ball_radius)
    return int(np.sum(np.all(np.isfinite(xy), axis=1) & spec.contains(np.nan_to_num(xy, nan=-1e9))))


def estimate_table(
    rgb: np.ndarray | None,
    detections: Detections,
    image_size: tuple[int, int] | None = None,
    spec: TableSpec | None = None,
    cues: str = "all",
    pixel_aspect: float | None = None,
    surface: SurfaceOutline | None = None,
    base: TableSpec | None = None,
) -> TableFit:
    """Fit the table to every cue in a photo: diamonds, cloth outline, balls.

    Args:
        rgb: the photo, RGB uint8 (H, W, 3); ``None`` fits the diamonds only.
        detections: the photo's detections (balls and diamonds, post-processed).
        image_size: (width, height) [px] (default: the photo's).
        spec: the table; ``None`` for a cloth fit measures its size from the balls (``size_source="balls"``) and
            matches diamonds to a 9-foot table.
        cues: ``"diamonds"``, ``"cloth"``, ``"surface"`` or ``"all"``.
        pixel_aspect: width over height of one pixel (default: read from the balls); 1 lets the cloth outline try
            the usual export stretches of a square photo too.
        surface: the table model's playing surface (:func:`~pix2pockets.vision.table.surface.surface_outline`),
            when there is one.
        base: without ``spec``, the table whose balls measure a fit's size without diamonds (default 9-foot; a UK
            preset for a blackball set's 2 in balls).

    Returns:
        The :class:`TableFit` explaining the most cues; ``source`` says which it came from.

    Raises:
        TableFitError: no cue gives a table, with what each cue lacked and what to do.
    """
    if cues not in CUES:
        raise ValueError(f"cues must be one of {CUES}, got {cues!r}")
    if image_size is None:
        if rgb is None:
            raise ValueError("estimate_table needs the photo or its image_size")
        image_size = (int(rgb.shape[1]), int(rgb.shape[0]))
    balls = detections[detections.is_ball]
    sure = balls[balls.own_score >= MIN_BALL_SCORE]
    diamonds = detections[detections.is_diamond].centres
    measured = pixel_aspect
    if measured is None:
        if rgb is not None:
            measured = pixel_aspect_of_photo(rgb, balls.boxes, balls.own_score)
        else:
            measured = pixel_aspect_of_balls(balls.boxes, balls.own_score)
    aspect = snapped_aspect(float(measured))
    # square pixels may just mean that nothing showed a stretch: the outline fit then weighs the usual export
    # stretches itself (a four-cornered outline shows the stretch a squashed photo has)
    outline_aspect = aspect if aspect != 1.0 else None

    def outline_fit(
        corners: np.ndarray, seen: np.ndarray, darkness: np.ndarray, mask: np.ndarray, **options: float | int
    ) -> TableFit:
        """The table seen through an outline's corners, with the photo's balls, diamonds and pixel stretch."""
        return fit_outline(
            corners,
            image_size,
            spec,
            seen=seen,
            ball_boxes=sure.boxes,
            diamonds=diamonds,
            pocket_darkness=darkness,
            cloth_mask=mask,
            pixel_aspect=outline_aspect,
            base=base,
            **options,
        )

    fits: list[TableFit] = []
    reasons: list[str] = []
    if cues in ("diamonds", "all"):
        try:
            fit = fit_table(detections, image_size, spec, pixel_aspect=aspect)
            fits.append(fit if spec is None else replace(fit, size_source="given"))
        except TableFitError as err:
            reasons.append(f"diamonds: {_reason(err)}")
    surface_fit: TableFit | None = None
    if cues in ("surface", "all") and surface is not None:
        found_fits: list[TableFit] = []
        for outline in (surface, surface.alternative):  # the outline and its second hypothesis
            if outline is None:
                continue
            try:
                darkness = SIDE_POCKET_DARKNESS * outline.side_pocket
                at_noses = {"offset": 0.0, "plane_z": 0.0, "max_rectangle_cost": SURFACE_MAX_RECTANGLE_COST}
                if shows_a_table(outline):  # a top view needs no balls to tell it from a window
                    at_noses["top_view_balls"] = 0
                found = replace(
                    outline_fit(outline.corners_px, outline.seen, darkness, outline.mask, **at_noses), source="surface"
                )
            except TableFitError as err:
                if outline is surface:
                    reasons.append(f"surface: {_reason(err)}")
                continue
            if rgb is not None:  # onto the cloth's edge in the photo, sharper than the model
                found = snap_fit(rgb, found, surface.mask, sure.boxes)
            if len(sure) >= MIN_BALLS_HELD and balls_on_table(found, sure.centres) == 0:
                if outline is surface:
                    reasons.append(f"surface: its table holds none of the {len(sure)} balls")
                continue
            found_fits.append(found)
        surface_fit = better_surface_fit(found_fits, rgb, surface.mask, sure.boxes)
        if surface_fit is None:  # a close view across the table: its two long cushions alone
            surface_fit = _two_cushion_fit(surface, image_size, spec, sure, outline_aspect, base, reasons)
    if surface_fit is not None:
        for fit in fits:  # a diamond fit on the surface's corners is the sharper of the two
            if corner_gap(fit.corners_px, surface_fit.corners_px) <= CORNER_TOLERANCE * math.hypot(*image_size):
                return replace(fit, source="diamonds+surface")
            # they disagree: a diamond fit far off the model's surface is taken from false diamonds (a rack
            # triangle, balls in a row); else the one explaining more diamonds and balls (ties to the diamonds)
            if surface_overlap(fit, surface.mask) + SURFACE_OVERLAP_MARGIN < surface_overlap(surface_fit, surface.mask):
                continue
            centres = sure.centres
            if (
                explained_cues(fit, diamonds, None, centres).total
                >= explained_cues(surface_fit, diamonds, None, centres).total
            ):
                return fit
        return surface_fit
    if cues == "surface":
        raise TableFitError("no table found: " + "; ".join(reasons or ["surface: no playing surface"]))
    cloth: ClothOutline | None = None
    if cues in ("cloth", "all") and rgb is not None:
        try:
            cloth = find_cloth(rgb, sure.boxes)
            fit = outline_fit(cloth.corners_px, cloth.seen, cloth.pocket_darkness, cloth.mask)
            on_table = balls_on_table(fit, sure.centres)
            if on_table < MIN_BALLS and not (cloth.seen.all() and cloth.confidence >= MIN_CONFIDENCE_WITHOUT_BALLS):
                raise TableFitError(
                    f"no table found: a cloth without balls on it ({on_table}) must show all four cushions clearly"
                )
            fits.append(fit)
        except TableFitError as err:
            reasons.append(f"cloth: {_reason(err)}")
    if not fits:
        raise TableFitError(
            "no table found: "
            + "; ".join(reasons)
            + " (show the whole table: its cloth with the four cushions and pockets"
            + (", or two rails with their sights" if cues != "cloth" else "")
            + ")"
        )
    if len(fits) == 1:
        return fits[0]
    centres = sure.centres
    scores = [explained_cues(f, diamonds, cloth, centres) for f in fits]
    diamond_fit, cloth_fit = fits
    if scores[0].corners >= 3:  # the diamonds' table lies on the cloth outline too
        return replace(diamond_fit, source="diamonds+cloth")
    return diamond_fit if scores[0].total >= scores[1].total else cloth_fit


def better_surface_fit(
    fits: list[TableFit], rgb: np.ndarray | None, mask: np.ndarray, ball_boxes: np.ndarray
) -> TableFit | None:
    """Of the surface fits from an outline and from its second hypothesis (in that order), the one with more sides on
    the cloth's edge in the photo (:func:`edge_sides`: a side the surface region leaked past, onto a rail or a
    player, lies on none) while it holds as many of the balls ``ball_boxes`` (n, 4) [px]; ties, and fits without the
    photo, keep the outline's. ``mask``: the surface region (H, W) bool. None without a fit."""
    if not fits:
        return None
    best = fits[0]
    if rgb is None:
        return best
    centres = (ball_boxes[:, :2] + ball_boxes[:, 2:]) / 2 if len(ball_boxes) else np.zeros((0, 2))
    best_edges = edge_sides(rgb, best, mask, ball_boxes)
    for fit in fits[1:]:
        edges = edge_sides(rgb, fit, mask, ball_boxes)
        if edges > best_edges and balls_on_table(fit, centres) >= balls_on_table(best, centres):
            best, best_edges = fit, edges
    return best


def edge_sides(rgb: np.ndarray, fit: TableFit, mask: np.ndarray, ball_boxes: np.ndarray) -> int:
    """How many sides of a fit's cloth outline lie on the cloth's edge in the photo: the colour across them leaves
    the cloth's by at least :data:`EDGE_CONTRAST` (:func:`~pix2pockets.vision.table.cloth_edge.side_contrasts`)."""
    return int((side_contrasts(rgb, fit, mask, ball_boxes) >= EDGE_CONTRAST).sum())


def shows_a_table(outline: SurfaceOutline) -> bool:
    """Whether the table model sees a table there beyond doubt: all four corners are its corner peaks and two opposite
    sides have a side pocket in their middle (no window, door or picture has those)."""
    pockets = outline.side_pocket >= SURE_SIDE_POCKET
    return bool(outline.from_peak.all() and ((pockets[0] and pockets[2]) or (pockets[1] and pockets[3])))


def surface_overlap(fit: TableFit, mask: np.ndarray) -> float:
    """Intersection over union of a fit's playing surface in the photo with a surface region ``mask`` (H, W) bool;
    0 for a surface behind the camera."""
    inside = quad_mask(fit.corners_px, mask.shape)
    union = int((inside | mask).sum())
    return int((inside & mask).sum()) / union if union else 0.0


def outline_used(fit: TableFit, surface: SurfaceOutline) -> SurfaceOutline:
    """Of a surface's outline and its :attr:`~SurfaceOutline.alternative`, the one a surface fit came from (the one
    nearer its corners)."""
    alternative = surface.alternative
    if alternative is None:
        return surface
    gap = corner_gap(fit.corners_px, alternative.corners_px)
    return alternative if gap < corner_gap(fit.corners_px, surface.corners_px) else surface


def _two_cushion_fit(
    surface: SurfaceOutline,
    image_size: tuple[int, int],
    spec: TableSpec | None,
    sure: Detections,
    pixel_aspect: float | None,
    base: TableSpec | None,
    reasons: list[str],
) -> TableFit | None:
    """The table from the surface's two long cushions and their marks (:func:`long_cushion_pair`), when it shows
    them; a reason is added to ``reasons`` where they give none."""
    pair = long_cushion_pair(surface)
    if pair is None:
        return None
    lines, marks = pair
    try:
        fit = fit_two_cushions(
            lines,
            marks,
            image_size,
            spec,
            ball_boxes=sure.boxes,
            cloth_mask=surface.mask,
            pixel_aspect=pixel_aspect,
            offset=0.0,
            plane_z=0.0,
            base=base,
        )
    except TableFitError as err:
        reasons.append(f"two cushions: {_reason(err)}")
        return None
    if len(sure) >= MIN_BALLS_HELD and balls_on_table(fit, sure.centres) == 0:
        reasons.append(f"two cushions: their table holds none of the {len(sure)} balls")
        return None
    return replace(fit, source="surface")


def _reason(err: TableFitError) -> str:
    """An error's reason without its lead-in and its advice (the estimate gives one piece of advice for all)."""
    text = str(err).removeprefix("no table found: ")
    cut = text.find(" (show ")
    return text if cut < 0 else text[:cut]

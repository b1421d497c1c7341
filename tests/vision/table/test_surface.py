"""The playing surface's outline from the table model's surface chances: whole tables and tables the frame cuts."""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np
import pytest

from pix2pockets.vision.detect.letterbox import Letterbox
from pix2pockets.vision.table.errors import TableFitError
from pix2pockets.vision.table.keypoints import N_TABLE_CHANNELS, STRIDE, TableModel, cues_from_output, pixel_of_cell
from pix2pockets.vision.table.quad_geometry import line_through
from pix2pockets.vision.table.surface import MAX_CUT_REGION_SHARE, long_cushion_pair, surface_agreement, surface_outline

IMAGE = (768, 432)  # photo (width, height) [px]; the network input is the photo itself (scale 1)


def cues_of(corners_px: np.ndarray):
    """Table cues whose surface channel is 1 inside the quadrilateral ``corners_px`` (4, 2) [px], 0 outside; no
    corner or side-pocket peaks."""
    w, h = IMAGE
    cols, rows = -(-w // 32) * 32 // STRIDE, -(-h // 32) * 32 // STRIDE
    xy = pixel_of_cell(np.stack(np.meshgrid(np.arange(cols), np.arange(rows)), axis=-1).reshape(-1, 2))
    inside = np.array([cv2.pointPolygonTest(corners_px.astype(np.float32), tuple(p), False) >= 0 for p in xy])
    in_photo = (xy[:, 0] < w) & (xy[:, 1] < h)
    out = np.zeros((N_TABLE_CHANNELS, rows, cols), dtype=np.float32)
    out[0] = (inside & in_photo).reshape(rows, cols)
    return cues_from_output(out, Letterbox(scale=1.0, size=(cols * STRIDE, rows * STRIDE)), IMAGE)


def distance_to_line(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    line = line_through(a, b)
    return np.abs(points @ line[:2] + line[2])


def test_a_whole_table_shows_four_cushions():
    corners = np.array([[120.0, 100.0], [640.0, 90.0], [700.0, 350.0], [70.0, 370.0]])
    outline = surface_outline(cues_of(corners))
    assert outline.seen.all()
    order = [int(np.argmin(np.linalg.norm(corners - c, axis=1))) for c in outline.corners_px]
    assert sorted(order) == [0, 1, 2, 3]
    assert np.linalg.norm(outline.corners_px - corners[order], axis=1).max() < 4.0


def test_a_table_cut_by_the_frame_shows_its_three_cushions_in_view():
    """A low view: the near cushion lies below the photo and the side cushions run out of its bottom edge. The
    three cushions in view are read from the region's edge; the frame closes the fourth side, marked unseen."""
    far_left, far_right, near_right, near_left = np.array([[150.0, 110.0], [620.0, 95.0], [900.0, 520.0], [-150, 560]])
    outline = surface_outline(cues_of(np.array([far_left, far_right, near_right, near_left])))
    assert outline.seen.sum() == 3
    sides = [(outline.corners_px[k], outline.corners_px[(k + 1) % 4]) for k in range(4)]
    truth = [(far_left, far_right), (far_right, near_right), (near_left, far_left)]
    for a, b in truth:  # each true cushion is one of the seen sides: its ends lie on that side's line
        fits = [distance_to_line(np.array([a, b]), *sides[k]).max() for k in np.flatnonzero(outline.seen)]
        assert min(fits) < 4.0, (a, b, fits)
    unseen = sides[int(np.flatnonzero(~outline.seen)[0])]
    assert np.all(np.abs(np.array(unseen)[:, 1] - IMAGE[1]) < 8.0)  # the frame's bottom edge closes the region


def test_a_corner_view_cut_on_three_edges_shows_the_cushions_in_view():
    """A low view at a corner: the frame's left, bottom and right edges cut the cloth; the cushions run out of the
    photo at shallow angles, so the smallest quadrilateral round the region takes frame edges for sides. The
    cushions are read from the region's edge instead, corners far outside the photo included."""
    truth = np.array([[-377.0, 361.0], [627.0, 166.0], [1012.0, 258.0], [489.0, 453.0]])
    outline = surface_outline(cues_of(truth))
    assert outline.seen.sum() >= 3
    order = [int(np.argmin(np.linalg.norm(truth - c, axis=1))) for c in outline.corners_px]
    assert sorted(order) == [0, 1, 2, 3]
    assert np.linalg.norm(outline.corners_px - truth[order], axis=1).max() < 6.0


@pytest.mark.parametrize("far", [[[386.0, 164.0], [184.0, 160.0]], [[360.0, 150.0], [220.0, 148.0]]])
def test_a_short_far_cushion_is_not_merged_into_the_long_ones_when_a_corner_is_cut(far):
    """A low view along the table, one near corner out of the photo: the region's edge runs along the short far
    cushion, both long cushions and the near one, and along the frame. The smallest quadrilateral round it can drop
    the short far cushion (the long cushions, extended, meet just beyond it) instead of the frame's stretch; the
    cushions read off the frame keep all four."""
    truth = np.array([[711.0, 332.0], *far, [-250.0, 420.0]])
    outline = surface_outline(cues_of(truth))
    assert outline.seen.all()
    order = [int(np.argmin(np.linalg.norm(truth - c, axis=1))) for c in outline.corners_px]
    assert sorted(order) == [0, 1, 2, 3]
    assert np.linalg.norm(outline.corners_px - truth[order], axis=1).max() < 8.0
    # the quadrilateral's own outline stays as the second hypothesis, for a fit where the runs make no rectangle
    assert outline.alternative is not None and outline.alternative.seen.sum() == 3


def test_a_band_across_the_photo_shows_only_two_cushions():
    """Looking along the table from close up: only the two long cushions are in view; no third line is made up."""
    band = np.array([[-200.0, 120.0], [1000.0, 100.0], [1000.0, 330.0], [-200.0, 360.0]])
    outline = surface_outline(cues_of(band))
    assert outline.seen.sum() <= 2


@pytest.mark.parametrize("shift", [0.0, 40.0])
def test_the_cut_table_outline_is_deterministic(shift):
    quad = np.array([[150.0 + shift, 110.0], [620.0, 95.0], [900.0, 520.0], [-150, 560]])
    a, b = surface_outline(cues_of(quad)), surface_outline(cues_of(quad))
    assert np.array_equal(a.corners_px, b.corners_px) and np.array_equal(a.seen, b.seen)


def test_a_region_filling_the_photo_gives_no_cushions_from_scraps_of_its_edge():
    """A blank grey photo, which the shipped table model takes for cloth nearly everywhere: the few stretches of the
    region's edge inside the photo are not read as cushions."""
    model = TableModel.from_option(None)
    if model is None:
        pytest.skip("this build has no table model")
    cues = model.read(np.full((360, 640, 3), 90, np.uint8))
    assert (cues.surface >= 0.5).mean() > MAX_CUT_REGION_SHARE
    try:
        outline = surface_outline(cues)
    except TableFitError:
        return
    assert outline.seen.sum() < 3


def cues_with_peaks(surface_polygons: list[np.ndarray], peaks_px: np.ndarray):
    """Table cues whose surface is 1 inside any of ``surface_polygons``, with corner peaks at ``peaks_px`` (k, 2)."""
    w, h = IMAGE
    cols, rows = -(-w // 32) * 32 // STRIDE, -(-h // 32) * 32 // STRIDE
    xy = pixel_of_cell(np.stack(np.meshgrid(np.arange(cols), np.arange(rows)), axis=-1).reshape(-1, 2))
    inside = np.zeros(len(xy), dtype=bool)
    for poly in surface_polygons:
        inside |= np.array([cv2.pointPolygonTest(poly.astype(np.float32), tuple(p), False) >= 0 for p in xy])
    out = np.zeros((N_TABLE_CHANNELS, rows, cols), dtype=np.float32)
    out[0] = (inside & (xy[:, 0] < w) & (xy[:, 1] < h)).reshape(rows, cols)
    cues = cues_from_output(out, Letterbox(scale=1.0, size=(cols * STRIDE, rows * STRIDE)), IMAGE)
    return replace(cues, corners_px=np.asarray(peaks_px, dtype=float), corner_scores=np.full(len(peaks_px), 0.6))


TABLE = np.array([[200.0, 230.0], [520.0, 225.0], [600.0, 380.0], [130.0, 390.0]])
WALL = np.array([[470.0, 0.0], [560.0, 0.0], [560.0, 230.0], [470.0, 230.0]])  # a cloth-coloured wall joining the table


def test_the_corner_peaks_outline_a_table_whose_surface_leaks_into_a_wall():
    """The region joins table and wall, so its enclosing quadrilateral takes in the wall; the four corner peaks
    round the table agree far better with the surface and give the outline."""
    outline = surface_outline(cues_with_peaks([TABLE, WALL], TABLE), np.array([[360.0, 300.0]]))
    assert outline.from_peak.all() and outline.seen.all()
    order = [int(np.argmin(np.linalg.norm(TABLE - c, axis=1))) for c in outline.corners_px]
    assert sorted(order) == [0, 1, 2, 3]
    assert np.allclose(outline.corners_px, TABLE[order])


def test_corner_peaks_off_the_surface_do_not_replace_the_tables_outline():
    picture = np.array([[600.0, 40.0], [700.0, 40.0], [700.0, 120.0], [600.0, 120.0]])  # peaks round a wall picture
    outline = surface_outline(cues_with_peaks([TABLE], picture), np.array([[360.0, 300.0]]))
    assert np.linalg.norm(outline.corners_px[:, None] - TABLE[None], axis=2).min(axis=1).max() < 4.0


def test_surface_agreement_counts_cloth_in_and_penalises_what_is_not():
    cues = cues_with_peaks([TABLE], np.zeros((0, 2)))
    grown = TABLE + 60.0 * np.sign(TABLE - TABLE.mean(axis=0))
    assert surface_agreement(cues, TABLE) > surface_agreement(cues, grown)
    assert surface_agreement(cues, TABLE) > surface_agreement(cues, 0.5 * (TABLE + TABLE.mean(axis=0))) > 0


def test_four_peaks_that_lose_to_the_region_stay_as_the_alternative():
    """Surface joined to the table along a whole side (a player's shirt of the cloth's colour) outscores the four
    peaks, so the region's outline stays first and the peaks' outline is kept as the second hypothesis."""
    shirt = np.array([[200.0, 120.0], [520.0, 115.0], [520.0, 228.0], [200.0, 232.0]])
    outline = surface_outline(cues_with_peaks([TABLE, shirt], TABLE), np.array([[360.0, 300.0]]))
    assert outline.corners_px[:, 1].min() < 150.0  # the region's outline takes in the shirt
    assert outline.alternative is not None and outline.alternative.from_peak.all()
    order = [int(np.argmin(np.linalg.norm(TABLE - c, axis=1))) for c in outline.alternative.corners_px]
    assert np.allclose(outline.alternative.corners_px, TABLE[order])


def test_peaks_on_the_regions_outline_give_no_alternative():
    outline = surface_outline(cues_with_peaks([TABLE], TABLE), np.array([[360.0, 300.0]]))
    assert outline.alternative is None


def _with_peaks(cues, corners_px: np.ndarray, sides_px: np.ndarray):
    """Cues with corner and side-pocket peaks (score 0.9) at these points [px]."""
    corners_px, sides_px = np.asarray(corners_px, float).reshape(-1, 2), np.asarray(sides_px, float).reshape(-1, 2)
    return replace(
        cues,
        corners_px=corners_px,
        corner_scores=np.full(len(corners_px), 0.9),
        sides_px=sides_px,
        side_scores=np.full(len(sides_px), 0.9),
    )


BAND = np.array([[-300.0, 120.0], [1100.0, 95.0], [1100.0, 360.0], [-300.0, 400.0]])  # two long cushions across


def test_two_long_cushions_are_paired_with_their_side_pockets():
    """A close view across the table: the region's two cushion lines and the side pockets on them."""
    far_pocket, near_pocket = np.array([400.0, 109.0]), np.array([400.0, 380.0])
    outline = surface_outline(_with_peaks(cues_of(BAND), np.zeros((0, 2)), [far_pocket, near_pocket]))
    assert len(outline.cushion_lines) == 2
    pair = long_cushion_pair(outline)
    assert pair is not None
    lines, marks = pair
    assert sorted(m.kind for m in marks) == ["pocket", "pocket"]
    for mark in marks:  # each pocket lies on the line it is given to
        line = lines[mark.line]
        assert abs(mark.px @ line[:2] + line[2]) / np.hypot(*line[:2]) < 4.0
    assert {marks[0].line, marks[1].line} == {0, 1}


def test_two_cushions_need_a_side_pocket_and_a_second_mark():
    far_pocket = np.array([400.0, 109.0])
    assert long_cushion_pair(surface_outline(_with_peaks(cues_of(BAND), np.zeros((0, 2)), [far_pocket]))) is None
    assert long_cushion_pair(surface_outline(cues_of(BAND))) is None


def test_two_cushions_meeting_at_a_corner_in_view_are_no_pair():
    """A corner view: a long and a short cushion meet at a corner in the photo; they are not two long cushions."""
    corner = np.array([300.0, 100.0])
    wedge = np.array([corner, [1200.0, 500.0], [-400.0, 900.0]])
    pocket = corner + 0.5 * (np.array([1200.0, 500.0]) - corner) * 0.6
    outline = surface_outline(_with_peaks(cues_of(wedge), [corner], [pocket]))
    assert len(outline.cushion_lines) >= 2
    assert long_cushion_pair(outline) is None


def test_a_scaled_outline_keeps_its_cushion_lines_on_its_corners_and_its_cues_surface():
    far_left, far_right, near_right, near_left = np.array([[150.0, 110.0], [620.0, 95.0], [900.0, 520.0], [-150, 560]])
    outline = surface_outline(cues_of(np.array([far_left, far_right, near_right, near_left])))
    assert len(outline.cushion_lines)
    sx, sy = 2.5, 2.0
    size = (round(IMAGE[0] * sx), round(IMAGE[1] * sy))
    big = outline.scaled(sx, sy, size)
    np.testing.assert_allclose(big.corners_px, outline.corners_px * [sx, sy])
    assert big.mask.shape == (size[1], size[0]) and big.mask.dtype == bool
    assert abs(big.mask.mean() - outline.mask.mean()) < 0.01
    for old, new in zip(outline.cushion_lines, big.cushion_lines, strict=True):  # the same points lie on each line
        on_old = np.array([[-old[2] * old[0], -old[2] * old[1]]]) + np.array([[0.0], [100.0]]) * [-old[1], old[0]]
        assert np.abs(on_old * [sx, sy] @ new[:2] + new[2]).max() < 1e-9
        assert np.linalg.norm(new[:2]) == pytest.approx(1.0)
    size = (round(IMAGE[0] * sx), round(IMAGE[1] * sx))
    cues = outline.scaled(sx, sx, size).cues  # the network input scales alike across and down
    assert cues.image_size == size
    assert abs(cues.surface_mask().mean() - outline.cues.surface_mask().mean()) < 0.01
    net = np.array([[100.0, 50.0]])
    np.testing.assert_allclose(cues.letterbox.to_image(net), outline.cues.letterbox.to_image(net) * sx)

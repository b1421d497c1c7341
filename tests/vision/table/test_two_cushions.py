"""The table from its two long cushions: exact marks give the exact rectangle; too few marks give none."""

from __future__ import annotations

import numpy as np
import pytest

from pix2pockets.geometry import PinholeCamera, TableSpec
from pix2pockets.vision.table.quad_geometry import line_through
from pix2pockets.vision.table.two_cushions import CushionMark, complete_two_long_cushions

SPEC = TableSpec()
SIZE = (960, 540)
FOCAL = 700.0


def across_view() -> PinholeCamera:
    """A low camera beside the table's long side, looking across it."""
    return PinholeCamera.look_at(np.array([1.6, -0.9, 0.9]), np.array([1.6, 0.7, 0.0]), FOCAL, SIZE)


def seen(camera: PinholeCamera) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The playing surface's corners [px], the near and far long cushion lines and the two side pockets [px]."""
    corners = camera.project_table(SPEC.corners, 0.0)
    pockets = camera.project_table(np.array([[SPEC.length / 2, 0.0], [SPEC.length / 2, SPEC.width]]), 0.0)
    return corners, line_through(corners[0], corners[1]), line_through(corners[3], corners[2]), pockets


def same_rectangle(quad: np.ndarray, truth: np.ndarray) -> float:
    """Largest corner distance [px] between two rectangles' corners, either way round."""
    return min(
        float(np.abs(np.roll(quad, k, axis=0)[order] - truth).max())
        for k in range(4)
        for order in ([0, 1, 2, 3], [3, 2, 1, 0])
    )


def test_two_pockets_and_a_corner_fix_the_table_and_the_focal_length():
    corners, near, far, pockets = seen(across_view())
    marks = [
        CushionMark(pockets[0], 0, "pocket"),
        CushionMark(pockets[1], 1, "pocket"),
        CushionMark(corners[2], 1, "corner"),
    ]
    for start in (500.0, 900.0, 1300.0):
        tables = complete_two_long_cushions(near, far, marks, start, SIZE, SPEC.length, SPEC.width, free_focal=True)
        best = tables[0]
        assert best.cost < 1e-6
        assert best.focal == pytest.approx(FOCAL, rel=1e-4)
        assert same_rectangle(best.quad, corners) < 0.5


def test_a_pocket_and_a_corner_fix_the_table_for_a_known_focal_length():
    """One turn puts the corner at each end of the cushion: the true table is one of the exact solutions."""
    corners, near, far, pockets = seen(across_view())
    marks = [CushionMark(pockets[1], 1, "pocket"), CushionMark(corners[2], 1, "corner")]
    tables = complete_two_long_cushions(near, far, marks, FOCAL, SIZE, SPEC.length, SPEC.width)
    exact = [t for t in tables if t.cost < 1e-6]
    assert exact and min(same_rectangle(t.quad, corners) for t in exact) < 0.5
    wrong_focal = complete_two_long_cushions(near, far, marks, 1.3 * FOCAL, SIZE, SPEC.length, SPEC.width)
    assert min(same_rectangle(t.quad, corners) for t in wrong_focal) > 5.0


def test_the_marks_lines_are_swappable():
    corners, near, far, pockets = seen(across_view())
    marks = [
        CushionMark(pockets[1], 0, "pocket"),
        CushionMark(pockets[0], 1, "pocket"),
        CushionMark(corners[2], 0, "corner"),
    ]
    best = complete_two_long_cushions(far, near, marks, 900.0, SIZE, SPEC.length, SPEC.width, free_focal=True)[0]
    assert same_rectangle(best.quad, corners) < 0.5


def test_too_few_marks_give_no_table():
    corners, near, far, pockets = seen(across_view())
    pocket = CushionMark(pockets[0], 0, "pocket")
    corner = CushionMark(corners[2], 1, "corner")
    assert complete_two_long_cushions(near, far, [pocket], FOCAL, SIZE, SPEC.length, SPEC.width) == []
    assert complete_two_long_cushions(near, far, [corner, corner], FOCAL, SIZE, SPEC.length, SPEC.width) == []

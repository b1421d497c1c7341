"""Layouts, cameras, z-buffered figures and YOLO rows of the synthetic renderer."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.table import TableSpec
from pix2pockets.synth.cameras import BROADCAST_KINDS, CAMERA_KINDS, camera_kinds, sample_camera, table_coverage
from pix2pockets.synth.labels import sphere_outline_px, yolo_lines
from pix2pockets.synth.layouts import LAYOUT_MODES, sample_layout
from pix2pockets.synth.people import draw_figure

SPEC = TableSpec()


@pytest.mark.parametrize("mode", sorted(LAYOUT_MODES))
def test_layout_modes_are_valid(mode):
    rng = np.random.default_rng(4)
    for _ in range(5):
        layout, used = sample_layout(rng, SPEC, mode)
        assert used == mode and len(layout) >= 1
        numbers = [b.number for b in layout.balls]
        assert len(set(numbers)) == len(numbers)
    rack, _ = sample_layout(np.random.default_rng(0), SPEC, "rack")
    assert len(rack) == 16


def test_unknown_layout_mode():
    with pytest.raises(ValueError, match="unknown layout mode"):
        sample_layout(np.random.default_rng(0), SPEC, "banana")


@pytest.mark.parametrize("kind", [*CAMERA_KINDS, "front"])
def test_cameras_see_the_table_from_above(kind):
    rng = np.random.default_rng(1)
    for _ in range(4):
        cam, got = sample_camera(rng, SPEC, (320, 180), kind)
        assert got in (kind, "jib")
        assert cam.position[2] > 0.1
        assert table_coverage(cam, SPEC) > 0.05
        forward = cam.R[2]
        elevation = math.degrees(math.asin(-forward[2]))
        if kind == "top":
            assert elevation > 75
        if kind == "front":
            assert 10 < elevation < 35


def test_unknown_camera_kind():
    with pytest.raises(ValueError, match="unknown camera kind"):
        sample_camera(np.random.default_rng(0), SPEC, (320, 180), "drone")
    with pytest.raises(ValueError, match="unknown camera kind 'drone'"):
        sample_camera(np.random.default_rng(0), SPEC, (320, 180), ["top", "drone"])


def test_camera_kinds_from_names_and_groups():
    assert camera_kinds("broadcast") == BROADCAST_KINDS == ("top", "high", "jib")
    assert camera_kinds("phone_low, top,phone") == ("top", "phone", "phone_low")  # CAMERA_KINDS order
    assert camera_kinds(["jib", "broadcast", "low"]) == ("top", "high", "low", "jib")
    assert camera_kinds(["phone,low", "top"]) == ("top", "low", "phone")
    for bad in ("", " , ", "tv"):
        with pytest.raises(ValueError):
            camera_kinds(bad)


def test_cameras_drawn_among_the_given_kinds():
    got = {sample_camera(np.random.default_rng(i), SPEC, (320, 180), ("top", "low"))[1] for i in range(40)}
    assert got == {"top", "low"}
    broadcast = [sample_camera(np.random.default_rng(i), SPEC, (320, 180), ["broadcast"])[1] for i in range(40)]
    assert set(broadcast) == set(BROADCAST_KINDS)


def test_figures_are_z_buffered():
    cam = PinholeCamera.look_at(np.array([0.0, 0.0, 3.0]), np.array([0.0, 0.0, 0.0]), 200.0, (64, 48))
    img = np.zeros((48, 64, 3), np.float32)
    mask = np.zeros((48, 64), bool)
    depth = np.full((48, 64), 2.5, np.float32)  # a wall 2.5 m from the camera
    behind = [(np.array([-0.1, 0.0, 0.0]), np.array([0.1, 0.0, 0.0]), 0.05, 0.05, np.array([1.0, 0.0, 0.0]))]
    draw_figure(img, mask, depth, cam, behind)  # 3 m away: hidden
    assert not mask.any()
    front = [(np.array([-0.1, 0.0, 1.0]), np.array([0.1, 0.0, 1.0]), 0.05, 0.05, np.array([1.0, 0.0, 0.0]))]
    draw_figure(img, mask, depth, cam, front)  # 2 m away: drawn
    assert mask[24, 32] and img[24, 32, 0] > 0.2 and depth[24, 32] < 2.5


def test_sphere_outline_matches_projection_scale():
    cam = PinholeCamera.look_at(np.array([0.0, 0.0, 2.0]), np.array([0.0, 0.0, 0.0]), 500.0, (200, 200))
    outline = sphere_outline_px(cam, np.array([0.0, 0.0, 0.0]), 0.1)
    radius = np.linalg.norm(outline - [100, 100], axis=1)
    expected = 500 * 0.1 / math.sqrt(2.0**2 - 0.1**2)
    assert np.allclose(radius, expected, rtol=1e-6)


def test_yolo_rows_normalised():
    labels = {
        "image_size": [200, 100],
        "balls": [{"labelled": True, "class_id": 3, "box_px": [10, 20, 30, 60]}, {"labelled": False}],
        "diamonds": [{"labelled": True, "box_px": [0, 0, 4, 4]}],
    }
    rows = yolo_lines(labels)
    assert rows == ["3 0.100000 0.400000 0.100000 0.400000", "4 0.010000 0.020000 0.020000 0.040000"]

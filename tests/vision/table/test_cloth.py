"""The cloth finder on photos drawn in the test (a projected table) and on the bundled example render."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from pix2pockets.data.examples import example_labels_path, example_photo_path
from pix2pockets.geometry import PinholeCamera, TableSpec, table_preset
from pix2pockets.pipeline.photo import load_image
from pix2pockets.vision.detect.analytic import detections_from_synth_labels
from pix2pockets.vision.locate.balls import sphere_boxes
from pix2pockets.vision.table.cloth import find_cloth
from pix2pockets.vision.table.cloth_region import content_frame
from pix2pockets.vision.table.errors import TableFitError
from pix2pockets.vision.table.outline_camera import outline_rectangle
from pix2pockets.vision.table.quad_geometry import enclosing_quad

SPEC = TableSpec()
SIZE = (640, 360)
BALLS = np.array([[0.6, 0.4], [1.9, 0.9], [1.2, 0.6], [0.3, 1.0], [2.2, 0.2], [1.5, 1.1]])


def view(kind: str = "oblique", spec: TableSpec = SPEC, size: tuple[int, int] = SIZE) -> PinholeCamera:
    """A camera on the table: ``oblique`` from beside the head-bottom corner, ``end`` low behind the head rail."""
    centre = np.array([spec.length / 2, spec.width / 2, 0.0])
    if kind == "end":
        return PinholeCamera.look_at(np.array([-2.0, spec.width / 2 + 0.2, 1.8]), centre, 0.9 * size[0], size)
    return PinholeCamera.look_at(centre + np.array([-1.6, -2.3, 2.4]), centre, 0.75 * size[0], size)


def _poly(camera: PinholeCamera, xy: np.ndarray, z: float) -> np.ndarray:
    """Projected table points as a cv2 polygon (pixel centres at integers, 4 fractional bits)."""
    return np.round((camera.project_table(xy, z) - 0.5) * 16).astype(np.int32)


def draw_table_photo(
    camera: PinholeCamera,
    spec: TableSpec = SPEC,
    cloth: tuple[int, int, int] = (30, 130, 60),
    seed: int = 0,
    player: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """A photo of a table drawn in the test: floor and wall, wooden rails, a cloth with a lamp's gradient whose
    outline is the cushion backs (:func:`outline_rectangle`), six dark pockets, balls and a player leaning over the
    head end. Returns the RGB image and the ball boxes (n, 4) [px]."""
    w, h = camera.image_size
    rng = np.random.default_rng(seed)
    img = np.zeros((h, w, 3), np.float32)
    img[:] = np.linspace(150, 90, h)[:, None, None] * np.array([0.9, 0.8, 0.7])
    z = spec.cushion_height
    rail = outline_rectangle(spec, 0.05 + 0.12)
    cv2.fillPoly(img, [_poly(camera, rail, z)], (95, 55, 30), cv2.LINE_AA, 4)
    layer = np.zeros((h, w), np.float32)
    cv2.fillPoly(layer, [_poly(camera, outline_rectangle(spec), z)], 1.0, cv2.LINE_AA, 4)
    yy, xx = np.mgrid[0:h, 0:w]
    light = 1.15 - 0.35 * np.hypot((xx - w / 2) / w, (yy - h / 2) / h)
    img = img * (1 - layer[:, :, None]) + layer[:, :, None] * np.array(cloth, np.float32) * light[:, :, None]
    for pocket in spec.pockets:
        centre = camera.project_table(pocket.centre, z) - 0.5
        edge = camera.project_table(pocket.centre + np.array([0.06, 0.0]), z) - 0.5
        axes = (max(int(np.linalg.norm(edge - centre)), 2),) * 2
        cv2.ellipse(img, (round(centre[0]), round(centre[1])), axes, 0, 0, 360, (12, 12, 12), -1, cv2.LINE_AA)
    centres = np.column_stack([BALLS * spec.size / SPEC.size, np.full(len(BALLS), spec.ball_radius)])
    boxes = sphere_boxes(camera, centres, spec.ball_radius)
    for k, box in enumerate(boxes):
        colour = (240, 240, 230) if k == 0 else tuple(int(c) for c in rng.integers(20, 255, 3))
        c = (box[:2] + box[2:]) / 2 - 0.5
        cv2.ellipse(img, (round(c[0]), round(c[1])), (round((box[2] - box[0]) / 2), round((box[3] - box[1]) / 2)),
                    0, 0, 360, colour, -1, cv2.LINE_AA)  # fmt: skip
    if player:  # a dark body leaning over the top rail, hiding part of it
        body = camera.project_table(np.array([spec.length * 0.3, spec.width + 0.1]), 0.25) - 0.5
        cv2.ellipse(img, (round(body[0]), round(body[1])), (w // 18, h // 6), 10, 0, 360, (40, 35, 45), -1)
    img += rng.normal(0, 3.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8), boxes


def corner_error(found: np.ndarray, truth: np.ndarray) -> float:
    """Largest corner distance [px] between two quadrilaterals, over the orders describing the same one."""
    return min(np.abs(np.roll(c, k, axis=0) - truth).max() for c in (found, found[::-1]) for k in range(4))


@pytest.mark.parametrize(
    ("kind", "cloth"), [("oblique", (30, 130, 60)), ("end", (40, 80, 170)), ("oblique", (150, 30, 40))]
)
def test_cloth_outline_of_a_drawn_table(kind, cloth):
    camera = view(kind)
    img, boxes = draw_table_photo(camera, cloth=cloth)
    found = find_cloth(img, boxes)
    truth = camera.project_table(outline_rectangle(SPEC), SPEC.cushion_height)
    assert corner_error(found.corners_px, truth) < 2.0
    assert found.seen.all()
    assert found.confidence > 0.3
    # the mask covers the outline (balls and pockets filled), not the rails
    inside = np.zeros(img.shape[:2], np.uint8)
    cv2.fillPoly(inside, [np.round(truth - 0.5).astype(np.int32)], 1)
    iou = np.sum(found.mask & (inside > 0)) / np.sum(found.mask | (inside > 0))
    assert iou > 0.88  # the mask is found on a coarse grid


def test_side_pockets_darken_the_long_sides():
    camera = view("oblique")
    img, boxes = draw_table_photo(camera, player=False)
    found = find_cloth(img, boxes)
    truth = camera.project_table(outline_rectangle(SPEC), SPEC.cushion_height)
    # which found side lies on the long bottom rail (from truth corner 0 to 1)
    mids = (found.corners_px + np.roll(found.corners_px, -1, axis=0)) / 2
    long_side = int(np.argmin(np.linalg.norm(mids - (truth[0] + truth[1]) / 2, axis=1)))
    dark = found.pocket_darkness
    assert dark[long_side] + dark[(long_side + 2) % 4] > dark[(long_side + 1) % 4] + dark[(long_side + 3) % 4] + 10


def test_a_side_cut_by_the_frame_is_not_seen():
    camera = view("oblique")
    img, boxes = draw_table_photo(camera)
    truth = camera.project_table(outline_rectangle(SPEC), SPEC.cushion_height)
    cut = int(max(truth[0, 0], truth[3, 0])) + 20  # the head cushion and its corners left of the frame
    found = find_cloth(np.ascontiguousarray(img[:, cut:]), boxes[boxes[:, 0] > cut] - np.array([cut, 0, cut, 0]))
    assert found.seen.sum() == 3
    left = int(np.argmin((found.corners_px + np.roll(found.corners_px, -1, axis=0))[:, 0]))
    assert not found.seen[left]
    # the three cushions seen are where they were
    for k in np.flatnonzero(found.seen):
        line = found.lines[k]
        for corner in truth:
            d = abs(line[:2] @ (corner - np.array([cut, 0])) + line[2])
            if d < 5:
                break
        else:
            raise AssertionError(f"side {k} lies on no cushion")


def test_letterbox_bands_are_the_frame():
    gray = np.full((90, 160), 120.0)
    gray[:12] = 0.0
    gray[-10:] = 2.0
    assert content_frame(gray) == (0, 12, 159, 79)


def test_enclosing_quad_of_a_cut_rectangle():
    # a rectangle with two corners cut off (corner pockets): the quad restores the corners
    hull = np.array([[0, 2], [2, 0], [10, 0], [10, 6], [8, 8], [0, 8.0]])
    np.testing.assert_allclose(enclosing_quad(hull), [[0, 0], [10, 0], [10, 8], [0, 8]], atol=1e-9)


@pytest.mark.parametrize("scene", ["wall", "close-up", "noise"])
def test_no_table_in_the_photo(scene):
    rng = np.random.default_rng(1)
    boxes = np.zeros((0, 4))
    if scene == "wall":
        img = np.zeros((240, 320, 3), np.uint8)
        img[:] = (200, 190, 170)
    elif scene == "close-up":  # cloth and balls fill the frame: no cushion to see
        img = np.zeros((240, 320, 3), np.uint8)
        img[:] = (30, 130, 60)
        for x in (80, 160, 240):
            cv2.circle(img, (x, 120), 30, (230, 230, 220), -1)
        boxes = np.array([[x - 30, 90, x + 30, 150] for x in (80, 160, 240)], dtype=float)
    else:
        img = rng.integers(0, 255, (240, 320, 3)).astype(np.uint8)
    with pytest.raises(TableFitError, match="no table found"):
        find_cloth(img, boxes)


def test_bundled_example_cloth_corners():
    labels = json.loads(Path(example_labels_path()).read_text())
    spec = table_preset(labels["table"]["name"])
    cam = labels["camera"]
    camera = PinholeCamera(np.array(cam["K"]), np.array(cam["R"]), np.array(cam["t"]), tuple(cam["image_size"]))
    det = detections_from_synth_labels(labels)
    found = find_cloth(load_image(example_photo_path()), det[det.is_ball].boxes)
    truth = camera.project_table(outline_rectangle(spec), spec.cushion_height)
    assert corner_error(found.corners_px, truth) < 4.0


def test_same_photo_same_outline():
    img, boxes = draw_table_photo(view("end"), seed=3)
    a, b = find_cloth(img, boxes), find_cloth(img.copy(), boxes.copy())
    np.testing.assert_array_equal(a.corners_px, b.corners_px)
    np.testing.assert_array_equal(a.mask, b.mask)

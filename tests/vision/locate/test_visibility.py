import numpy as np

from pix2pockets.geometry import TableSpec
from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.vision.locate.balls import locate_sphere, sphere_boxes
from pix2pockets.vision.locate.visibility import unexplained_shortfall, visible_boxes

SPEC = TableSpec()
R = SPEC.ball_radius
LOW = PinholeCamera.look_at(
    np.array([-0.9, SPEC.width / 2, 0.45]), np.array([0.8, SPEC.width / 2, 0.0]), 1100.0, (1280, 720)
)
"""A low view from behind the head cushion, along the table."""


def raster_boxes(camera: PinholeCamera, centres: np.ndarray, cushion_x: float | None = None) -> np.ndarray:
    """Boxes of the pixels whose ray meets each sphere first, one ray per pixel centre; with ``cushion_x``, a wall
    at x = ``cushion_x`` up to the cushion's height hides what lies beyond it."""
    sil = sphere_boxes(camera, centres, R)
    x1, y1 = np.floor(sil[:, :2].min(axis=0)).astype(int)
    x2, y2 = np.ceil(sil[:, 2:].max(axis=0)).astype(int)
    u, v = np.meshgrid(np.arange(x1, x2) + 0.5, np.arange(y1, y2) + 0.5)
    px = np.column_stack([u.ravel(), v.ravel()])
    rays = np.column_stack([px, np.ones(len(px))]) @ np.linalg.inv(camera.K).T
    rays = rays @ camera.R  # world directions
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    eye = camera.position
    depth = np.full((len(px), len(centres)), np.inf)
    for i, c in enumerate(centres):
        along = (c - eye) @ rays.T
        miss2 = np.sum((c - eye) ** 2) - along**2
        ok = miss2 <= R * R
        depth[ok, i] = along[ok] - np.sqrt(R * R - miss2[ok])
    first = np.where(np.isfinite(depth.min(axis=1)), depth.argmin(axis=1), -1)
    if cushion_x is not None:
        s = (cushion_x - eye[0]) / rays[:, 0]
        wall = (s > 0) & (eye[2] + s * rays[:, 2] < SPEC.cushion_height)
        hit = depth.min(axis=1)
        first[wall & (s < hit)] = -1
    out = np.full((len(centres), 4), np.nan)
    for i in range(len(centres)):
        p = px[first == i]
        if len(p):
            out[i] = [*(p.min(axis=0) - 0.5), *(p.max(axis=0) + 0.5)]
    return out


def test_a_ball_alone_is_seen_whole():
    centre = np.array([[1.2, 0.6, R]])
    sil = sphere_boxes(LOW, centre, R)
    vis = visible_boxes(LOW, centre, R, sil, SPEC)
    assert np.allclose(vis, sil, atol=1.0)


def test_a_ball_behind_another_shows_its_top_only():
    centres = np.array([[1.0, 0.6, R], [1.0 + 2.05 * R, 0.6 + 0.2 * R, R]])  # the second is behind the first
    sil = sphere_boxes(LOW, centres, R)
    vis = visible_boxes(LOW, centres, R, sil, SPEC)
    truth = raster_boxes(LOW, centres)
    assert np.allclose(vis[0], sil[0], atol=1.0)  # the front ball whole
    assert sil[1, 3] - vis[1, 3] > 5.0  # the rear ball's bottom hidden
    assert np.allclose(vis[1], truth[1], atol=1.5)


def test_the_near_cushion_hides_a_ball_beside_it():
    centre = np.array([[R + 0.002, 0.6, R]])
    sil = sphere_boxes(LOW, centre, R)
    vis = visible_boxes(LOW, centre, R, sil, SPEC)
    truth = raster_boxes(LOW, centre, cushion_x=0.0)
    assert sil[0, 3] - vis[0, 3] > 5.0
    assert np.allclose(vis[0], truth[0], atol=1.5)
    assert np.allclose(visible_boxes(LOW, centre, R, sil, None), sil, atol=1.0)  # no table, no cushion


def test_partly_hidden_balls_are_located_from_the_edges_they_show():
    centres = np.array([[1.0, 0.6, R], [1.0 + 2.05 * R, 0.6 + 0.2 * R, R], [R + 0.002, 0.3, R]])
    seen = raster_boxes(LOW, centres, cushion_x=0.0)
    with_model = locate_sphere(LOW, seen, R, spec=SPEC)
    without = locate_sphere(LOW, seen, R, spec=SPEC, occlusion=False)
    err = np.linalg.norm(with_model - centres[:, :2], axis=1)
    err_without = np.linalg.norm(without - centres[:, :2], axis=1)
    assert np.all(err < 0.003)
    assert err_without[1] > 0.01 and err_without[2] > 0.01  # the box centre is not the ball's


def test_a_box_cut_by_nothing_in_view_is_short_by_what_is_missing():
    centres = np.array([[1.0, 0.6, R], [1.0 + 2.05 * R, 0.6 + 0.2 * R, R], [1.6, 0.3, R]])
    boxes = raster_boxes(LOW, centres)  # the second ball's bottom hidden by the first: explained
    boxes[2, 1] += 0.5 * (boxes[2, 3] - boxes[2, 1])  # the third's top half under a cue: not explained
    short = unexplained_shortfall(LOW, boxes, centres[:, :2], R, SPEC)
    assert np.all(short[:2] == 0.0)
    assert short[2, 0] == 0.0
    size = boxes[2, 3] - boxes[2, 1]
    assert 0.6 * size < short[2, 1] < 1.0 * size  # half its height, less the slack

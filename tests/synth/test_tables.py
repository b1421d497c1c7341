"""Tables as people own them: plain rails and sight shapes, pub / coin-op and home builds, phone cameras held low
or upright, with labels that stay exact."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.synth import render
from pix2pockets.synth import scene_codes as sc
from pix2pockets.synth.builds import SIGHT_CODES
from pix2pockets.synth.cameras import sample_camera
from pix2pockets.synth.labels import diamond_outline, polygon_area, yolo_lines
from pix2pockets.synth.renderer import scene_of, trace
from pix2pockets.vision.classes import DIAMOND_ID

SIZE = (320, 180)
STYLES = {s: scene_of(s).style for s in range(60)}


def first_seed(**style) -> int:
    return next(s for s, st in STYLES.items() if all(st[k] == v for k, v in style.items()))


def camera_of(labels: dict) -> PinholeCamera:
    c = labels["camera"]
    return PinholeCamera(np.array(c["K"]), np.array(c["R"]), np.array(c["t"]), tuple(c["image_size"]))


def test_plain_rails_label_no_diamond():
    seed = first_seed(sights="none")
    rend = render(seed, SIZE, camera_kind="top")
    assert rend.labels["style"]["sights"] == "none"
    diamonds = rend.labels["diamonds"]
    assert len(diamonds) == 18 and not any(d["labelled"] for d in diamonds)
    assert not any(row.startswith(f"{DIAMOND_ID} ") for row in yolo_lines(rend.labels))
    assert not ((rend.ids >= sc.ID_DIAMOND0) & (rend.ids < sc.ID_DIAMOND0 + 18)).any()
    assert sum(d["in_frame"] for d in diamonds) >= 12  # the positions are there, the sights are not


@pytest.mark.parametrize("shape", sorted(SIGHT_CODES))
def test_sight_shapes_cover_their_labelled_outline(shape):
    """Seen from straight above, each sight's pixels cover the projected outline the labels use."""
    base = scene_of(first_seed(build="hall", sights="round"))
    shade = base.shade.copy()
    shade[sc.S_DIA_SHAPE] = SIGHT_CODES[shape]
    geo = base.geo.copy()
    geo[sc.G_DR] = 0.004 if shape == "dot" else 0.008
    scene = dataclasses.replace(base, shade=shade, geo=geo, style={**base.style, "sights": shape})
    for k in (1, 7, 10, 16):
        x, y = scene.spec.diamonds[k]
        cam = PinholeCamera.look_at(np.array([x + 0.01, y, 0.5]), np.array([x, y, 0.0]), 1000, (96, 96))
        ids = trace(scene, cam)[1]
        outline = cam.project(diamond_outline(scene, k, n=64))
        area = polygon_area(outline)
        pixels = np.argwhere(ids == sc.ID_DIAMOND0 + k)[:, ::-1] + 0.5
        assert area > 100 and abs(len(pixels) - area) < 0.05 * area, (shape, k, len(pixels), area)
        assert np.allclose(pixels.min(axis=0), outline.min(axis=0), atol=2.0)  # same extent, same orientation
        assert np.allclose(pixels.max(axis=0), outline.max(axis=0), atol=2.0)


def test_pub_tables_have_rounded_pockets_plates_and_a_coin_box():
    seed = first_seed(build="pub", coin_box=True, plates="square")
    scene = scene_of(seed)
    L, W = scene.spec.length, scene.spec.width
    top = PinholeCamera.look_at(np.array([L / 2, W / 2, 2.6]), np.array([L / 2, W / 2, 0.0]), 700, (960, 540))
    ids = trace(scene, top)[1]
    assert (ids == sc.ID_PLATE).sum() > 500
    for hole in scene.holes:
        assert hole[3] > hole[2] > 0  # a round cut around a drop hole
        u, v = top.project(np.array([hole[0], hole[1], 0.0]))
        assert ids[int(v), int(u)] == sc.ID_HOLE
    foot = PinholeCamera.look_at(np.array([L + 1.5, W / 2, 0.2]), np.array([L, W / 2, -0.35]), 600, (480, 360))
    assert (trace(scene, foot)[1] == sc.ID_BOX).sum() > 500


def test_rounded_pockets_keep_the_spec_s_jaw_points():
    scene = scene_of(first_seed(pockets="rounded"))
    for pocket, hole in zip(scene.spec.pockets, scene.holes, strict=True):
        for jaw in pocket.jaws:
            assert np.linalg.norm(jaw - hole[:2]) == pytest.approx(hole[3], abs=1e-9)


def test_build_mix():
    styles = [scene_of((3, i)).style for i in range(400)]
    plain = {b: np.mean([s["sights"] == "none" for s in styles if s["build"] == b]) for b in ("hall", "pub", "home")}
    assert 0.22 < np.mean([s["sights"] == "none" for s in styles]) < 0.42
    assert plain["hall"] < 0.15 < plain["home"] < plain["pub"]
    greens_blues = {"tournament_blue", "electric_blue", "green", "english_green", "teal"}
    assert np.mean([s["cloth"] not in greens_blues for s in styles]) >= 0.25
    assert {s["cloth"] for s in styles} >= {"black", "red", "grey", "purple"}
    assert {s["rail"] for s in styles if s["build"] == "pub"} >= {"white", "black", "dark_wood"}


def test_phone_cameras_stand_0_8_to_1_95_m_above_the_floor():
    rng = np.random.default_rng(5)
    spec = scene_of(0).spec
    heights = []
    for _ in range(40):
        cam, kind = sample_camera(rng, spec, (480, 270), "phone", floor_z=-0.78, rail=0.15)
        assert kind == "phone"
        heights.append(cam.position[2] + 0.78)
    assert 0.8 <= min(heights) < 1.1 and 1.6 < max(heights) <= 1.95


def test_portrait_frames_swap_the_size_and_keep_labels_exact():
    rend = render(4, SIZE, camera_kind="phone", portrait=1.0)
    assert rend.image.shape == (SIZE[0], SIZE[1], 3)
    assert rend.labels["image_size"] == [SIZE[1], SIZE[0]] == rend.labels["camera"]["image_size"]
    assert rend.labels["camera"]["orientation"] == "portrait"
    cam = camera_of(rend.labels)
    spec = scene_of(4).spec
    for entry, xy in zip(rend.labels["corners"], spec.corners, strict=True):
        assert np.allclose(entry["px_cloth"], cam.project_table(xy), atol=2e-3)
    for entry, pocket in zip(rend.labels["pockets"], spec.pockets, strict=True):
        assert np.allclose(entry["px"], cam.project_table(pocket.aim), atol=2e-3)
    checked = 0
    for i, ball in enumerate(rend.labels["balls"]):
        if ball["labelled"] and ball["occluded_fraction"] == 0:
            u, v = ball["centre_px"]
            assert rend.ids[int(v), int(u)] == sc.ID_BALL0 + i
            checked += 1
    assert checked >= 1


def test_portrait_share_leaves_landscape_scenes_unchanged():
    again = 0
    for seed in range(6):
        half = render(seed, SIZE, camera_kind="phone", portrait=0.5)
        if half.labels["camera"]["orientation"] == "landscape":
            plain = render(seed, SIZE, camera_kind="phone")
            assert half.image.tobytes() == plain.image.tobytes() and half.labels == plain.labels
            again += 1
    assert 1 <= again <= 5


def test_portrait_is_deterministic():
    a = render(2, SIZE, camera_kind="phone", portrait=1.0)
    b = render(2, SIZE, camera_kind="phone", portrait=1.0)
    assert a.image.tobytes() == b.image.tobytes() and a.labels == b.labels


@pytest.mark.parametrize("share", [-0.1, 1.5])
def test_bad_portrait_share(share):
    with pytest.raises(ValueError, match="portrait"):
        render(0, SIZE, portrait=share)

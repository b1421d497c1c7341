"""Render one labelled sample from a seed: layout -> scene -> camera -> ray cast -> occluders -> camera
pipeline -> labels."""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass, replace

import cv2
import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.table import TABLE_PRESETS, TableSpec
from pix2pockets.state.ball_set import BallSet, parse_ball_set
from pix2pockets.synth import effects as fx
from pix2pockets.synth import people, props, render_pass
from pix2pockets.synth import scene_codes as sc
from pix2pockets.synth.cameras import PHONE_KINDS, VIEW_KINDS, draw_camera_kind, sample_camera
from pix2pockets.synth.labels import build_labels, camera_dict, sphere_outline_px
from pix2pockets.synth.layouts import sample_layout
from pix2pockets.synth.scene import Scene, sample_scene
from pix2pockets.synth.textures import digit_bitmaps

RENDERER_VERSION = 3
"""What a seed draws. The same seed gives the same scene, camera and photo within a version; a change to what a seed
draws bumps it, so a test set named by its seeds and this version can be rendered again. 1: the first renderer (the
detector recipe's chunks 101-110); 2: American sets on tables with sights; 3: pub, home and UK builds (plain rails,
other sights, coin-op tables) and blackball sets."""
DEFAULT_SIZE = (960, 540)
TABLE_SIZES = {"9ft": 0.45, "8ft": 0.25, "7ft": 0.25, "6ft": 0.05}
"""Table presets (``geometry.table.TABLE_PRESETS``) and their shares."""
BLACKBALL_TABLE_SIZES = {"uk7": 0.7, "uk6": 0.3}
"""UK table presets for a blackball set and their shares."""
OWNED_BUILDS = ("pub", "home")
"""Builds of tables people own (``builds.BUILD_WEIGHTS``), photographed by phones more often."""

Seed = int | Sequence[int]


@dataclass(frozen=True, eq=False)
class Render:
    """One rendered image with everything known about it.

    Attributes:
        image: RGB uint8 (H, W, 3).
        ids: object id per pixel from the ray caster (H, W) int16 (``scene_codes.ID_*``), before 2-D occluders.
        occluded: pixels covered by 2-D occluders and overlays (H, W) bool.
        labels: the label dict written as JSON (see ``docs/synth.md``).
    """

    image: np.ndarray
    ids: np.ndarray
    occluded: np.ndarray
    labels: dict


RAIL_CLUTTER = {"pub": 0.35, "home": 0.3}
"""Share of scenes, by room, with 1-3 glasses, bottles or phones standing or lying on the rails."""

STRETCH_PROBABILITY = 0.2
"""Share of single views rendered with non-square pixels (photos resized to another aspect ratio, as
Roboflow exports stretch them)."""


def stretch_pixels(cam: PinholeCamera, aspect: float) -> PinholeCamera:
    """The same camera with its horizontal focal length scaled by ``aspect`` (non-square pixels), as if the
    photo had been resized horizontally by ``aspect`` about the image centre."""
    K = cam.K.copy()
    K[0, 0] *= aspect
    return replace(cam, K=K)


def _streams(seed: Seed, n: int) -> list[np.random.Generator]:
    entropy = [int(seed)] if np.isscalar(seed) else [int(s) for s in seed]
    if any(s < 0 for s in entropy):
        raise ValueError(f"seed must be non-negative, got {seed!r}")
    return [np.random.default_rng(s) for s in np.random.SeedSequence(entropy).spawn(n)]


def parse_size(text: str) -> tuple[int, int]:
    """Parse ``"960x540"`` into (width, height)."""
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise ValueError(f"image size must look like 960x540, got {text!r}") from None
    if not (16 <= w <= 8192 and 16 <= h <= 8192):
        raise ValueError(f"image size {w}x{h} out of range (16-8192 px per side)")
    return w, h


def trace(
    scene: Scene, cam: PinholeCamera, diamonds: bool = True
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Ray cast ``scene`` through ``cam``: raw RGB (H, W, 3) float32, ids (H, W) int16, depth along each
    ray (H, W) float32 [m], silhouette pixel counts per ball (n,). ``diamonds=False`` leaves the sights out
    (plain rail caps), for measuring how much each diamond shows."""
    w, h = cam.image_size
    rgb = np.zeros((h, w, 3), np.float32)
    ids = np.zeros((h, w), np.int16)
    depth = np.zeros((h, w), np.float32)
    sil = _trace_into(scene, cam, diamonds, rgb, ids, depth, np.ones((h, w), np.uint8))
    return rgb, ids, depth, sil


DIAMOND_RETRACE_MARGIN_PX = 2
"""Pixels this close to a diamond pixel are traced again without the diamonds: the diamond pixels, their
anti-aliased edges, and the neighbours that decide whether those are edges."""


def trace_without_diamonds(
    scene: Scene, cam: PinholeCamera, raw: np.ndarray, ids: np.ndarray, depth: np.ndarray
) -> np.ndarray:
    """Raw RGB (H, W, 3) of the view of :func:`trace`'s ``raw, ids, depth`` with plain rail caps.

    Only the pixels within :data:`DIAMOND_RETRACE_MARGIN_PX` of a diamond pixel are traced again; every
    other pixel is the same with or without the sights and is copied. Same result as
    ``trace(scene, cam, diamonds=False)[0]`` for a fraction of the cost.
    """
    on_diamond = (ids >= sc.ID_DIAMOND0) & (ids < sc.ID_DIAMOND0 + len(scene.spec.diamonds))
    side = 2 * DIAMOND_RETRACE_MARGIN_PX + 1
    mask = cv2.dilate(on_diamond.astype(np.uint8), np.ones((side, side), np.uint8))
    rgb, ids_plain, depth_plain = raw.copy(), ids.copy(), depth.copy()
    if mask.any():
        _trace_into(scene, cam, False, rgb, ids_plain, depth_plain, mask)
    return rgb


def _trace_into(
    scene: Scene,
    cam: PinholeCamera,
    diamonds: bool,
    rgb: np.ndarray,
    ids: np.ndarray,
    depth: np.ndarray,
    mask: np.ndarray,
) -> np.ndarray:
    """Trace the pixels where ``mask`` is set into ``rgb``, ``ids``, ``depth``; returns silhouette counts."""
    w, h = cam.image_size
    centres = scene.ball_centres
    n = len(centres)
    bboxes = np.full((n, 4), -1, np.int64)
    for i, c in enumerate(centres):
        outline = sphere_outline_px(cam, c, c[2])  # centre height = radius
        if outline is None:
            if cam.world_to_camera(c)[2] > -c[2]:
                bboxes[i] = [0, 0, w, h]
            continue
        lo = np.floor(outline.min(axis=0)) - 2
        hi = np.ceil(outline.max(axis=0)) + 2
        bboxes[i] = [max(lo[0], -1), max(lo[1], -1), min(hi[0], w + 1), min(hi[1], h + 1)]
    cols, kinds, nums = scene.ball_arrays()
    sil = np.zeros(n, np.int64)
    render_pass.render_scene(
        np.linalg.inv(cam.K),
        cam.R.T.copy(),
        cam.position,
        w,
        h,
        scene.geo,
        scene.shade,
        scene.mats,
        scene.holes,
        scene.sights.astype(np.float64) if diamonds else np.zeros((0, 2)),
        centres.reshape(-1, 3).astype(np.float64),
        scene.rotations.reshape(-1, 3, 3).astype(np.float64),
        cols,
        kinds,
        nums,
        bboxes,
        scene.lights,
        digit_bitmaps(),
        scene.noise,
        scene.grain,
        scene.floor_tex,
        scene.wall_tex,
        rgb,
        ids,
        depth,
        sil,
        mask,
    )
    return sil


def _exposure(scene: Scene, rgb: np.ndarray, ids: np.ndarray) -> float:
    """Auto-exposure: put the median lit cloth (or the median image) near mid-grey brightness."""
    table = (ids == sc.ID_CLOTH) | (ids == sc.ID_CUSHION)
    lum = fx.channel_mean(rgb)
    ref = float(np.median(lum[table])) if table.sum() > 200 else float(np.median(lum))
    cloth_albedo = float(scene.mats[sc.M_CLOTH].mean())
    target = np.clip(cloth_albedo, 0.08, 0.5) * 1.1 if table.sum() > 200 else 0.35
    return float(target / max(ref, 1e-4))


def _clearance(capsules: list, cam: PinholeCamera) -> float:
    """Smallest distance from the camera centre to any capsule's surface [m]."""
    c = cam.position
    best = np.inf
    for p0, p1, r0, r1, _ in capsules:
        seg = p1 - p0
        s = float(np.clip(np.dot(c - p0, seg) / max(float(np.dot(seg, seg)), 1e-12), 0.0, 1.0))
        best = min(best, float(np.linalg.norm(p0 + s * seg - c)) - max(r0, r1))
    return best


def _add_occluders(
    img: np.ndarray,
    depth: np.ndarray,
    scene: Scene,
    cam: PinholeCamera,
    kind: str,
    rng: np.random.Generator,
    strength: float,
) -> tuple[np.ndarray, list[str]]:
    """Players, bystanders, cue sticks, chalk (z-buffered 3-D figures) and broadcast overlays (2-D)."""
    h, w = img.shape[:2]
    mask = np.zeros((h, w), bool)
    depth = depth.copy()
    used = []
    centres = scene.ball_centres
    spec = scene.spec
    phone = kind.startswith("phone")
    lighting = scene.style.get("lighting")
    # lamp shades over pub tables (a top-down camera hangs among or above them: skip there)
    if lighting in ("pub_lamps", "warm_pub") and kind != "top" and rng.random() < 0.8:
        people.draw_figure(img, mask, depth, cam, props.lamp_shades(rng, scene.lights, float(scene.geo[sc.G_ZC])))
        used.append("lamps")
    for _ in range(int(rng.poisson(0.8 if scene.style.get("room") != "arena" else 0.2))):
        ang = rng.uniform(-np.pi, np.pi)
        reach = scene.rail_width + rng.uniform(0.4, 2.0)
        xy = spec.size / 2 + (spec.size / 2 + reach) * np.array([np.cos(ang), np.sin(ang)])
        people.draw_figure(img, mask, depth, cam, props.bar_stool(rng, xy, scene.floor_z))
        used.append("stool")
    if rng.random() < 0.08:
        xy = rng.uniform([0.2, 0.2], spec.size - 0.2)
        people.draw_figure(img, mask, depth, cam, props.triangle_rack(rng, xy, 0.02, rng.uniform(0.3, 0.36)))
        used.append("rack")
    if rng.random() < RAIL_CLUTTER.get(scene.style.get("room", ""), 0.0):
        for _ in range(int(rng.integers(1, 4))):
            k = int(rng.integers(4))
            s = rng.uniform(0.03, 0.97)
            off = scene.geo[sc.G_CW] + (scene.rail_width - scene.geo[sc.G_CW]) * rng.uniform(0.35, 0.65)
            xy = [(s * spec.length, -off), (spec.length + off, s * spec.width), (s * spec.length, spec.width + off),
                  (-off, s * spec.width)][k]  # fmt: skip
            name = str(rng.choice(list(props.RAIL_CLUTTER), p=[0.5, 0.3, 0.2]))
            item = props.RAIL_CLUTTER[name](rng, np.array([*xy, scene.geo[sc.G_HR]]))
            people.draw_figure(img, mask, depth, cam, item, 0.5)
            used.append(name)
    if len(centres) and rng.random() < 0.4 * strength:
        cue_i = scene.layout.cue_index
        i = cue_i if cue_i is not None and rng.random() < 0.75 else int(rng.integers(len(centres)))
        body, cue = people.shooting_player(
            rng, centres[i, :2], spec.size, scene.rail_width, scene.floor_z, spec.ball_radius
        )
        people.draw_figure(img, mask, depth, cam, cue, gloss=0.4)
        if rng.random() < 0.85 and _clearance(body, cam) > 0.5:
            people.draw_figure(img, mask, depth, cam, body)
            used.append("player")
        used.append("cue_stick")
    n_people = int(rng.poisson((0.9 if phone else 0.5) * strength))
    for _ in range(min(n_people, 4)):
        people.draw_figure(
            img, mask, depth, cam, people.standing_person(rng, spec.size, scene.rail_width, scene.floor_z)
        )
        used.append("person")
    if rng.random() < 0.12 * strength:  # a cue lying on the table or leaning over a rail
        xy = rng.uniform([0.1, 0.1], spec.size - 0.1)
        a = rng.uniform(0, 2 * np.pi)
        tip = np.array([xy[0], xy[1], 0.015])
        rise = 0.0 if rng.random() < 0.5 else rng.uniform(0.05, 0.6)
        people.draw_figure(img, mask, depth, cam, people.cue_capsules(rng, tip, np.array([np.cos(a), np.sin(a)]), rise))
        used.append("cue_stick")
    if phone and rng.random() < 0.06 * strength:
        fx.draw_arm(img, mask, rng, None)
        used.append("arm")
    if rng.random() < 0.25 * strength:
        k = int(rng.integers(4))
        s = rng.uniform(0.05, 0.95)
        off = scene.geo[sc.G_CW] + (scene.rail_width - scene.geo[sc.G_CW]) * rng.uniform(0.2, 0.8)
        xy = [(s * spec.length, -off), (spec.length + off, s * spec.width), (s * spec.length, spec.width + off),
              (-off, s * spec.width)][k]  # fmt: skip
        fx.draw_chalk(img, mask, rng, cam, np.array([xy[0], xy[1], scene.geo[sc.G_HR]]))
        used.append("chalk")
    broadcast = scene.style.get("room") == "arena"
    if not phone and rng.random() < (0.45 if broadcast else 0.08) * strength:
        fx.draw_scoreboard(img, mask, rng)
        used.append("scoreboard")
    if rng.random() < (0.25 if broadcast else 0.04) * strength:
        fx.draw_logo(img, mask, rng)
        used.append("logo")
    return mask, used


def _photograph(
    raw: np.ndarray,
    depth: np.ndarray,
    scene: Scene,
    cam: PinholeCamera,
    kind: str,
    exposure: float,
    rng: np.random.Generator,
    strength: float,
) -> tuple[np.ndarray, np.ndarray, list[str], dict]:
    """Raw radiance -> uint8 photo: tone map, occluders, camera pipeline. Returns the image, the occluder
    mask, the occluders drawn and the pipeline's settings."""
    img = fx.tone_map(raw, exposure, rng.uniform(0.85, 1.2), rng.uniform(0.75, 1.25))
    occluded, used = _add_occluders(img, depth, scene, cam, kind, rng, strength)
    image, pipeline = fx.camera_pipeline(img, rng, strength)
    return image, occluded, used, pipeline


def diamond_signal(
    image: np.ndarray,
    scene: Scene,
    cam: PinholeCamera,
    kind: str,
    raw: np.ndarray,
    ids: np.ndarray,
    depth: np.ndarray,
    exposure: float,
    rng: np.random.Generator,
    strength: float,
) -> np.ndarray:
    """How much the diamonds change each pixel of the finished ``image`` (H, W) [0-255, largest channel].

    The photo is taken again without the diamonds, with ``rng`` in the state the first photo started from
    (same occluders, blur, noise and compression), so what is left is what the diamonds add: whether a
    sight can be seen at all after blur and against its rail.
    """
    raw_plain = trace_without_diamonds(scene, cam, raw, ids, depth)
    plain = _photograph(raw_plain, depth, scene, cam, kind, exposure, rng, strength)[0]
    return fx.channel_max(np.abs(image.astype(np.int16) - plain.astype(np.int16)))


def render_scene_view(
    scene: Scene, cam: PinholeCamera, kind: str, rng: np.random.Generator, strength: float = 1.0
) -> Render:
    """Render ``scene`` through ``cam`` with occluders and the camera pipeline drawn from ``rng``."""
    raw, ids, depth, sil = trace(scene, cam)
    exposure = _exposure(scene, raw, ids) * rng.uniform(0.75, 1.3)
    rng_plain = copy.deepcopy(rng) if scene.has_sights else None
    image, occluded, used, pipeline = _photograph(raw, depth, scene, cam, kind, exposure, rng, strength)
    signal = None
    if rng_plain is not None:  # plain rails: no sight to measure
        signal = diamond_signal(image, scene, cam, kind, raw, ids, depth, exposure, rng_plain, strength)
    labels = build_labels(scene, cam, ids, occluded, sil, diamond_signal=signal)
    labels["image_size"] = list(cam.image_size)
    labels["camera"] = camera_dict(cam, kind)
    labels["style"] = {k: v for k, v in scene.style.items() if k != "ball_jitter"}
    labels["ball_set"] = scene.ball_set.value
    labels["effects"] = {"exposure": round(exposure, 4), "occluders": used, **pipeline}
    return Render(image=image, ids=ids, occluded=occluded, labels=labels)


def _spec(rng: np.random.Generator, ball_set: BallSet = BallSet.AMERICAN) -> TableSpec:
    sizes = BLACKBALL_TABLE_SIZES if ball_set is BallSet.BLACKBALL else TABLE_SIZES
    keys = list(sizes)
    p = np.array([sizes[k] for k in keys])
    return TABLE_PRESETS[keys[int(rng.choice(len(keys), p=p / p.sum()))]]


def _scene_and_streams(
    seed: Seed, layout_mode: str | None = None, ball_set: BallSet | str = BallSet.AMERICAN
) -> tuple[Scene, str, np.random.Generator, np.random.Generator]:
    """The scene of ``seed`` (its layout of mode ``layout_mode``, random when None; a blackball set on a UK table),
    that mode, and the camera and effects streams that follow it."""
    ball_set = parse_ball_set(ball_set)
    r_layout, r_scene, r_cam, r_fx = _streams(seed, 4)
    spec = _spec(r_layout, ball_set)
    layout, mode = sample_layout(r_layout, spec, layout_mode)
    return sample_scene(r_scene, layout, ball_set=ball_set), mode, r_cam, r_fx


def scene_of(seed: Seed, ball_set: BallSet | str = BallSet.AMERICAN) -> Scene:
    """The 3-D scene (layout, ball rotations, materials) that :func:`render` draws for ``seed``, unrendered."""
    return _scene_and_streams(seed, ball_set=ball_set)[0]


def render(
    seed: Seed,
    size: tuple[int, int] = DEFAULT_SIZE,
    camera_kind: str | Sequence[str] | None = None,
    layout_mode: str | None = None,
    portrait: float = 0.0,
    ball_set: BallSet | str = BallSet.AMERICAN,
) -> Render:
    """Render the sample of ``seed`` (same seed -> identical pixels and labels).

    Args:
        seed: non-negative int or sequence of ints (e.g. ``(dataset_seed, index)``).
        size: (width, height) [px] of a landscape frame.
        camera_kind: force a camera kind (see ``cameras.CAMERA_KINDS``), or draw among several kinds (their
            ``CAMERA_KINDS`` probabilities, phone kinds weighted up for pub and home tables); drawn among all when
            ``None``.
        layout_mode: force a layout mode (see ``layouts.LAYOUT_MODES``, e.g. ``"rack"``); random when ``None``.
        portrait: share of phone views (``cameras.PHONE_KINDS``) held upright: rendered at (height, width). The
            draw is made for every scene, so a scene that stays landscape renders the same at any share.
        ball_set: ``american`` (numbered balls on American tables) or ``blackball`` (7 reds, 7 yellows and the
            black on UK 7- and 6-foot tables; reds are labelled with the solid class, yellows with the stripe class,
            :mod:`pix2pockets.state.ball_set`).
    """
    if not 0.0 <= portrait <= 1.0:
        raise ValueError(f"portrait must be a share in [0, 1], got {portrait!r}")
    scene, mode, r_cam, r_fx = _scene_and_streams(seed, layout_mode, ball_set)
    kind = draw_camera_kind(r_cam, camera_kind, owned=scene.style.get("build") in OWNED_BUILDS)
    upright = r_cam.random() < portrait and kind in PHONE_KINDS
    if upright:
        size = (size[1], size[0])
    cam, kind = sample_camera(r_cam, scene.spec, size, kind, scene.floor_z, scene.rail_width)
    if r_cam.random() < STRETCH_PROBABILITY:
        cam = stretch_pixels(cam, float(np.exp(r_cam.uniform(np.log(0.75), np.log(1.33)))))
    out = render_scene_view(scene, cam, kind, r_fx)
    out.labels["layout_mode"] = mode
    out.labels["seed"] = [int(seed)] if np.isscalar(seed) else [int(s) for s in seed]
    return out


def render_sample(
    seed: Seed, size: tuple[int, int] = DEFAULT_SIZE, camera_kind: str | None = None, portrait: float = 0.0
) -> tuple[np.ndarray, dict]:
    """One labelled synthetic photo: (RGB uint8 image (H, W, 3), label dict). Deterministic in ``seed``.

    Example:
        >>> image, labels = render_sample(7, size=(320, 180))
        >>> image.shape
        (180, 320, 3)
    """
    out = render(seed, size, camera_kind, portrait=portrait)
    return out.image, out.labels


def render_views(
    seed: Seed,
    size: tuple[int, int] = DEFAULT_SIZE,
    views: Sequence[str] = VIEW_KINDS,
    layout_mode: str | None = None,
    ball_set: BallSet | str = BallSet.AMERICAN,
) -> list[Render]:
    """One layout (of mode ``layout_mode``, random when None) and scene seen from several cameras (default top,
    ~45 degrees, front) for the view-to-view projection-error experiment. Effects are lighter than in single
    views."""
    scene, mode, r_cam, r_fx = _scene_and_streams(seed, layout_mode, ball_set)
    out = []
    for view in views:
        cam, kind = sample_camera(r_cam, scene.spec, size, view, scene.floor_z, scene.rail_width, crop=False)
        rend = render_scene_view(scene, cam, kind, r_fx, strength=0.3)
        rend.labels["layout_mode"] = mode
        rend.labels["view"] = view
        rend.labels["seed"] = [int(seed)] if np.isscalar(seed) else [int(s) for s in seed]
        out.append(rend)
    return out

"""Camera sampling like real pool footage: broadcast top-down, high 45-degree, low front/side, camera
jibs, and hand-held phone photos (standing, sitting or crouched beside a rail or off a corner: tilt, roll, partial
crops, close and far, landscape or portrait).

Every camera is a :class:`~pix2pockets.geometry.camera.PinholeCamera` built with ``look_at``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.table import TableSpec

CAMERA_KINDS: dict[str, float] = {
    "top": 0.18,
    "high": 0.20,
    "low": 0.12,
    "jib": 0.15,
    "phone": 0.27,
    "phone_low": 0.08,
}
"""Camera kinds and their sampling probabilities."""

PHONE_KINDS = ("phone", "phone_low")
"""Hand-held kinds: the ones that may be turned to portrait."""

OWNED_TABLE_PHONE_WEIGHT = 2.0
"""Pub and home tables are photographed by phones: their phone kinds' weights are multiplied by this."""

BROADCAST_KINDS = ("top", "high", "jib")
"""The kinds a TV broadcast shows the whole table from: overhead, a high end view, a camera jib."""

CAMERA_GROUPS: dict[str, tuple[str, ...]] = {"broadcast": BROADCAST_KINDS}
"""Names for sets of camera kinds (accepted wherever a list of kinds is)."""


def camera_kinds(names: str | Sequence[str]) -> tuple[str, ...]:
    """Camera kinds from names of kinds or groups (comma-separated, in one string or several), in
    :data:`CAMERA_KINDS` order, without repeats.

    Raises:
        ValueError: an unknown name, or none at all.
    """
    known = ", ".join([*CAMERA_KINDS, *CAMERA_GROUPS])
    chosen: set[str] = set()
    for part in [names] if isinstance(names, str) else names:
        for name in (n.strip() for n in part.split(",")):
            if name in CAMERA_GROUPS:
                chosen.update(CAMERA_GROUPS[name])
            elif name in CAMERA_KINDS:
                chosen.add(name)
            elif name:
                raise ValueError(f"unknown camera kind {name!r}; choose from {known}")
    if not chosen:
        raise ValueError(f"no camera kind given; choose from {known}")
    return tuple(k for k in CAMERA_KINDS if k in chosen)


VIEW_KINDS = ("top", "high", "front")
"""The three views of a multi-view set (top-down, about 45 degrees, low from an end rail)."""


PHONE_MIN_COVERAGE = 0.12
"""A phone view is kept when the cloth covers at least this share of the frame."""
PHONE_LOW_LIFT = 0.3
"""Phones held lower than this above the cloth [m] see it as a thin band ..."""
PHONE_LOW_MIN_COVERAGE = 0.06
"""... and are kept from this cloth share of the frame."""


def focal_from_hfov(width: int, hfov: float) -> float:
    """Focal length [px] for a horizontal field of view ``hfov`` [rad]."""
    return (width / 2) / math.tan(hfov / 2)


def _direction(elevation: float, azimuth: float) -> np.ndarray:
    """Unit vector from the target toward the eye, elevation above the cloth and azimuth from +x [rad]."""
    ce = math.cos(elevation)
    return np.array([ce * math.cos(azimuth), ce * math.sin(azimuth), math.sin(elevation)])


def _outline(spec: TableSpec, rail: float) -> np.ndarray:
    """Points around the outer rail edge at cushion height [m], shape (12, 3)."""
    L, W = spec.length, spec.width
    xs = [-rail, L / 2, L + rail]
    ys = [-rail, W / 2, W + rail]
    pts = [(x, y, 0.04) for x in xs for y in ys if not (x == L / 2 and y == W / 2)]
    return np.array(pts, dtype=float)


def fit_camera(
    spec: TableSpec,
    direction: np.ndarray,
    target: np.ndarray,
    hfov: float,
    size: tuple[int, int],
    fill: float,
    roll: float = 0.0,
    up: np.ndarray | None = None,
    rail: float = 0.14,
) -> PinholeCamera:
    """A camera looking at ``target`` from ``direction`` whose distance makes the table fill ``fill`` of
    the frame (1 = the outer rails touch the image border; > 1 crops the table)."""
    f = focal_from_hfov(size[0], hfov)
    pts = _outline(spec, rail)
    dist = 5.0
    for _ in range(6):
        cam = PinholeCamera.look_at(target + direction * dist, target, f, size, roll=roll, up=up)
        uv = cam.project(pts)
        if np.any(~np.isfinite(uv)):
            dist *= 2.0
            continue
        ex = np.max(np.abs(uv[:, 0] - size[0] / 2)) / (size[0] / 2)
        ey = np.max(np.abs(uv[:, 1] - size[1] / 2)) / (size[1] / 2)
        dist *= max(ex, ey) / fill
        dist = float(np.clip(dist, 0.5, 40.0))
    return PinholeCamera.look_at(target + direction * dist, target, f, size, roll=roll, up=up)


def table_coverage(cam: PinholeCamera, spec: TableSpec, grid: tuple[int, int] = (24, 14)) -> float:
    """Fraction of the image (sampled on a grid) that shows the playing surface."""
    w, h = cam.image_size
    us = (np.arange(grid[0]) + 0.5) / grid[0] * w
    vs = (np.arange(grid[1]) + 0.5) / grid[1] * h
    uu, vv = np.meshgrid(us, vs)
    pix = np.stack([uu.ravel(), vv.ravel(), np.ones(uu.size)])
    rays = cam.R.T @ np.linalg.solve(cam.K, pix)
    c = cam.position
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -c[2] / rays[2]
    xy = c[:2, None] + t * rays[:2]
    ok = (t > 0) & spec.contains(xy.T)
    return float(np.mean(ok))


def _side_or_end_azimuth(rng: np.random.Generator, spread: float) -> float:
    """An azimuth mostly facing a long rail (broadcast main camera) or a short rail."""
    u = rng.random()
    if u < 0.6:
        base = -math.pi / 2 if rng.random() < 0.5 else math.pi / 2
    elif u < 0.85:
        base = 0.0 if rng.random() < 0.5 else math.pi
    else:
        base = rng.uniform(-math.pi, math.pi)
    return base + rng.normal(0.0, spread)


def draw_camera_kind(rng: np.random.Generator, kind: str | Sequence[str] | None = None, owned: bool = False) -> str:
    """One camera kind: ``kind`` itself when it is one name, else drawn among the given kinds (all of
    :data:`CAMERA_KINDS` for ``None``) with their :data:`CAMERA_KINDS` probabilities; ``owned`` (a pub or home
    table) weights the phone kinds by :data:`OWNED_TABLE_PHONE_WEIGHT`."""
    if isinstance(kind, str):
        return kind
    keys = list(CAMERA_KINDS) if kind is None else list(camera_kinds(kind))
    p = np.array([CAMERA_KINDS[k] * (OWNED_TABLE_PHONE_WEIGHT if owned and k in PHONE_KINDS else 1.0) for k in keys])
    return keys[int(rng.choice(len(keys), p=p / p.sum()))]


def _phone_eye(rng: np.random.Generator, spec: TableSpec, rail: float, lift: float) -> np.ndarray:
    """Where a person holds a phone, ``lift`` [m] above the cloth: beside a rail or off a corner, 0.05-1.5 m out
    from the rail's outer edge, or leaning over the rail when high enough [m]."""
    L, W = spec.length, spec.width
    out = rng.uniform(0.05, 1.5)
    if lift > 0.4 and rng.random() < 0.15:  # leaning over the rail
        out = -rng.uniform(0.0, rail + 0.25)
    if rng.random() < 0.35:  # off a corner
        sx, sy = rng.choice([-1.0, 1.0], 2)
        a = math.atan2(sy, sx) + rng.normal(0.0, 0.3)
        corner = np.array([L / 2 + sx * L / 2, W / 2 + sy * W / 2])
        return corner + (rail * math.sqrt(2) + out) * np.array([math.cos(a), math.sin(a)])
    s = rng.uniform(-0.05, 1.05)
    if rng.random() < L / (L + W):  # a long rail
        sy = 1.0 if rng.random() < 0.5 else -1.0
        return np.array([s * L, W / 2 + sy * (W / 2 + rail + out)])
    sx = 1.0 if rng.random() < 0.5 else -1.0
    return np.array([L / 2 + sx * (L / 2 + rail + out), s * W])


def sample_camera(
    rng: np.random.Generator,
    spec: TableSpec,
    size: tuple[int, int],
    kind: str | Sequence[str] | None = None,
    floor_z: float = -0.78,
    rail: float = 0.14,
    crop: bool = True,
) -> tuple[PinholeCamera, str]:
    """A camera of the given kind or a multi-view kind (``"front"``); given several kinds, or ``None`` (all of
    :data:`CAMERA_KINDS`), one is drawn with the :data:`CAMERA_KINDS` probabilities. ``crop=False`` keeps the
    whole table in a top view. Returns the camera and its kind."""
    kind = draw_camera_kind(rng, kind)
    centre = np.array([spec.length / 2, spec.width / 2, 0.0])
    if kind == "top":
        el = math.radians(rng.uniform(80.0, 89.5))
        az = rng.uniform(-math.pi, math.pi)
        up = np.array([0.0, 1.0 if rng.random() < 0.5 else -1.0, 0.0])
        fill = rng.uniform(0.78, 1.0) if rng.random() < 0.85 else rng.uniform(1.0, 1.35)
        if not crop:
            fill = min(fill, 0.95)
        target = centre + np.array([rng.normal(0, 0.04), rng.normal(0, 0.04), 0.0])
        cam = fit_camera(
            spec, _direction(el, az), target, math.radians(rng.uniform(25, 60)), size, fill,
            roll=math.radians(rng.normal(0, 1.0)), up=up, rail=rail,
        )  # fmt: skip
        return cam, kind
    if kind in ("high", "low", "jib", "front"):
        if kind == "high":
            el, az, hfov = rng.uniform(35, 60), _side_or_end_azimuth(rng, 0.35), rng.uniform(30, 65)
            fill, roll, jit = rng.uniform(0.75, 1.05), rng.normal(0, 1.5), 0.05
        elif kind == "low":
            el, az, hfov = rng.uniform(9, 30), _side_or_end_azimuth(rng, 0.45), rng.uniform(35, 70)
            fill, roll, jit = rng.uniform(0.8, 1.15), rng.normal(0, 2.0), 0.1
        elif kind == "front":
            el, hfov = rng.uniform(14, 26), rng.uniform(40, 60)
            az = (0.0 if rng.random() < 0.5 else math.pi) + rng.normal(0, 0.1)
            fill, roll, jit = rng.uniform(0.85, 1.0), rng.normal(0, 1.0), 0.03
        else:
            el, az, hfov = rng.uniform(20, 75), rng.uniform(-math.pi, math.pi), rng.uniform(35, 75)
            fill = rng.uniform(0.65, 1.0) if rng.random() < 0.7 else rng.uniform(1.0, 1.5)
            roll, jit = rng.normal(0, 4.0), 0.25
        target = centre + np.array([rng.normal(0, jit) * spec.length / 2, rng.normal(0, jit) * spec.width / 2, 0.0])
        cam = fit_camera(
            spec, _direction(math.radians(el), az), target, math.radians(hfov), size, fill,
            roll=math.radians(roll), rail=rail,
        )  # fmt: skip
        return cam, kind
    if kind in ("phone", "phone_low"):
        for _ in range(40):
            # stand (or sit) beside a rail or off a corner, look at a point on the table
            min_cover = PHONE_MIN_COVERAGE
            if kind == "phone":
                eye_z = floor_z + rng.uniform(0.8, 1.95)
                eye_xy = _phone_eye(rng, spec, rail, eye_z)
                if eye_z < PHONE_LOW_LIFT:  # held about at rail height: the cloth is a thin band
                    min_cover = PHONE_LOW_MIN_COVERAGE
                target = np.array([rng.uniform(0, spec.length), rng.uniform(0, spec.width), 0.0])
                hfov = rng.uniform(55, 78) if rng.random() < 0.8 else rng.uniform(25, 50)
                roll = rng.normal(0, 5.0) if rng.random() < 0.85 else rng.uniform(-35, 35)
            else:
                eye_z = rng.uniform(0.12, 0.5)
                s, out = rng.uniform(0.1, 0.9), rail + rng.uniform(0.05, 0.5)
                L, W = spec.length, spec.width
                eye_xy = [np.array([s * L, -out]), np.array([s * L, W + out]), np.array([-out, s * W]),
                          np.array([L + out, s * W])][int(rng.integers(4))]  # fmt: skip
                target = np.array([rng.uniform(0.2, 0.8) * spec.length, rng.uniform(0.2, 0.8) * spec.width, 0.0])
                target[2] = -rng.uniform(0.0, 0.15)
                hfov = rng.uniform(50, 78)
                roll = rng.normal(0, 6.0)
            eye = np.array([eye_xy[0], eye_xy[1], eye_z])
            if np.linalg.norm(target - eye) < 0.3:
                continue
            cam = PinholeCamera.look_at(
                eye, target, focal_from_hfov(size[0], math.radians(hfov)), size, roll=math.radians(roll)
            )
            if table_coverage(cam, spec) >= min_cover:
                return cam, kind
        return sample_camera(rng, spec, size, "jib", floor_z, rail, crop)
    raise ValueError(f"unknown camera kind {kind!r}; choose one of {[*CAMERA_KINDS, 'front']}")

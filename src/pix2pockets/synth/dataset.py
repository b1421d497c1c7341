"""Write a YOLO dataset in the Roboflow export layout, plus one JSON label file per image.

Layout::

    OUT/data.yaml                       names [cue, black, solid, stripe, dot], nc 5, split paths
    OUT/{train,valid,test}/images/*.jpg
    OUT/{train,valid,test}/labels/*.txt  one "class cx cy w h" row per object (normalised)
    OUT/{train,valid,test}/meta/*.json   full labels (see docs/synth.md)
    OUT/manifest.json                   seed, size, counts, split of every image

Sample ``i`` is rendered from the seed sequence ``(seed, i)``, so any image can be reproduced alone.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from pix2pockets.state.ball_set import BallSet
from pix2pockets.synth.cameras import camera_kinds as camera_kinds_of
from pix2pockets.synth.labels import yolo_lines
from pix2pockets.synth.layouts import LAYOUT_MODES
from pix2pockets.synth.renderer import DEFAULT_SIZE, RENDERER_VERSION, Render, render, render_views
from pix2pockets.vision.classes import CLASS_NAMES

SPLITS = ("train", "valid", "test")
JPEG_QUALITY = 93


def parse_split(text: str) -> tuple[float, float, float]:
    """Parse ``"0.8,0.1,0.1"`` into three non-negative fractions summing to 1."""
    try:
        parts = tuple(float(v) for v in text.split(","))
    except ValueError:
        raise ValueError(f"split must be three numbers like 0.8,0.1,0.1, got {text!r}") from None
    if len(parts) != 3 or min(parts) < 0 or abs(sum(parts) - 1.0) > 1e-6:
        raise ValueError(f"split must be three non-negative fractions summing to 1, got {text!r}")
    return parts  # type: ignore[return-value]


def split_assignment(n: int, fractions: Sequence[float], seed: int) -> list[str]:
    """Split name for each of ``n`` scenes: exact counts by rounding, shuffled by ``seed``."""
    counts = [round(n * f) for f in fractions]
    counts[0] = n - counts[1] - counts[2]
    if counts[0] < 0:
        counts[0], counts[2] = 0, n - counts[1]
    names = [s for s, c in zip(SPLITS, counts, strict=True) for _ in range(c)]
    rng = np.random.default_rng([int(seed), 0x5EED])
    rng.shuffle(names)
    return names


def data_yaml() -> str:
    """The Roboflow-style ``data.yaml`` text (split paths relative to the yaml's folder)."""
    names = ", ".join(CLASS_NAMES)
    return (
        "train: train/images\n"
        "val: valid/images\n"
        "test: test/images\n\n"
        f"nc: {len(CLASS_NAMES)}\n"
        f"names: [{names}]\n\n"
        "# pix2pockets synthetic renders; boxes = visible extent of each ball, diamonds padded to >= 4 px\n"
        "# (labelled only when they show in the photo).\n"
    )


def write_sample(root: Path, split: str, stem: str, rend: Render) -> None:
    """Write one render's image, YOLO label rows and meta JSON as ``root/split/{images,labels,meta}/stem.*``."""
    bgr = cv2.cvtColor(rend.image, cv2.COLOR_RGB2BGR)
    if not cv2.imwrite(str(root / split / "images" / f"{stem}.jpg"), bgr, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY]):
        raise OSError(f"could not write image {stem}.jpg")
    rows = yolo_lines(rend.labels)
    (root / split / "labels" / f"{stem}.txt").write_text("".join(r + "\n" for r in rows))
    meta = dict(rend.labels, image=f"{stem}.jpg", split=split)
    (root / split / "meta" / f"{stem}.json").write_text(json.dumps(meta, indent=1))


@dataclass(frozen=True, slots=True)
class SceneJob:
    """What every scene of a dataset shares; scene ``i`` is rendered from ``(seed, i)`` alone.

    Attributes:
        seed: dataset seed.
        size: image (width, height) [px].
        views: 1 (one random camera) or 3 (top, ~45 deg, front).
        kinds: camera kinds to draw from (``None``: all).
        layout_mode: every scene's layout mode (``None``: drawn per scene).
        portrait: share of phone views rendered upright.
        blackball: share of scenes with a blackball set on a UK table (:func:`scene_ball_set`).
    """

    seed: int
    size: tuple[int, int]
    views: int = 1
    kinds: tuple[str, ...] | None = None
    layout_mode: str | None = None
    portrait: float = 0.0
    blackball: float = 0.0


BLACKBALL_STREAM = 0xB1AC
"""Last entry of the seed sequence that draws whether a scene holds a blackball set."""


def scene_ball_set(job: SceneJob, i: int) -> BallSet:
    """The ball set of scene ``i``: blackball for a share ``job.blackball`` of scenes, drawn from its own stream
    ``(seed, i, BLACKBALL_STREAM)`` so that every other scene renders as it would without blackball sets."""
    if job.blackball <= 0.0:
        return BallSet.AMERICAN
    draw = np.random.default_rng([job.seed, i, BLACKBALL_STREAM]).random()
    return BallSet.BLACKBALL if draw < job.blackball else BallSet.AMERICAN


SceneFiles = tuple[dict[str, bytes], list[dict]]
"""One scene's files (path relative to the dataset root -> bytes) and its manifest items."""
SceneMap = Callable[[SceneJob, Sequence[tuple[int, str]]], Iterable[SceneFiles]]
"""Renders ``(scene index, split)`` pairs anywhere (e.g. Ray workers) and yields their files in the same order."""


def write_scene(root: Path, job: SceneJob, i: int, split: str) -> list[dict]:
    """Render scene ``i`` into ``root/split/...``; returns its manifest items."""
    items = []
    ball_set = scene_ball_set(job, i)
    if job.views == 1:
        rend = render(
            (job.seed, i),
            job.size,
            camera_kind=job.kinds,
            layout_mode=job.layout_mode,
            portrait=job.portrait,
            ball_set=ball_set,
        )
        stem = f"synth_{job.seed}_{i:06d}"
        write_sample(root, split, stem, rend)
        items.append({"image": f"{split}/images/{stem}.jpg", "scene": i, "camera": rend.labels["camera"]["kind"]})
    else:
        for rend in render_views((job.seed, i), job.size, layout_mode=job.layout_mode, ball_set=ball_set):
            stem = f"synth_{job.seed}_{i:06d}_{rend.labels['view']}"
            rend.labels["scene_id"] = i
            write_sample(root, split, stem, rend)
            items.append({"image": f"{split}/images/{stem}.jpg", "scene": i, "view": rend.labels["view"]})
    return items


def scene_files(job: SceneJob, scenes: Sequence[tuple[int, str]]) -> list[SceneFiles]:
    """Render ``(index, split)`` scenes into a scratch folder and return their files' bytes (for remote workers:
    the same writer as a local run, so the same bytes)."""
    out = []
    with tempfile.TemporaryDirectory(prefix="synth-shard-") as scratch:
        root = Path(scratch)
        for i, split in scenes:
            for sub in ("images", "labels", "meta"):
                (root / split / sub).mkdir(parents=True, exist_ok=True)
            items = write_scene(root, job, i, split)
            files = {}
            for path in sorted(root.rglob("*")):
                if path.is_file():
                    files[path.relative_to(root).as_posix()] = path.read_bytes()
                    path.unlink()
            out.append((files, items))
    return out


@contextmanager
def staged_dataset(out_dir: str | os.PathLike, force: bool = False) -> Iterator[Path]:
    """A folder ``OUT.partial`` with empty split folders to write a dataset into; it becomes ``out_dir`` only
    when the block finishes, and is removed if it raises (never a half-written dataset).

    Raises:
        ValueError: if ``out_dir`` is a file, or a non-empty folder and not ``force`` (with ``force`` it is
            cleared on entry).
    """
    root = Path(out_dir)
    if root.exists() and not root.is_dir():
        raise ValueError(f"{root} exists and is not a directory")
    if root.exists() and any(root.iterdir()):
        if not force:
            raise ValueError(f"{root} is not empty; use --force to overwrite")
        shutil.rmtree(root)
    tmp = root.with_name(root.name + ".partial")
    shutil.rmtree(tmp, ignore_errors=True)
    for s in SPLITS:
        for sub in ("images", "labels", "meta"):
            (tmp / s / sub).mkdir(parents=True, exist_ok=True)
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    if root.exists():
        root.rmdir()
    tmp.rename(root)


def write_dataset(
    out_dir: str | os.PathLike,
    n: int,
    seed: int = 0,
    size: tuple[int, int] = DEFAULT_SIZE,
    views: int = 1,
    split: Sequence[float] = (0.8, 0.1, 0.1),
    force: bool = False,
    progress: bool = False,
    only_split: str | None = None,
    layout_mode: str | None = None,
    camera_kinds: str | Sequence[str] | None = None,
    portrait: float = 0.0,
    blackball: float = 0.0,
    scene_map: SceneMap | None = None,
) -> dict:
    """Render ``n`` scenes into a YOLO dataset at ``out_dir``.

    Args:
        out_dir: output folder; must be empty or absent unless ``force`` (then it is cleared).
        n: number of scenes; with ``views == 3`` each scene gives three images (top, ~45 deg, front).
        seed: dataset seed; scene ``i`` uses the seed sequence ``(seed, i)``.
        size: image (width, height) [px].
        views: 1 (one random camera per scene) or 3 (multi-view sets).
        split: train/valid/test fractions; all views of a scene share a split.
        force: overwrite a non-empty ``out_dir``.
        progress: show a tqdm progress bar.
        only_split: render only the scenes of this split (``train``, ``valid`` or ``test``): the same images
            as the whole dataset holds there, e.g. a held-out test split without its training scenes.
        layout_mode: every scene's layout of this mode (``layouts.LAYOUT_MODES``, e.g. ``"rack"``); drawn per
            scene when None.
        camera_kinds: draw each scene's camera among these kinds or groups (``cameras.CAMERA_KINDS``,
            ``cameras.CAMERA_GROUPS``, e.g. ``"broadcast"`` or ``"phone,phone_low"``) instead of all; one random
            camera per scene only.
        portrait: share of phone views rendered upright at (height, width) (``render(..., portrait=)``); one random
            camera per scene only.
        blackball: share of scenes with a blackball set (7 reds, 7 yellows, the black) on a UK 7- or 6-foot table;
            reds carry the solid class id, yellows the stripe class id, and each image's meta says ``ball_set``.
        scene_map: renders the scenes elsewhere (e.g. :func:`pix2pockets.scale.synth.ray_scene_map`); the files
            are byte-identical to a local run.

    Returns:
        The manifest (also written to ``out_dir/manifest.json``).
    """
    if n < 1:
        raise ValueError(f"n must be at least 1, got {n}")
    if views not in (1, 3):
        raise ValueError(f"views must be 1 or 3, got {views}")
    if seed < 0:
        raise ValueError(f"seed must be non-negative, got {seed}")
    fractions = tuple(float(f) for f in split)
    if len(fractions) != 3 or min(fractions) < 0 or abs(sum(fractions) - 1) > 1e-6:
        raise ValueError(f"split must be three non-negative fractions summing to 1, got {split!r}")
    if only_split is not None and only_split not in SPLITS:
        raise ValueError(f"only_split must be one of {', '.join(SPLITS)}, got {only_split!r}")
    if layout_mode is not None and layout_mode not in LAYOUT_MODES:
        raise ValueError(f"layout_mode must be one of {', '.join(LAYOUT_MODES)}, got {layout_mode!r}")
    kinds = None if camera_kinds is None else camera_kinds_of(camera_kinds)
    if kinds is not None and views != 1:
        raise ValueError("camera kinds apply to one random camera per scene (views 1); views 3 are top, 45 deg, front")
    if not 0.0 <= portrait <= 1.0:
        raise ValueError(f"portrait must be a share in [0, 1], got {portrait!r}")
    if portrait > 0 and views != 1:
        raise ValueError("portrait frames apply to one random camera per scene (views 1)")
    if not 0.0 <= blackball <= 1.0:
        raise ValueError(f"blackball must be a share in [0, 1], got {blackball!r}")
    assignment = split_assignment(n, fractions, seed)
    items = []
    todo = [(i, assignment[i]) for i in range(n) if only_split is None or assignment[i] == only_split]
    job = SceneJob(seed, tuple(size), views, None if kinds is None else tuple(kinds), layout_mode, portrait, blackball)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=len(todo), desc="synth", unit="scene" if views > 1 else "img")
    with staged_dataset(out_dir, force) as tmp:
        if scene_map is None:
            for i, s in todo:
                items.extend(write_scene(tmp, job, i, s))
                if bar is not None:
                    bar.update(1)
        else:
            for files, scene_items in scene_map(job, todo):
                for rel, data in files.items():
                    (tmp / rel).write_bytes(data)
                items.extend(scene_items)
                if bar is not None:
                    bar.update(1)
        if bar is not None:
            bar.close()
        manifest = {
            "generator": "pix2pockets.synth",
            "renderer_version": RENDERER_VERSION,
            "seed": seed,
            "n_scenes": n,
            "views": views,
            "layout_mode": layout_mode,
            "camera_kinds": None if kinds is None else list(kinds),
            "size": list(size),
            "portrait": portrait,
            "blackball": blackball,
            "split": list(fractions),
            "classes": list(CLASS_NAMES),
            "box_convention": (
                "visible extent of each ball (clipped to the image); diamonds: projected sight, >= 4 px, labelled when "
                "drawing it changes the photo by >= 12 of 255"
            ),
            "counts": {s: sum(1 for it in items if it["image"].startswith(s + "/")) for s in SPLITS},
            "images": items,
        }
        (tmp / "manifest.json").write_text(json.dumps(manifest, indent=1))
        (tmp / "data.yaml").write_text(data_yaml())
    return manifest

"""Read YOLO-format datasets (Roboflow layout: ``data.yaml``, ``<split>/images``, ``<split>/labels``).

Labels are ``class cx cy w h`` normalised to [0, 1]. An optional JSON sidecar per image (same stem, in
``<split>/meta`` or next to the label) may hold ball contact points; see :func:`read_contacts`.
"""

from __future__ import annotations

import fnmatch
import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

IMAGE_SUFFIXES = (".jpg", ".jpeg", ".png", ".bmp", ".webp")


@dataclass(frozen=True, slots=True)
class LabelledImage:
    """One image and its ground truth.

    Attributes:
        image_path: the image file.
        boxes: (n, 4) xyxy [px].
        class_id: (n,) dataset class ids.
        contact: (n, 2) ball-cloth contact points [px], NaN where unknown.
        size: (width, height) [px].
    """

    image_path: Path
    boxes: np.ndarray
    class_id: np.ndarray
    contact: np.ndarray
    size: tuple[int, int]


def split_dir(root: str | Path, split: str) -> Path:
    """The folder of one split; ``root`` itself if it directly holds ``images/``."""
    root = Path(root)
    if not root.is_dir():
        raise ValueError(f"dataset folder not found: {root}")
    for cand in (root / split, root / ("valid" if split == "val" else split)):
        if (cand / "images").is_dir():
            return cand
    if (root / "images").is_dir():
        return root
    raise ValueError(f"no '{split}/images' folder in dataset {root}")


def image_size(path: Path) -> tuple[int, int]:
    """(width, height) of an image file without decoding all pixels."""
    from PIL import Image

    with Image.open(path) as im:
        return im.size


def read_yolo_labels(path: Path, size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Boxes xyxy [px] and class ids from a YOLO label file (missing file: no objects)."""
    if not path.exists():
        return np.zeros((0, 4)), np.zeros(0, dtype=int)
    rows = [line.split() for line in path.read_text().splitlines() if line.strip()]
    if not rows:
        return np.zeros((0, 4)), np.zeros(0, dtype=int)
    try:
        arr = np.array([[float(v) for v in r[:5]] for r in rows])
    except ValueError as err:
        raise ValueError(f"bad YOLO label line in {path}: {err}") from err
    if arr.shape[1] != 5:
        raise ValueError(f"YOLO label rows need 5 numbers in {path}")
    w, h = size
    cx, cy, bw, bh = arr[:, 1] * w, arr[:, 2] * h, arr[:, 3] * w, arr[:, 4] * h
    boxes = np.stack([cx - bw / 2, cy - bh / 2, cx + bw / 2, cy + bh / 2], axis=1)
    return boxes, arr[:, 0].astype(int)


def _render_meta(image_path: str | Path) -> tuple[dict | None, Path]:
    """A rendered image's ``<split>/meta/<stem>.json`` sidecar (written by ``pix2pockets synth``) and its path; None
    where it is missing or unreadable."""
    path = Path(image_path)
    meta = path.parent.parent / "meta" / f"{path.stem}.json"
    try:
        doc = json.loads(meta.read_text())
    except (OSError, ValueError):
        return None, meta
    return (doc if isinstance(doc, dict) else None), meta


def camera_kind_of(image_path: str | Path) -> str:
    """The camera kind (``synth.cameras.CAMERA_KINDS``) a rendered image was taken with, from its
    ``<split>/meta/<stem>.json`` sidecar (written by ``pix2pockets synth``).

    Raises:
        ValueError: the image has no sidecar or the sidecar names no camera kind.
    """
    doc, meta = _render_meta(image_path)
    camera = (doc or {}).get("camera")
    kind = camera.get("kind") if isinstance(camera, dict) else None
    if not isinstance(kind, str):
        raise ValueError(
            f"no camera kind for {Path(image_path).name}: {meta} is missing or names none (camera kinds come with "
            "datasets rendered by pix2pockets synth)"
        )
    return kind


def ball_set_of(image_path: str | Path) -> str:
    """The ball set (``"american"`` or ``"blackball"``) of a rendered image, from its ``<split>/meta/<stem>.json``
    sidecar; ``"american"`` for an image without one (real photos, renders from before blackball sets)."""
    ball_set = (_render_meta(image_path)[0] or {}).get("ball_set")
    return ball_set if isinstance(ball_set, str) else "american"


def read_contacts(split: Path, stem: str, boxes: np.ndarray) -> np.ndarray:
    """Contact points [px] for the label rows, from a JSON sidecar if one exists, else NaN.

    The sidecar (``<split>/meta/<stem>.json`` or ``<split>/labels/<stem>.json``) may hold ``"contacts_px"``: a
    list parallel to the label rows of ``[u, v]`` or ``null``; or ``"objects"``: a list of dicts with
    ``"bbox_px"`` and ``"contact_px"`` matched to label rows by nearest box centre.
    """
    out = np.full((len(boxes), 2), np.nan)
    for cand in (split / "meta" / f"{stem}.json", split / "labels" / f"{stem}.json"):
        if cand.exists():
            data = json.loads(cand.read_text())
            break
    else:
        return out
    if isinstance(data.get("contacts_px"), list) and len(data["contacts_px"]) == len(boxes):
        for i, p in enumerate(data["contacts_px"]):
            if p is not None:
                out[i] = p
        return out
    objs = [
        o
        for o in data.get("objects", data.get("balls", []))
        if o.get("contact_px") is not None and o.get("labelled", True)
    ]
    if objs and len(boxes):
        centres = (boxes[:, :2] + boxes[:, 2:]) / 2
        for o in objs:
            b = np.asarray(o.get("bbox_px", o.get("box_px")), dtype=float)
            if b.shape != (4,):
                continue
            d = np.linalg.norm(centres - (b[:2] + b[2:]) / 2, axis=1)
            i = int(np.argmin(d))
            if d[i] < 2.0:
                out[i] = o["contact_px"]
    return out


def load_split(root: str | Path, split: str = "test", limit: int | None = None) -> list[LabelledImage]:
    """All labelled images of a split, sorted by file name.

    Raises:
        ValueError: if the split folder is missing or holds no images.
    """
    folder = split_dir(root, split)
    images = sorted(p for p in (folder / "images").iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
    if not images:
        raise ValueError(f"no images in {folder / 'images'}")
    if limit is not None:
        images = images[:limit]
    items = []
    for path in images:
        size = image_size(path)
        boxes, cls = read_yolo_labels(folder / "labels" / f"{path.stem}.txt", size)
        contact = read_contacts(folder, path.stem, boxes)
        items.append(LabelledImage(path, boxes, cls, contact, size))
    return items


def load_splits(roots: Sequence[str | Path], split: str = "train", exclude: Sequence[str] = ()) -> list[LabelledImage]:
    """The ``split`` images of several datasets in order, without those whose file name matches a glob in
    ``exclude`` (e.g. ``"yt-*"``, the frames of a validation video)."""
    return [
        it
        for root in roots
        for it in load_split(root, split)
        if not any(fnmatch.fnmatch(it.image_path.name, pat) for pat in exclude)
    ]


def read_class_names(root: str | Path) -> list[str] | None:
    """Class names from ``data.yaml`` (the ``names:`` list), or None if absent or unreadable."""
    path = Path(root) / "data.yaml"
    if not path.exists():
        return None
    text = path.read_text()
    for line in text.splitlines():
        if line.strip().startswith("names:") and "[" in line:
            inner = line.split("[", 1)[1].rsplit("]", 1)[0]
            return [n.strip().strip("'\"") for n in inner.split(",") if n.strip()]
    names, grab = [], False
    for line in text.splitlines():
        if line.strip().startswith("names:"):
            grab = True
            continue
        if grab:
            s = line.strip()
            if s.startswith("- "):
                names.append(s[2:].strip().strip("'\""))
            elif ":" in s and s.split(":")[0].strip().isdigit():
                names.append(s.split(":", 1)[1].strip().strip("'\""))
            elif s:
                break
    return names or None


NAME_SYNONYMS = {
    "dots": "dot",
    "diamond": "dot",
    "stripes": "stripe",
    "solids": "solid",
    "8-ball": "black",
    "cue ball": "cue",
}


def dataset_class_map(root: str | Path) -> dict[int, int]:
    """Dataset class id -> detector class id, matched by name from ``data.yaml`` (identity without names).

    Raises:
        ValueError: if ``data.yaml`` names none of the detector's classes.
    """
    from pix2pockets.vision.classes import CLASS_NAMES

    names = read_class_names(root)
    if names is None:
        return {i: i for i in range(len(CLASS_NAMES))}
    lookup = {n: i for i, n in enumerate(CLASS_NAMES)}
    out = {}
    for i, n in enumerate(names):
        key = NAME_SYNONYMS.get(n.lower(), n.lower())
        if key in lookup:
            out[i] = lookup[key]
    if not out:
        raise ValueError(f"dataset {root}: none of its classes {names} is one of {list(CLASS_NAMES)}")
    return out

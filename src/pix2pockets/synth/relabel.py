"""Refresh the labels of a rendered dataset after a change of the labelling rules, without new images.

Every image keeps its seed in its meta file, so it can be rendered again: the pixels must come out the same
(checked), and the labels are written by the current rules. Used when a rule changes, e.g. diamonds are
labelled only when they show in the photo (``labels.DIAMOND_MIN_SIGNAL``).

Example:
    >>> relabel_dataset("data/synth-v2/chunk-s111", "data/synth-v2/chunk-s111-relabelled")  # doctest: +SKIP
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import cv2
import numpy as np

from pix2pockets.synth.dataset import JPEG_QUALITY, SPLITS, data_yaml, staged_dataset, write_sample
from pix2pockets.synth.renderer import Render, render, render_views


def _rerender(meta: dict, cache: dict) -> Render:
    """The render a meta file was written from (multi-view scenes rendered once per scene)."""
    seed = tuple(meta["seed"])
    size = tuple(meta["image_size"])
    if "view" not in meta:
        return render(seed, size)
    key = (seed, size)
    if key not in cache:
        cache.clear()
        cache[key] = {r.labels["view"]: r for r in render_views(seed, size)}
    rend = cache[key][meta["view"]]
    rend.labels["scene_id"] = meta.get("scene_id")
    return rend


def _same_pixels(stored: Path, rend: Render) -> bool:
    """Whether ``stored`` decodes to the same pixels as ``rend`` written the way the dataset writer does."""
    old = cv2.imread(str(stored), cv2.IMREAD_COLOR)
    bgr = cv2.cvtColor(rend.image, cv2.COLOR_RGB2BGR)
    ok, buf = cv2.imencode(".jpg", bgr, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
    return old is not None and ok and np.array_equal(old, cv2.imdecode(buf, cv2.IMREAD_COLOR))


def relabel_dataset(
    src: str | os.PathLike, out: str | os.PathLike, force: bool = False, progress: bool = False
) -> dict[str, int]:
    """Write ``out``: the images of the synthetic dataset ``src`` with labels made by the current rules.

    Args:
        src: a dataset written by ``pix2pockets synth`` (or a merge of such), with ``meta/*.json`` per image.
        out: new dataset folder; must be absent or empty unless ``force``. ``src`` is never modified.
        force: replace a non-empty ``out``.
        progress: show a tqdm progress bar.

    Returns:
        Images written per split.

    Raises:
        ValueError: if ``src`` has no meta files, ``out`` is ``src`` or not empty, or an image no longer
            renders to the same pixels (it came from another renderer version: render it again instead).
    """
    src_root, root = Path(src), Path(out)
    metas = sorted(p for s in SPLITS for p in (src_root / s / "meta").glob("*.json"))
    if not metas:
        raise ValueError(f"{src_root} has no {{train,valid,test}}/meta/*.json files: not a pix2pockets synth dataset")
    if root.resolve() == src_root.resolve():
        raise ValueError("the output folder must differ from the source; the source is never modified")
    counts = dict.fromkeys(SPLITS, 0)
    cache: dict = {}
    iterator = metas
    if progress:
        from tqdm import tqdm

        iterator = tqdm(metas, desc="relabel", unit="img")
    with staged_dataset(root, force) as tmp:
        for path in iterator:
            split = path.parent.parent.name
            meta = json.loads(path.read_text())
            rend = _rerender(meta, cache)
            stored = path.parent.parent / "images" / meta.get("image", path.stem + ".jpg")
            if not _same_pixels(stored, rend):
                raise ValueError(
                    f"{stored} does not render to the same pixels any more (made by another renderer version); "
                    "render the dataset again with `pix2pockets synth` instead"
                )
            write_sample(tmp, split, path.stem, rend)
            counts[split] += 1
        (tmp / "data.yaml").write_text(data_yaml())
    return counts

"""Relabelling a rendered dataset: same pixels, labels by the current rules, the source left alone."""

from __future__ import annotations

import pytest

from pix2pockets.synth import labels, write_dataset
from pix2pockets.synth.relabel import relabel_dataset

SIZE = (192, 108)


@pytest.fixture(scope="module")
def source(tmp_path_factory):
    root = tmp_path_factory.mktemp("src") / "ds"
    write_dataset(root, 3, seed=4, size=SIZE, split=(0.5, 0.0, 0.5))
    return root


def _files(root, sub):
    return {p.relative_to(root): p.read_bytes() for p in root.rglob(f"{sub}/*")}


def test_same_rules_give_the_same_dataset(source, tmp_path):
    counts = relabel_dataset(source, tmp_path / "out")
    assert sum(counts.values()) == 3
    for sub in ("images", "labels", "meta"):
        assert _files(tmp_path / "out", sub) == _files(source, sub)


def test_new_rules_change_the_labels_not_the_source(source, tmp_path, monkeypatch):
    before = _files(source, "labels")
    monkeypatch.setattr(labels, "DIAMOND_MIN_SIGNAL", 256)  # no diamond shows enough
    relabel_dataset(source, tmp_path / "out")
    rows = [r for f in (tmp_path / "out").rglob("labels/*.txt") for r in f.read_text().splitlines()]
    assert rows and not [r for r in rows if r.startswith("4 ")]
    assert any(r.startswith("4 ") for b in before.values() for r in b.decode().splitlines())
    assert _files(source, "labels") == before


def test_refuses_changed_images_the_source_itself_and_non_empty_output(source, tmp_path):
    with pytest.raises(ValueError, match="must differ"):
        relabel_dataset(source, source)
    full = tmp_path / "full"
    full.mkdir()
    (full / "keep.txt").write_text("keep")
    with pytest.raises(ValueError, match="not empty"):
        relabel_dataset(source, full)
    assert (full / "keep.txt").exists()
    with pytest.raises(ValueError, match="not a pix2pockets synth dataset"):
        relabel_dataset(tmp_path / "nothing", tmp_path / "out")
    copy = tmp_path / "copy"
    relabel_dataset(source, copy)
    image = next(copy.rglob("images/*.jpg"))
    image.write_bytes(_other(source, image.name))  # another scene's picture under this name
    with pytest.raises(ValueError, match="same pixels"):
        relabel_dataset(copy, tmp_path / "again")
    assert not (tmp_path / "again").exists() and not (tmp_path / "again.partial").exists()


def _other(root, name):
    return next(p for p in root.rglob("images/*.jpg") if p.name != name).read_bytes()

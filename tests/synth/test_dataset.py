"""The dataset writer: Roboflow/YOLO layout, labels in range, determinism, refusing non-empty folders."""

from __future__ import annotations

import json

import pytest

from pix2pockets.cli.main import main
from pix2pockets.synth import write_dataset
from pix2pockets.synth.dataset import parse_split, split_assignment
from pix2pockets.synth.renderer import RENDERER_VERSION

SIZE = (192, 108)


def test_layout_and_labels(tmp_path):
    out = tmp_path / "ds"
    manifest = write_dataset(out, 5, seed=2, size=SIZE)
    assert (out / "data.yaml").read_text().count("names: [cue, black, solid, stripe, dot]") == 1
    assert sum(manifest["counts"].values()) == 5
    assert manifest["renderer_version"] == RENDERER_VERSION
    for item in manifest["images"]:
        img = out / item["image"]
        assert img.exists()
        split = item["image"].split("/")[0]
        lab = out / split / "labels" / (img.stem + ".txt")
        meta = json.loads((out / split / "meta" / (img.stem + ".json")).read_text())
        assert meta["camera"]["image_size"] == list(SIZE)
        assert len(meta["diamonds"]) == 18 and len(meta["corners"]) == 4
        rows = [r.split() for r in lab.read_text().splitlines()]
        assert len(rows) == sum(b["labelled"] for b in meta["balls"]) + sum(d["labelled"] for d in meta["diamonds"])
        for r in rows:
            assert 0 <= int(r[0]) <= 4
            cx, cy, w, h = (float(v) for v in r[1:])
            assert 0 <= cx <= 1 and 0 <= cy <= 1 and 0 < w <= 1 and 0 < h <= 1


def test_deterministic_bytes(tmp_path):
    write_dataset(tmp_path / "a", 2, seed=9, size=SIZE)
    write_dataset(tmp_path / "b", 2, seed=9, size=SIZE)
    for f in (tmp_path / "a").rglob("*.jpg"):
        assert f.read_bytes() == (tmp_path / "b" / f.relative_to(tmp_path / "a")).read_bytes()


def test_multi_view_dataset(tmp_path):
    manifest = write_dataset(tmp_path / "mv", 1, seed=1, size=SIZE, views=3)
    assert sorted(it["view"] for it in manifest["images"]) == ["front", "high", "top"]


def test_refuses_non_empty(tmp_path, capsys):
    out = tmp_path / "full"
    out.mkdir()
    (out / "x.txt").write_text("keep")
    rc = main(["synth", "--n", "1", "--out", str(out), "--size", "64x36", "--no-progress"])
    assert rc == 2
    assert "not empty" in capsys.readouterr().err
    assert (out / "x.txt").read_text() == "keep"
    rc = main(["synth", "--n", "1", "--out", str(out), "--size", "64x36", "--no-progress", "--force"])
    assert rc == 0 and not (out / "x.txt").exists()


@pytest.mark.parametrize("bad", ["0.8,0.2", "0.5,0.5,0.5", "a,b,c", "-0.1,0.6,0.5"])
def test_bad_split(bad):
    with pytest.raises(ValueError):
        parse_split(bad)


def test_split_counts():
    names = split_assignment(100, (0.8, 0.1, 0.1), 0)
    assert names.count("train") == 80 and names.count("valid") == 10 and names.count("test") == 10


def test_only_split_renders_the_same_images_of_that_split(tmp_path):
    full = write_dataset(tmp_path / "full", 6, seed=4, size=SIZE, split=(0.5, 0.0, 0.5))
    part = write_dataset(tmp_path / "part", 6, seed=4, size=SIZE, split=(0.5, 0.0, 0.5), only_split="test")
    assert part["counts"] == {"train": 0, "valid": 0, "test": 3}
    tests = [it["image"] for it in full["images"] if it["image"].startswith("test/")]
    assert [it["image"] for it in part["images"]] == tests
    for name in tests:
        assert (tmp_path / "part" / name).read_bytes() == (tmp_path / "full" / name).read_bytes()
    with pytest.raises(ValueError, match="only_split"):
        write_dataset(tmp_path / "bad", 2, size=SIZE, only_split="tests")


def test_layout_mode_forces_every_scene_s_layout(tmp_path):
    manifest = write_dataset(tmp_path / "racks", 3, seed=5, size=SIZE, layout_mode="rack")
    assert manifest["layout_mode"] == "rack"
    for item in manifest["images"]:
        split, _, name = item["image"].split("/")
        labels = json.loads((tmp_path / "racks" / split / "meta" / name).with_suffix(".json").read_text())
        assert labels["layout_mode"] == "rack"
    with pytest.raises(ValueError, match="layout_mode"):
        write_dataset(tmp_path / "bad", 2, size=SIZE, layout_mode="triangle")
    assert main(["synth", "--n", "1", "--out", str(tmp_path / "cli"), "--size", "192x108", "--layout", "endgame"]) == 0
    assert json.loads((tmp_path / "cli" / "manifest.json").read_text())["layout_mode"] == "endgame"


def test_camera_kinds_restrict_every_scene_s_camera(tmp_path):
    manifest = write_dataset(tmp_path / "tv", 4, seed=3, size=SIZE, split=(0, 0, 1), camera_kinds=["broadcast"])
    assert manifest["camera_kinds"] == ["top", "high", "jib"]
    for item in manifest["images"]:
        meta = json.loads((tmp_path / "tv" / item["image"].replace("images", "meta")).with_suffix(".json").read_text())
        assert item["camera"] == meta["camera"]["kind"] and item["camera"] in ("top", "high", "jib")
    with pytest.raises(ValueError, match="views 1"):
        write_dataset(tmp_path / "mv", 1, size=SIZE, views=3, camera_kinds=["top"])
    assert not (tmp_path / "mv").exists()


def test_synth_cameras_option(tmp_path, capsys):
    out = tmp_path / "cli"
    assert main(["synth", "--n", "2", "--out", str(out), "--size", "192x108", "--cameras", "low", "--no-progress"]) == 0
    assert {it["camera"] for it in json.loads((out / "manifest.json").read_text())["images"]} == {"low"}
    two = tmp_path / "two"
    args = ["synth", "--n", "6", "--out", str(two), "--size", "64x36", "--cameras", "top,low", "--no-progress"]
    assert main(args) == 0
    assert json.loads((two / "manifest.json").read_text())["camera_kinds"] == ["top", "low"]
    bad = tmp_path / "bad"
    assert main(["synth", "--n", "1", "--out", str(bad), "--size", "64x36", "--cameras", "drone", "--no-progress"]) == 2
    assert "unknown camera kind 'drone'" in capsys.readouterr().err
    assert not bad.exists()


def test_synth_portrait_option(tmp_path):
    out = tmp_path / "upright"
    args = ["synth", "--n", "3", "--out", str(out), "--size", "96x54", "--cameras", "phone", "--portrait", "1"]
    assert main([*args, "--no-progress"]) == 0
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["portrait"] == 1.0 and manifest["size"] == [96, 54]
    for item in manifest["images"]:
        meta = json.loads((out / item["image"].replace("images", "meta")).with_suffix(".json").read_text())
        assert meta["image_size"] == [54, 96] and meta["camera"]["orientation"] == "portrait"
        rows = (out / item["image"].replace("images", "labels")).with_suffix(".txt").read_text().splitlines()
        assert all(0 <= float(v) <= 1 for row in rows for v in row.split()[1:])  # normalised by the upright size
    with pytest.raises(ValueError, match="portrait"):
        write_dataset(tmp_path / "bad", 1, size=SIZE, portrait=2.0)


def test_blackball_share_draws_sets_per_scene_and_keeps_the_others(tmp_path):
    mixed = write_dataset(tmp_path / "mixed", 8, seed=4, size=SIZE, split=(1, 0, 0), blackball=0.5)
    plain = write_dataset(tmp_path / "plain", 8, seed=4, size=SIZE, split=(1, 0, 0))
    assert mixed["blackball"] == 0.5 and plain["blackball"] == 0.0
    sets = []
    for item in mixed["images"]:
        meta_path = (tmp_path / "mixed" / item["image"].replace("images", "meta")).with_suffix(".json")
        sets.append(json.loads(meta_path.read_text())["ball_set"])
        same = (tmp_path / "mixed" / item["image"]).read_bytes() == (tmp_path / "plain" / item["image"]).read_bytes()
        assert same == (sets[-1] == "american")  # an American scene renders as in a dataset without blackball sets
    assert set(sets) == {"american", "blackball"}
    with pytest.raises(ValueError, match="blackball"):
        write_dataset(tmp_path / "bad", 1, size=SIZE, blackball=1.5)


def test_synth_blackball_option(tmp_path):
    out = tmp_path / "uk"
    assert main(["synth", "--n", "2", "--out", str(out), "--size", "96x54", "--blackball", "1", "--no-progress"]) == 0
    for item in json.loads((out / "manifest.json").read_text())["images"]:
        meta = json.loads((out / item["image"].replace("images", "meta")).with_suffix(".json").read_text())
        assert meta["ball_set"] == "blackball" and meta["table"]["name"] in ("uk7", "uk6")

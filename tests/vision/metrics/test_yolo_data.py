import json

import numpy as np
import pytest

from pix2pockets.vision.metrics.yolo_data import (
    ball_set_of,
    camera_kind_of,
    dataset_class_map,
    load_split,
    load_splits,
    read_class_names,
    read_contacts,
)


def _dataset(tmp_path, names="names: [cue, black, solid, stripe, dot]\n"):
    (tmp_path / "test" / "images").mkdir(parents=True)
    (tmp_path / "test" / "labels").mkdir()
    (tmp_path / "test" / "meta").mkdir()
    (tmp_path / "data.yaml").write_text(names)
    from PIL import Image

    Image.fromarray(np.zeros((50, 100, 3), np.uint8)).save(tmp_path / "test" / "images" / "a.jpg")
    (tmp_path / "test" / "labels" / "a.txt").write_text("2 0.5 0.5 0.1 0.2\n4 0.1 0.1 0.04 0.08\n")
    return tmp_path


def test_load_split_boxes_in_pixels_and_contacts_from_synth_meta(tmp_path):
    root = _dataset(tmp_path)
    meta = {"balls": [{"box_px": [45, 20, 55, 30], "contact_px": [50, 28], "labelled": True}]}
    (root / "test" / "meta" / "a.json").write_text(json.dumps(meta))
    (item,) = load_split(root, "test")
    assert item.size == (100, 50)
    assert np.allclose(item.boxes, [[45, 20, 55, 30], [8, 3, 12, 7]])
    assert item.class_id.tolist() == [2, 4]
    assert np.allclose(item.contact[0], [50, 28]) and np.all(np.isnan(item.contact[1]))


def test_contacts_list_form(tmp_path):
    (tmp_path / "meta").mkdir()
    (tmp_path / "meta" / "x.json").write_text(json.dumps({"contacts_px": [[1, 2], None]}))
    c = read_contacts(tmp_path, "x", np.zeros((2, 4)))
    assert np.allclose(c[0], [1, 2]) and np.all(np.isnan(c[1]))


def test_class_names_both_yaml_forms(tmp_path):
    (tmp_path / "data.yaml").write_text("nc: 2\nnames:\n  - Ball\n  - Billiard table\n")
    assert read_class_names(tmp_path) == ["Ball", "Billiard table"]
    with pytest.raises(ValueError, match="none of its classes"):
        dataset_class_map(tmp_path)
    (tmp_path / "data.yaml").write_text("names: ['Stripes', 'solids', 'dots']\n")
    assert dataset_class_map(tmp_path) == {0: 3, 1: 2, 2: 4}


def test_missing_split(tmp_path):
    with pytest.raises(ValueError, match="no 'test/images'"):
        load_split(tmp_path, "test")


def test_load_splits_joins_datasets_and_drops_excluded_names(tmp_path):
    roots = [_dataset(tmp_path / "one"), _dataset(tmp_path / "two")]
    (roots[1] / "test" / "images" / "a.jpg").rename(roots[1] / "test" / "images" / "yt-0001.jpg")
    (roots[1] / "test" / "labels" / "a.txt").rename(roots[1] / "test" / "labels" / "yt-0001.txt")
    assert [it.image_path.name for it in load_splits(roots, "test")] == ["a.jpg", "yt-0001.jpg"]
    assert [it.image_path.name for it in load_splits(roots, "test", exclude=["yt-*"])] == ["a.jpg"]


def test_camera_kind_of_reads_the_synth_sidecar(tmp_path):
    (tmp_path / "test" / "images").mkdir(parents=True)
    (tmp_path / "test" / "meta").mkdir()
    image = tmp_path / "test" / "images" / "a.jpg"
    (tmp_path / "test" / "meta" / "a.json").write_text(json.dumps({"camera": {"kind": "jib"}}))
    assert camera_kind_of(image) == "jib"
    (tmp_path / "test" / "meta" / "a.json").write_text(json.dumps({"camera": {}}))
    with pytest.raises(ValueError, match=r"no camera kind for a\.jpg"):
        camera_kind_of(image)
    with pytest.raises(ValueError, match="pix2pockets synth"):
        camera_kind_of(tmp_path / "test" / "images" / "b.jpg")


def test_ball_set_of_reads_the_synth_sidecar_and_defaults_to_american(tmp_path):
    (tmp_path / "test" / "images").mkdir(parents=True)
    (tmp_path / "test" / "meta").mkdir()
    (tmp_path / "test" / "meta" / "a.json").write_text(json.dumps({"ball_set": "blackball"}))
    (tmp_path / "test" / "meta" / "b.json").write_text("not json")
    assert ball_set_of(tmp_path / "test" / "images" / "a.jpg") == "blackball"
    assert ball_set_of(tmp_path / "test" / "images" / "b.jpg") == "american"  # unreadable
    assert ball_set_of(tmp_path / "test" / "images" / "c.jpg") == "american"  # no sidecar: a real photo

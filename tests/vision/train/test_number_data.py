"""Ball-number crops: numbers come from the renderer's sidecars, one jittered crop per ball and copy."""

import json

import numpy as np
import pytest

from pix2pockets.vision.metrics.yolo_data import LabelledImage
from pix2pockets.vision.train.crop_data import CropConfig
from pix2pockets.vision.train.number_data import collect_number_crops, meta_path, number_crops, numbered_balls

META = {
    "balls": [
        {"number": 3, "box_px": [10, 10, 30, 30], "labelled": True, "visible_fraction": 1.0},
        {"number": 11, "box_px": [40, 10, 60, 30], "labelled": True, "visible_fraction": 0.2},
        {"number": 0, "box_px": [70, 10, 90, 30], "labelled": False, "visible_fraction": 0.0},
    ]
}


def test_meta_path_is_the_sidecar_next_to_the_images_folder(tmp_path):
    assert meta_path(tmp_path / "test" / "images" / "a.jpg") == tmp_path / "test" / "meta" / "a.json"


def test_numbered_balls_keeps_labelled_balls_that_show_enough():
    boxes, numbers = numbered_balls(META)
    assert numbers.tolist() == [3, 11] and boxes.shape == (2, 4)
    boxes, numbers = numbered_balls(META, min_visible=0.5)
    assert numbers.tolist() == [3]
    assert numbered_balls({"balls": []})[0].shape == (0, 4)


def test_number_crops_gives_copies_of_every_ball_with_its_number():
    image = np.zeros((40, 100, 3), np.uint8)
    image[10:30, 10:30] = (255, 0, 0)
    boxes, numbers = numbered_balls(META)
    crops, labels = number_crops(image, boxes, numbers, np.random.default_rng(0), CropConfig(copies=3, low_res=0))
    assert crops.shape == (6, 32, 32, 3) and crops.dtype == np.uint8
    assert labels.tolist() == [3, 11] * 3
    assert crops[0, 16, 16, 0] == 255  # the red ball sits in the middle of its crop
    empty, none = number_crops(image, np.zeros((0, 4)), np.zeros(0, int), np.random.default_rng(0), CropConfig())
    assert empty.shape == (0, 32, 32, 3) and none.shape == (0,)


def test_collect_number_crops_needs_renderer_sidecars(tmp_path):
    (tmp_path / "test" / "images").mkdir(parents=True)
    (tmp_path / "test" / "meta").mkdir()
    image_path = tmp_path / "test" / "images" / "a.png"
    import cv2

    cv2.imwrite(str(image_path), np.zeros((40, 100, 3), np.uint8))
    item = LabelledImage(image_path, np.zeros((0, 4)), np.zeros(0, int), np.zeros((0, 2)), (100, 40))

    def read_rgb(path):
        return cv2.imread(str(path))[:, :, ::-1]

    with pytest.raises(ValueError, match="sidecar"):
        collect_number_crops([item], read_rgb, seed=0)
    (tmp_path / "test" / "meta" / "a.json").write_text(json.dumps(META))
    crops, numbers = collect_number_crops([item], read_rgb, seed=0)
    again, _ = collect_number_crops([item], read_rgb, seed=0)
    assert numbers.tolist() == [3, 11] and np.array_equal(crops, again)

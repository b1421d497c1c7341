"""The diamond refiner's crop geometry, output decoding, and the shipped model on a fresh render."""

import numpy as np
import pytest

from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.stages.ball_classifier import BallClassifier
from pix2pockets.vision.stages.crops import crop_balls, crop_windows
from pix2pockets.vision.stages.diamond_refiner import (
    DIAMOND_CROP_SIZE,
    MIN_DIAMOND_CROP_PX,
    DiamondRefiner,
    box_targets,
    boxes_from_outputs,
    crop_diamonds,
    diamond_crop_sides,
)


def test_crop_windows_are_where_the_crops_come_from():
    image = np.zeros((60, 80, 3), np.uint8)
    image[20, 30] = 255  # one bright pixel, centre (30.5, 20.5)
    centres = np.array([[31.2, 19.6]])
    corners, sides = crop_windows(centres, np.array([16.0]), 1.0)
    crop = crop_balls(image, centres, np.array([16.0]), size=16, context=1.0)[0]
    (row, col) = np.argwhere(crop[:, :, 0] == 255)[0]
    assert (corners[0][0] + col, corners[0][1] + row) == (30, 20)
    assert sides[0] == 16


def test_outputs_decode_to_photo_pixels_and_targets_invert_them():
    corners, sides = np.array([[100, 50], [7, 9]]), np.array([16, 20])
    out = np.array([[0.25, -0.125, 0.5, 0.25], [0.0, 0.1, 0.3, 0.4]])
    boxes = boxes_from_outputs(out, corners, sides)
    assert np.allclose(boxes, [[108, 54, 116, 58], [14, 17, 20, 25]])
    assert np.allclose(box_targets(boxes, corners, sides), out)
    wild = boxes_from_outputs(np.array([[3.0, -9.0, 0.01, 5.0]]), corners[:1], sides[:1])
    assert np.allclose(wild, [[114, 42, 118, 58]])  # centre held at the crop's edge, sides between 4 px and 16 px


def test_crop_sides_follow_the_box_with_a_floor():
    sides = diamond_crop_sides(np.array([[0, 0, 4, 4], [0, 0, 10, 8.0]]))
    assert sides[0] == MIN_DIAMOND_CROP_PX and sides[1] == pytest.approx(36.0)
    crops, _, windows = crop_diamonds(np.zeros((50, 50, 3), np.uint8), np.array([[25.0, 25.0]]), np.array([16.0]))
    assert crops.shape == (1, DIAMOND_CROP_SIZE, DIAMOND_CROP_SIZE, 3) and windows.tolist() == [16]


def test_missing_or_wrong_model_is_a_clear_error(tmp_path):
    with pytest.raises(ValueError, match="not found"):
        DiamondRefiner(tmp_path / "nope.onnx")

    if BallClassifier.default_path().exists():  # a crop model, but not a refiner
        with pytest.raises(ValueError, match="not a diamond refiner"):
            DiamondRefiner(BallClassifier.default_path())


@pytest.mark.skipif(not DiamondRefiner.default_path().exists(), reason="no diamond refiner committed")
def test_shipped_refiner_moves_shifted_boxes_back_onto_the_diamonds():
    pytest.importorskip("pix2pockets.synth")
    from pix2pockets.synth.renderer import render
    from pix2pockets.vision.classes import DIAMOND_ID
    from pix2pockets.vision.detect.postprocess import paired_box_iou

    rend = render((5155, 0), (960, 540))
    truth = np.array([d["box_px"] for d in rend.labels["diamonds"] if d["labelled"]], float)
    if len(truth) < 6:
        pytest.skip("render shows fewer than 6 diamonds")
    shifted = truth + np.tile(np.random.default_rng(0).uniform(-1.5, 1.5, (len(truth), 2)), 2)
    diamonds = Detections(shifted, np.linspace(0.9, 0.5, len(truth)), np.full(len(truth), DIAMOND_ID))
    refined = DiamondRefiner.from_default().refine(rend.image, diamonds)

    def centre_error(boxes: np.ndarray) -> np.ndarray:
        return np.linalg.norm((boxes[:, :2] + boxes[:, 2:] - truth[:, :2] - truth[:, 2:]) / 2, axis=1)

    assert np.median(centre_error(refined.boxes)) < 0.5 * np.median(centre_error(shifted))
    assert np.median(paired_box_iou(refined.boxes, truth)) > np.median(paired_box_iou(shifted, truth))
    assert np.all(refined.boxes[:, 2:] - refined.boxes[:, :2] >= 4.0 - 1e-9)  # the labels' floor
    assert np.array_equal(refined.confidence, diamonds.confidence)
    faint = Detections(shifted, np.full(len(truth), 0.1), np.full(len(truth), DIAMOND_ID))
    assert np.array_equal(DiamondRefiner.from_default().refine(rend.image, faint).boxes, shifted)  # below min_score

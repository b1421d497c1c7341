"""Table-model training samples: exact targets from a render's camera, kept through the augmentation."""

import json
from pathlib import Path

import numpy as np
import pytest

from pix2pockets.data.examples import example_labels_path
from pix2pockets.vision.table.keypoints import CORNER_CHANNEL, SIDE_CHANNEL, SURFACE_CHANNEL, cell_of_pixel
from pix2pockets.vision.train.table_data import TableAugment, augment_sample, table_targets, truth_of_meta

META = json.loads(Path(example_labels_path()).read_text())


def test_truth_matches_the_render_labels():
    truth = truth_of_meta(META)
    labelled = np.array([c["px_cloth"] for c in META["corners"]])
    assert truth.corners == pytest.approx(labelled, abs=0.05)
    # side pockets lie between the corners of the long rails
    assert np.linalg.norm(truth.sides[0] - labelled[:2].mean(axis=0)) < 0.1 * np.linalg.norm(labelled[1] - labelled[0])


def test_targets_peak_at_the_corners_and_fill_the_surface():
    truth = truth_of_meta(META)
    y = table_targets(truth, (1280, 720))
    peaks = np.argwhere(y[CORNER_CHANNEL] >= 0.999)[:, ::-1]
    want = np.round(cell_of_pixel(truth.corners)).astype(int)
    assert sorted(map(tuple, peaks)) == sorted(map(tuple, want))
    assert (y[SIDE_CHANNEL] >= 0.999).sum() == 2
    centre = np.round(cell_of_pixel(truth.corners.mean(axis=0))).astype(int)
    assert y[SURFACE_CHANNEL][centre[1], centre[0]] == pytest.approx(1.0)
    assert y[SURFACE_CHANNEL][0, 0] == 0.0


def test_augmented_targets_follow_the_image():
    truth = truth_of_meta(META)
    image = np.zeros((720, 1280, 3), dtype=np.uint8)
    cfg = TableAugment(input_size=256, zoom_share=1.0, stretch_share=1.0, hue_share=0.0, blur_share=0.0,
                       noise_share=0.0, jpeg_share=0.0, grey_share=0.0)  # fmt: skip
    for seed in range(5):
        # paint the surface white, augment, and check the moved surface target covers the white
        import cv2

        painted = image.copy()
        cv2.fillConvexPoly(painted, np.round(truth.corners).astype(np.int32), (255, 255, 255))
        x, y = augment_sample(painted, truth, cfg, np.random.default_rng(seed))
        white = x.mean(axis=0)[1::4, 1::4][: y.shape[1], : y.shape[2]] > 0.9
        inside = y[SURFACE_CHANNEL] > 0.9
        assert x.shape == (3, 256, 256) and y.shape[1:] == (64, 64)
        if white.sum() > 20:
            assert (white & inside).sum() / white.sum() > 0.9

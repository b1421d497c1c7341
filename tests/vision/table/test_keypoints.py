"""The table model: its decoding, and the shipped model on the bundled example render."""

import json
from pathlib import Path

import numpy as np
import pytest

from pix2pockets.data.examples import example_labels_path, example_photo_path
from pix2pockets.pipeline.photo import load_image
from pix2pockets.vision.detect.letterbox import Letterbox
from pix2pockets.vision.stages.ball_classifier import BallClassifier
from pix2pockets.vision.table.errors import TableFitError
from pix2pockets.vision.table.keypoints import (
    N_TABLE_CHANNELS,
    TableModel,
    cell_of_pixel,
    cues_from_output,
    peaks,
    pixel_of_cell,
)
from pix2pockets.vision.table.surface import surface_outline

_needs_model = pytest.mark.skipif(not TableModel.default_path().is_file(), reason="no table model committed")


def test_cells_and_pixels_are_inverse():
    xy = np.array([[0.0, 0.0], [10.3, 7.9], [383.0, 200.5]])
    assert np.allclose(pixel_of_cell(cell_of_pixel(xy)), xy)
    assert np.allclose(cell_of_pixel([[1.5, 5.5]]), [[0.0, 1.0]])  # cell 0 covers pixels 0-3


def test_peaks_are_local_maxima_read_between_cells():
    heat = np.zeros((10, 12))
    heat[4, 5], heat[4, 6] = 0.9, 0.9 * 0.5  # a peak leaning right
    heat[8, 2] = 0.3
    heat[1, 1] = 0.1  # under the floor
    got = peaks(heat)
    assert got.shape == (2, 3)
    assert got[0, 2] == pytest.approx(0.9) and 5.0 < got[0, 0] < 5.5 and got[0, 1] == pytest.approx(4.0)
    assert got[1, :2] == pytest.approx([2.0, 8.0])


def test_cues_map_cells_back_to_the_photo():
    out = np.zeros((N_TABLE_CHANNELS, 20, 30), dtype=np.float32)
    out[1, 10, 15] = 1.0
    cues = cues_from_output(out, Letterbox(scale=0.5, size=(120, 80)), (240, 160))
    assert cues.corners_px == pytest.approx(pixel_of_cell([[15.0, 10.0]]) / 0.5)
    assert len(cues.sides_px) == 0 and cues.surface_mask().shape == (160, 240)


def test_a_model_of_another_kind_is_refused():
    if not BallClassifier.default_path().is_file():
        pytest.skip("no ball classifier committed")
    with pytest.raises(ValueError, match="not a table model"):
        TableModel(BallClassifier.default_path())


def test_missing_model_file_is_a_clean_error(tmp_path):
    with pytest.raises(ValueError, match="not found"):
        TableModel(tmp_path / "none.onnx")
    assert TableModel.from_option("none") is None


@_needs_model
def test_shipped_model_finds_the_example_table():
    rgb = load_image(example_photo_path())
    truth = np.array([c["px_cloth"] for c in json.loads(Path(example_labels_path()).read_text())["corners"]])
    cues = TableModel.from_option(None).read(rgb)
    outline = surface_outline(cues)
    err = np.linalg.norm(outline.corners_px[:, None] - truth[None], axis=2).min(axis=1)
    assert np.all(err < 3.0)  # px, in a 1280x720 render
    assert outline.seen.all() and outline.from_peak.all()
    # the side pockets sit on the two long sides, which are opposite each other
    long_sides = np.flatnonzero(outline.side_pocket > 0.5)
    assert len(long_sides) == 2 and abs(long_sides[0] - long_sides[1]) == 2
    assert outline.mask.mean() > 0.2


@_needs_model
def test_a_photo_without_a_table_has_no_surface():
    rng = np.random.default_rng(0)
    noise = rng.integers(0, 255, (360, 640, 3), dtype=np.uint8)
    with pytest.raises(TableFitError, match="no table found"):
        surface_outline(TableModel.from_option(None).read(noise))

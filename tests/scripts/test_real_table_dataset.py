"""The real-photo table training set: folds that keep a video's neighbouring frames together, and labels the
table model's training reads back as the camera's own view of the table."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

from pix2pockets.geometry import TableSpec
from pix2pockets.vision.detect.analytic import standard_views
from pix2pockets.vision.train.table_data import truth_of_meta

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "real_table_dataset.py"


def load_script():
    spec = importlib.util.spec_from_file_location("real_table_dataset", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_video_frames_fall_in_contiguous_blocks_and_other_photos_in_turn():
    script = load_script()
    frames = [f"yt-abc-{i:04d}_jpg.rf.x.jpg" for i in (9, 0, 12, 3, 100, 7)]
    photos = ["b_jpg.rf.y.jpg", "a_jpg.rf.z.jpg", "c_jpg.rf.w.jpg"]
    folds = script.fold_of(frames + photos, 2)
    by_number = sorted(frames, key=lambda n: int(n.split("-")[-1][:4]))
    assert [folds[n] for n in by_number] == [0, 0, 0, 1, 1, 1]  # frames 0, 3, 7 | 9, 12, 100
    assert [folds[n] for n in sorted(photos)] == [0, 1, 0]
    assert set(script.fold_of(frames + photos, 1).values()) == {0}


def test_written_labels_read_back_as_the_cameras_view_of_the_table():
    script = load_script()
    spec = TableSpec()
    camera = standard_views(spec)["45"]
    meta = script.meta_of(spec, camera, "x.jpg", "train")
    truth = truth_of_meta(meta)
    expected = camera.project_table(spec.corners, 0.0)
    assert np.allclose(truth.corners, expected, atol=1e-6)
    assert np.allclose(truth.sides, camera.project_table(spec.pocket_aims[[1, 4]], 0.0), atol=1e-6)

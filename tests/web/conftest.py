"""The bundled example photo with its exact labels, and a detector that returns them (fast, deterministic)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from pix2pockets.cli.suggest_cmd import example_photo_path
from pix2pockets.vision.classes import CLASS_NAMES, DOT_ID
from pix2pockets.vision.detections import Detections


@dataclass
class LabelsDetector:
    """Returns the labelled balls and diamonds of a synth render (its label dict), minus the classes in ``drop``."""

    labels: dict
    drop: tuple[str, ...] = ()

    def detect(self, image_rgb: np.ndarray) -> Detections:
        rows = [(b["class_id"], b["box_px"]) for b in self.labels["balls"] if b["labelled"]]
        rows += [(DOT_ID, d["box_px"]) for d in self.labels["diamonds"] if d["labelled"]]
        rows = [r for r in rows if CLASS_NAMES[r[0]] not in self.drop]
        boxes = np.array([box for _, box in rows], dtype=float).reshape(-1, 4)
        return Detections(boxes, np.ones(len(rows)), np.array([c for c, _ in rows], dtype=int))


@pytest.fixture(scope="session")
def rendered():
    """(file bytes, labels) of the bundled example photo (a pix2pockets.synth render)."""
    photo = Path(example_photo_path())
    labels = photo.with_name(photo.stem + ".labels.json")
    if not (photo.is_file() and labels.is_file()):
        pytest.skip("the bundled example photo or its labels are missing from this build")
    return photo.read_bytes(), json.loads(labels.read_text())

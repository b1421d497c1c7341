"""A rendered photo with exact labels and a detector that returns them, for fast deterministic web tests."""

from __future__ import annotations

import io
from dataclasses import dataclass

import numpy as np
import pytest

from pix2pockets.vision.classes import CLASS_NAMES, DOT_ID
from pix2pockets.vision.detections import Detections

SEED = 73  # a 9-foot table seen from above (head rail left), solids, stripes, the 8 and the cue ball; no ball in a jaw
SIZE = (640, 360)


@dataclass
class LabelsDetector:
    """Returns the labelled balls and diamonds of a synth render, minus the classes in ``drop``."""

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
    """(PNG bytes, labels) of one synthetic photo."""
    from PIL import Image

    from pix2pockets.synth import render

    out = render(SEED, SIZE, camera_kind="top")
    buf = io.BytesIO()
    Image.fromarray(out.image).save(buf, format="PNG")
    return buf.getvalue(), out.labels

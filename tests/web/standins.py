"""Stand-ins that cross into worker processes (they pickle by reference to this module)."""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from pix2pockets.testing import LabelsDetector


class SlowDetector(LabelsDetector):
    """The exact labels, after ``seconds`` of waiting (a worker kept busy)."""

    def __init__(self, labels: dict, seconds: float) -> None:
        super().__init__(labels)
        self.seconds = seconds

    def detect(self, image_rgb: np.ndarray):
        time.sleep(self.seconds)
        return super().detect(image_rgb)


class GatedDetector(LabelsDetector):
    """The exact labels once the file ``gate`` exists (a test holds the worker until it has looked)."""

    def __init__(self, labels: dict, gate: str | Path) -> None:
        super().__init__(labels)
        self.gate = str(gate)

    def detect(self, image_rgb: np.ndarray):
        while not os.path.exists(self.gate):
            time.sleep(0.02)
        return super().detect(image_rgb)


class CrashOnDark(LabelsDetector):
    """Kills its own process on a dark photo (mean < 40), like a native crash would."""

    def detect(self, image_rgb: np.ndarray):
        if float(image_rgb.mean()) < 40:
            os._exit(3)
        return super().detect(image_rgb)


class HangOnDark(LabelsDetector):
    """Never returns on a dark photo (mean < 40)."""

    def detect(self, image_rgb: np.ndarray):
        while float(image_rgb.mean()) < 40:
            time.sleep(0.1)
        return super().detect(image_rgb)


def missing_model():
    """A detector factory for a build without its model."""
    raise ValueError("detector model not found: detector.onnx")

"""The second-stage diamond refiner run through onnxruntime: re-reads each diamond's centre from the photo.

The detector finds diamonds on a stride-4 grid. A diamond box is only 4-6 px wide, so a centre off by one pixel
fails IoU 0.5, and the table fit draws its lines through these centres. The refiner looks at a crop of the
full-resolution photo around each detected diamond and returns the diamond's centre to a fraction of a pixel.
It only moves boxes: scores, sizes and the set of detections stay the detector's
(``docs/detector.md``, "Diamond refiner").

Example:
    >>> refiner = DotRefiner.from_default()  # doctest: +SKIP
    >>> dots = refiner.refine(image_rgb, raw_dots)  # doctest: +SKIP
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np

from pix2pockets.vision.ball_crops import crop_balls, crop_windows
from pix2pockets.vision.detections import Detections
from pix2pockets.vision.onnx_session import open_crop_model

DEFAULT_DOT_REFINER = "dot-refiner.onnx"
DOT_CROP_SIZE = 32
"""Side of a refiner crop [px]."""
DOT_CROP_CONTEXT = 4.0
"""Crop side over the detected diamond's box side."""
MIN_DOT_CROP_PX = 16.0
"""Smallest crop side in the photo [px] (a 4 px diamond plus room for the detector's centre error)."""
N_OUTPUTS = 2
"""Refiner outputs per crop: the diamond's centre x and y, as fractions of the crop side from its middle."""
OUTPUT_NAME = "centre"
"""Name of the refiner's ONNX output."""
REFINE_MIN_SCORE = 0.15
"""Diamonds the detector scores below this keep their box: refining them too changed no AP on the test
renders (``docs/benchmarks-detector.md``), the pipeline reads only diamonds above 0.25, and they are 60 % of
the raw diamonds, so skipping them cuts the refiner's time by about that much."""


def default_dot_refiner_path() -> Path:
    """Path of the refiner shipped as package data (may not exist in a checkout without weights)."""
    return Path(str(resources.files("pix2pockets.data").joinpath("models", DEFAULT_DOT_REFINER)))


def dot_crop_sides(boxes: np.ndarray) -> np.ndarray:
    """Crop sides [px] for diamond boxes (n, 4): :data:`DOT_CROP_CONTEXT` box sides, at least
    :data:`MIN_DOT_CROP_PX`."""
    boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
    side = 0.5 * ((boxes[:, 2] - boxes[:, 0]) + (boxes[:, 3] - boxes[:, 1]))
    return np.maximum(DOT_CROP_CONTEXT * side, MIN_DOT_CROP_PX)


def crop_dots(image: np.ndarray, centres: np.ndarray, sides: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Crops (n, S, S, 3) uint8 of the photo, and their windows: top-left corners (n, 2) and sides (n,) [px]."""
    corners, windows = crop_windows(centres, sides, 1.0)
    return crop_balls(image, centres, sides, DOT_CROP_SIZE, 1.0), corners, windows


def centres_from_outputs(out: np.ndarray, corners: np.ndarray, sides: np.ndarray) -> np.ndarray:
    """Diamond centres (n, 2) [px] from refiner outputs (n, 2) and the crop windows they were read from; an
    output beyond the crop's edge (never seen in training) is held at the edge."""
    out = np.clip(np.asarray(out, dtype=float).reshape(-1, N_OUTPUTS), -0.5, 0.5)
    side = np.asarray(sides, dtype=float)[:, None]
    return np.asarray(corners, dtype=float) + side * (0.5 + out)


def centre_targets(centres: np.ndarray, corners: np.ndarray, sides: np.ndarray) -> np.ndarray:
    """Refiner targets (n, 2) for diamond centres (n, 2) [px] seen in crop windows; inverse of
    :func:`centres_from_outputs`."""
    side = np.asarray(sides, dtype=float)[:, None]
    return (np.asarray(centres, dtype=float).reshape(-1, 2) - corners) / side - 0.5


class DotRefiner:
    """Refines the centres of diamond detections from crops of the original photo.

    Args:
        model_path: the ``.onnx`` file written by ``pix2pockets train-dot-refiner``.
        threads: onnxruntime intra-op threads (0 lets onnxruntime choose).

    Raises:
        ValueError: if the file does not exist or is not a refiner of the expected form.
    """

    def __init__(self, model_path: str | Path, threads: int = 1) -> None:
        path = Path(model_path)
        self.session = open_crop_model(path, threads, "diamond refiner model", DOT_CROP_SIZE, OUTPUT_NAME, N_OUTPUTS)
        self.input_name = self.session.get_inputs()[0].name
        self.model_path = path

    @classmethod
    def from_default(cls, threads: int = 1) -> DotRefiner:
        """The refiner shipped with the package."""
        return cls(default_dot_refiner_path(), threads)

    def centres(self, image_rgb: np.ndarray, boxes: np.ndarray) -> np.ndarray:
        """Refined centres (n, 2) [px] of detected diamond boxes (n, 4) [px] in an RGB uint8 photo."""
        boxes = np.asarray(boxes, dtype=float).reshape(-1, 4)
        if len(boxes) == 0:
            return np.zeros((0, 2))
        crops, corners, sides = crop_dots(image_rgb, 0.5 * (boxes[:, :2] + boxes[:, 2:]), dot_crop_sides(boxes))
        return centres_from_outputs(self.session.run(None, {self.input_name: crops})[0], corners, sides)

    def refine(self, image_rgb: np.ndarray, dots: Detections, min_score: float = REFINE_MIN_SCORE) -> Detections:
        """The diamond detections with each box scoring at least `min_score` moved to its refined centre (same
        size, clipped to the image); the others, and every score, unchanged."""
        todo = dots.confidence >= min_score
        boxes = dots.boxes.copy()
        centre = self.centres(image_rgb, boxes[todo])
        half = 0.5 * (boxes[todo, 2:] - boxes[todo, :2])
        h, w = image_rgb.shape[:2]
        boxes[todo] = np.clip(np.hstack([centre - half, centre + half]), 0, [w, h, w, h])
        return Detections(boxes, dots.confidence, dots.class_id, dots.contact, dots.own_score)

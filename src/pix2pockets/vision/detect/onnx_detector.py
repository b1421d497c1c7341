"""The heatmap detector run through onnxruntime: no torch at inference time.

Example:
    >>> det = OnnxDetector.from_default()  # doctest: +SKIP
    >>> raw = det.detect(image_rgb)  # doctest: +SKIP
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path

import numpy as np

from pix2pockets.vision.classes import BALL_IDS, DIAMOND_ID
from pix2pockets.vision.detect.decode import decode_ball_peaks, decode_peaks
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.heads import INPUT_MULTIPLE
from pix2pockets.vision.detect.letterbox import network_input
from pix2pockets.vision.detect.onnx_session import open_session
from pix2pockets.vision.stages.ball_classifier import (
    BallClassifier,
    classified_balls,
    own_class_scores,
)
from pix2pockets.vision.stages.ball_numbers import BallNumberReader
from pix2pockets.vision.stages.ball_refiner import BallRefiner
from pix2pockets.vision.stages.diamond_refiner import DiamondRefiner
from pix2pockets.vision.table.pixel_aspect import boxes_in_aspect, pixel_aspect_of_photo

DEFAULT_MODEL = "detector.onnx"
NETWORK_MULTIPLE = 32
"""Network inputs are padded to multiples of this [px] (the trunk's largest stride is 32)."""


def default_model_path() -> Path:
    """Path of the detector shipped as package data (may not exist in a checkout without weights)."""
    return Path(str(resources.files("pix2pockets.data").joinpath("models", DEFAULT_MODEL)))


@dataclass(frozen=True, slots=True)
class OnnxDetectorConfig:
    """Inference settings.

    Attributes:
        input_size: long side of the network input [px] for images up to this size (smaller ones are scaled
            up to it).
        max_input_size: larger images run at their own long side (rounded down to a multiple of 32), up to
            this [px]. Far balls in a 720p or 1080p frame are only 8-12 px wide at 640; at 1024 synthetic 720p
            AP50 rises by 5-14 points per ball class (``docs/benchmarks-detector.md``), for about 2.5x the
            time. Set it to ``input_size`` for a fixed input size.
        conf_threshold: lowest score kept in raw detections.
        max_detections: most raw detections per image.
        threads: onnxruntime intra-op threads (0 lets onnxruntime choose).
    """

    input_size: int = 640
    max_input_size: int = 1024
    conf_threshold: float = 0.05
    max_detections: int = 300
    threads: int = 1

    def __post_init__(self) -> None:
        for name in ("input_size", "max_input_size"):
            v = getattr(self, name)
            if v < 64 or v % INPUT_MULTIPLE:
                raise ValueError(f"{name} must be >= 64 and a multiple of {INPUT_MULTIPLE}, got {v}")
        if not 0.0 <= self.conf_threshold <= 1.0:
            raise ValueError(f"conf_threshold must be in [0, 1], got {self.conf_threshold}")
        if self.max_detections < 1 or self.threads < 0:
            raise ValueError("max_detections must be >= 1 and threads >= 0")

    def long_side(self, image_long_side: int) -> int:
        """Network input long side [px] for an image whose long side is ``image_long_side`` [px]."""
        native = image_long_side // NETWORK_MULTIPLE * NETWORK_MULTIPLE
        return max(self.input_size, min(native, self.max_input_size))


class OnnxDetector:
    """A :class:`~pix2pockets.vision.detect.base.Detector` backed by an ONNX heatmap model.

    Args:
        model_path: the ``.onnx`` file written by ``pix2pockets train-detector``.
        config: inference settings.
        classifier: optional second stage that re-reads each ball from the full-resolution photo and
            re-scores its class (``pix2pockets train-ball-classifier``); None uses the detector's class heads.
        diamond_refiner: optional second stage that re-reads each diamond from the full-resolution photo and
            moves its box to the diamond's centre (``pix2pockets train-diamond-refiner``); None keeps the detector's
            boxes.
        ball_refiner: optional second stage that re-reads each ball's box from the full-resolution photo before the
            classifier reads it (``pix2pockets train-ball-refiner``); None keeps the detector's boxes.
        number_reader: optional stage, used with a classifier, that reads each ball's number so that the class
            scores are weighed across the table with every number on it at most once
            (:mod:`pix2pockets.vision.stages.number_posterior`; ``pix2pockets train-ball-numbers``); None weighs only
            the
            cue ball and the 8 that way.

    Raises:
        ValueError: if the file does not exist or is not a model of the expected form.
    """

    def __init__(
        self,
        model_path: str | Path,
        config: OnnxDetectorConfig | None = None,
        classifier: BallClassifier | None = None,
        diamond_refiner: DiamondRefiner | None = None,
        ball_refiner: BallRefiner | None = None,
        number_reader: BallNumberReader | None = None,
    ) -> None:
        self.config = config or OnnxDetectorConfig()
        self.classifier = classifier
        self.diamond_refiner = diamond_refiner
        self.ball_refiner = ball_refiner
        self.number_reader = number_reader
        self.session = open_session(model_path, self.config.threads, "detector model")
        self.input_name = self.session.get_inputs()[0].name
        self.model_path = Path(model_path)

    @classmethod
    def from_default(cls, config: OnnxDetectorConfig | None = None) -> OnnxDetector:
        """The detector shipped with the package, with the shipped second stages when there are any."""
        threads = (config or OnnxDetectorConfig()).threads
        return cls(
            default_model_path(),
            config,
            BallClassifier.from_option(None, threads),
            DiamondRefiner.from_option(None, threads),
            BallRefiner.from_option(None, threads),
            BallNumberReader.from_option(None, threads),
        )

    def _forward(self, image_rgb: np.ndarray):
        image = np.asarray(image_rgb)
        if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3:
            raise ValueError(f"expected an RGB uint8 image (H, W, 3), got {image.dtype} {image.shape}")
        x, box = network_input(image, self.config.long_side(max(image.shape[:2])), NETWORK_MULTIPLE)
        out = self.session.run(None, {self.input_name: x})[0][0]
        return out, box, (image.shape[1], image.shape[0])

    def detect(self, image_rgb: np.ndarray) -> Detections:
        """Raw (not post-processed) detections of the five classes in an RGB uint8 image, with what the detector
        measured on the way: the photo's pixel aspect, and with a number reader each ball's number chances
        (``data["number_probs"]``)."""
        out, box, size = self._forward(image_rgb)
        c = self.config
        if self.classifier is None:
            balls = decode_peaks(out, box, c.conf_threshold, c.max_detections, channels=BALL_IDS, image_size=size)
            balls, aspect = self._refined(image_rgb, balls)
        else:
            balls, heat = decode_ball_peaks(out, box, c.conf_threshold, c.max_detections, image_size=size)
            balls, aspect = self._refined(image_rgb, balls)
            probs = self.classifier.classify(image_rgb, balls.boxes, aspect)
            numbers = None
            if self.number_reader is not None:  # read only the candidates that can become detections
                scored = own_class_scores(balls.confidence, heat, probs).max(axis=1) >= c.conf_threshold
                balls, heat, probs = balls[scored], heat[scored], probs[scored]
                numbers = self.number_reader.read(image_rgb, balls.boxes, aspect)
            balls = classified_balls(balls, heat, probs, c.conf_threshold, numbers)
        diamonds = decode_peaks(out, box, c.conf_threshold, c.max_detections, channels=(DIAMOND_ID,), image_size=size)
        if self.diamond_refiner is not None:
            diamonds = self.diamond_refiner.refine(image_rgb, diamonds)
        return replace(Detections.concatenate([balls, diamonds]), pixel_aspect=aspect)

    def detect_balls(self, image_rgb: np.ndarray) -> Detections:
        """Class-agnostic ball detections from the "any ball" heatmap (class ids all 0, meaning "ball")."""
        out, box, size = self._forward(image_rgb)
        c = self.config
        balls = decode_peaks(out, box, c.conf_threshold, c.max_detections, agnostic=True, image_size=size)
        balls, aspect = self._refined(image_rgb, balls)
        return replace(balls, pixel_aspect=aspect)

    def _refined(self, image_rgb: np.ndarray, balls: Detections) -> tuple[Detections, float]:
        """Ball detections in the photo's pixel aspect, re-boxed by the ball refiner when there is one, and that
        aspect."""
        balls, aspect = _in_photo_aspect(image_rgb, balls)
        if self.ball_refiner is not None:
            balls = self.ball_refiner.refine(image_rgb, balls, aspect)
        return balls, aspect


def _in_photo_aspect(image_rgb: np.ndarray, balls: Detections) -> tuple[Detections, float]:
    """Ball detections with their boxes as stretched as the photo's pixels, and that pixel aspect
    (:mod:`pix2pockets.vision.table.pixel_aspect`; 1 and unchanged boxes for a photo as the camera took it)."""
    aspect = pixel_aspect_of_photo(image_rgb, balls.boxes, balls.confidence)
    boxes = boxes_in_aspect(balls.boxes, balls.confidence, aspect)
    return replace(balls, boxes=boxes), aspect

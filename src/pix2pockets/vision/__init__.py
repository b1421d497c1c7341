"""Vision: detections, detectors, post-processing, table fitting and ball location."""

from pix2pockets.vision.classes import CLASS_NAMES, DETECTION_CAPS, DetClass
from pix2pockets.vision.detect.base import Detector
from pix2pockets.vision.detect.detections import Detections

__all__ = ["CLASS_NAMES", "DETECTION_CAPS", "DetClass", "Detections", "Detector"]

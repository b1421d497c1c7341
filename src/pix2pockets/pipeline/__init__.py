"""The photo pipeline: photo -> detections -> table fit -> ball positions -> shot -> picture / JSON."""

from pix2pockets.pipeline.photo import suggest
from pix2pockets.pipeline.result import LocatedBall, ShotAdvice, Suggestion

__all__ = ["LocatedBall", "ShotAdvice", "Suggestion", "suggest"]

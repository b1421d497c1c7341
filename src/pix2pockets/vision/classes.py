"""The detector's five classes, in the fixed id order used by datasets, models and outputs."""

from __future__ import annotations

from enum import StrEnum

from pix2pockets.state.ball import CLASS_CAPS, BallClass


class DetClass(StrEnum):
    """Detection classes (the paper's five): four ball classes and the diamond sight ``diamond``."""

    CUE = "cue"
    BLACK = "black"
    SOLID = "solid"
    STRIPE = "stripe"
    DIAMOND = "dot"


CLASS_NAMES: tuple[str, ...] = tuple(c.value for c in DetClass)
"""Class names by id: 0 cue, 1 black, 2 solid, 3 stripe, 4 diamond (YOLO ``data.yaml`` order)."""

DIAMOND_ID = CLASS_NAMES.index("dot")
BALL_IDS = tuple(range(4))
MIN_DIAMOND_BOX_PX = 4.0
"""Smallest side of a diamond box [px]: the synthetic labels pad a sight's outline to it, and the decoder maps
the network's floor to the same floor in image pixels at any input scale (``heatmap_decode``)."""

DETECTION_CAPS: tuple[int, ...] = (
    CLASS_CAPS[BallClass.CUE],
    CLASS_CAPS[BallClass.BLACK],
    CLASS_CAPS[BallClass.SOLID],
    CLASS_CAPS[BallClass.STRIPE],
    18,
)
"""Most detections of each class an image can hold (paper section 6.1): 1, 1, 7, 7, 18."""

ONE_PER_TABLE: tuple[int, ...] = tuple(k for k in BALL_IDS if DETECTION_CAPS[k] == 1)
"""Ball classes a table holds once (cue, then black): their scores are weighed across the image."""


def ball_class_of(class_id: int) -> BallClass:
    """The ball class for a ball detection id (0-3)."""
    if class_id not in BALL_IDS:
        raise ValueError(f"class id {class_id} is not a ball class (0-3)")
    return BallClass(CLASS_NAMES[class_id])

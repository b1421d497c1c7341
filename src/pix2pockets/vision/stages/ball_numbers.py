"""Ball numbers from a photo: a small crop network reads each ball's colour, the ball's class picks the group.

The reader (``ball-numbers.onnx``, trained by ``pix2pockets train-ball-numbers``) gives chances of the 16 ball
numbers for a crop. A ball's class is known from the detector, so only the numbers of its class count
(a solid is 1-7, a stripe 9-15), and a set holds each number once: :func:`assign_numbers` picks the most
likely numbering of all balls together.

Example:
    >>> reader = BallNumberReader.from_default()  # doctest: +SKIP
    >>> numbers, chance = assign_numbers(reader.read(image_rgb, boxes), class_ids)  # doctest: +SKIP
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment

from pix2pockets.state.ball import class_of_number
from pix2pockets.vision.classes import BALL_IDS, CLASS_NAMES
from pix2pockets.vision.stages.base import CropModel
from pix2pockets.vision.stages.crops import crops_of_boxes

DEFAULT_NUMBER_READER = "ball-numbers.onnx"
N_NUMBERS = 16
"""Ball numbers 0 (the cue ball) to 15."""
OUTPUT_NAME = "probs"
CLASS_ID_OF_NUMBER = np.array([CLASS_NAMES.index(class_of_number(n).value) for n in range(N_NUMBERS)])
"""Detector class id (0 cue, 1 black, 2 solid, 3 stripe) of each ball number 0-15."""
NUMBERS_OF_CLASS: tuple[tuple[int, ...], ...] = tuple(
    tuple(int(n) for n in np.flatnonzero(k == CLASS_ID_OF_NUMBER)) for k in BALL_IDS
)
"""The numbers a ball of each detector class id may carry: cue 0, black 8, solid 1-7, stripe 9-15."""
UNKNOWN = -1
"""Number given to a ball whose class has no number left (more balls of a class than the set holds), and to every
ball of a table that does not read as a numbered set."""

STRAIN_OF_A_NUMBERED_SET = 1.0
"""Numbering strain [nats per ball] up to which a table reads as a standard numbered set (the detector's likely
balls on the validation renders: median 0.04-0.09, at most 1.4; the pipeline's balls within their classes: median
0, 90 % under 0.4)."""

STRAIN_OF_AN_UNNUMBERED_SET = 2.0
"""Numbering strain [nats per ball] from which a table reads as a set without numbers (real frames of red and
yellow pub balls: median 4.0, 2.1 at the tenth percentile; within their classes 3.1 and 1.8)."""

_UNNUMBERED_LOG_CHANCE = float(np.log(1e-3))


def class_mask(class_ids: np.ndarray) -> np.ndarray:
    """(n, 16) bool: which numbers each ball's class id (0-3) allows."""
    class_ids = np.asarray(class_ids, dtype=int).reshape(-1)
    if len(class_ids) and (class_ids.min() < 0 or class_ids.max() >= len(NUMBERS_OF_CLASS)):
        raise ValueError(f"ball class ids must be 0-3, got {sorted(set(class_ids.tolist()))}")
    return CLASS_ID_OF_NUMBER[None, :] == class_ids[:, None]


def numbering_strain(probs: np.ndarray) -> float:
    """How far a table's balls must be read from their likeliest numbers for each to get a number of its own
    [mean nats per ball].

    Near 0 for a standard set, whose balls read as different numbers. Far above for a set that carries no numbers
    (pub reds and yellows, snooker): its look-alike balls all read as the same few numbers, and giving each its own
    costs much chance. Balls beyond the 16 numbers count as read at chance 1e-3.
    """
    log_chance = np.log(np.maximum(np.asarray(probs, dtype=float).reshape(-1, N_NUMBERS), 1e-6))
    n = len(log_chance)
    if n == 0:
        return 0.0
    if n > N_NUMBERS:
        log_chance = np.hstack([log_chance, np.full((n, n - N_NUMBERS), _UNNUMBERED_LOG_CHANCE)])
    rows, cols = linear_sum_assignment(-log_chance)
    return float((log_chance.max(axis=1).sum() - log_chance[rows, cols].sum()) / n)


def numbered_set_weight(strain: float) -> float:
    """Trust in a table's numbers from its :func:`numbering_strain`: 1 up to :data:`STRAIN_OF_A_NUMBERED_SET`, 0
    from :data:`STRAIN_OF_AN_UNNUMBERED_SET`, linear between."""
    span = STRAIN_OF_AN_UNNUMBERED_SET - STRAIN_OF_A_NUMBERED_SET
    return float(np.clip((STRAIN_OF_AN_UNNUMBERED_SET - strain) / span, 0.0, 1.0))


def assign_numbers(probs: np.ndarray, class_ids: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The most likely numbering of a table's balls: each ball a number of its class, each number at most once.

    Args:
        probs: (n, 16) the reader's chances of each number per ball.
        class_ids: (n,) the balls' detector class ids (0 cue, 1 black, 2 solid, 3 stripe).

    Returns:
        numbers (n,) int, :data:`UNKNOWN` where the class has more balls than numbers; and each ball's chance of
        its number among its class's numbers (n,), 0 where unknown. The chances are scaled by
        :func:`numbered_set_weight` of the strain of the within-class chances: a table that does not read as a
        numbered set gets no numbers at all (pub reds and yellows: all classed solid, say, they cannot all be told
        apart as the 1-7).
    """
    probs = np.asarray(probs, dtype=float).reshape(-1, N_NUMBERS)
    mask = class_mask(class_ids)
    if len(mask) != len(probs):
        raise ValueError(f"{len(probs)} rows of chances but {len(mask)} class ids")
    within = np.where(mask, np.maximum(probs, 1e-9), 0.0)
    within /= np.maximum(within.sum(axis=1, keepdims=True), 1e-12)
    numbers = np.full(len(probs), UNKNOWN, dtype=int)
    chance = np.zeros(len(probs))
    if len(probs) == 0:
        return numbers, chance
    weight = numbered_set_weight(numbering_strain(within))  # the strain of the numbering asked for: within class
    if weight == 0:
        return numbers, chance
    forbidden = 1e6  # far above any sum of log chances
    cost = np.where(mask, -np.log(np.maximum(within, 1e-9)), forbidden)
    rows, cols = linear_sum_assignment(cost)
    ok = mask[rows, cols]
    numbers[rows[ok]] = cols[ok]
    chance[rows[ok]] = weight * within[rows[ok], cols[ok]]
    return numbers, chance


class BallNumberReader(CropModel):
    """Reads ball numbers from crops of the original photo (``pix2pockets train-ball-numbers``).

    See :class:`~pix2pockets.vision.stages.base.CropModel` for the arguments; the crop side is the model's own.
    """

    what = "ball-number reader model"
    file_name = DEFAULT_NUMBER_READER
    output_name = OUTPUT_NAME
    n_outputs = N_NUMBERS

    def read(self, image_rgb: np.ndarray, boxes: np.ndarray, aspect: float | None = None) -> np.ndarray:
        """Chances (n, 16) of ball numbers 0-15 for balls in xyxy boxes (n, 4) [px] (``aspect``: see
        :func:`~pix2pockets.vision.stages.crops.crops_of_boxes`)."""
        return self.run(crops_of_boxes(image_rgb, boxes, self.crop_size, aspect))

    def numbers(
        self, image_rgb: np.ndarray, boxes: np.ndarray, class_ids: np.ndarray, aspect: float | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Numbers (n,) and their chances (n,) for a table's balls (:func:`assign_numbers`)."""
        return assign_numbers(self.read(image_rgb, boxes, aspect), class_ids)

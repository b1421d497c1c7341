"""The second-stage ball classifier run through onnxruntime: full-resolution crops -> ball class or no ball.

Example:
    >>> clf = BallClassifier.from_default()  # doctest: +SKIP
    >>> probs = clf.classify(image_rgb, boxes)  # (n, 5): cue, black, solid, stripe, no ball  # doctest: +SKIP
"""

from __future__ import annotations

import numpy as np

from pix2pockets.vision.classes import BALL_IDS, ONE_PER_TABLE
from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.detect.postprocess import at_most_one_posterior
from pix2pockets.vision.stages.base import CropModel
from pix2pockets.vision.stages.crops import crops_of_boxes
from pix2pockets.vision.stages.number_posterior import numbered_table_weight, table_class_scores

DEFAULT_CLASSIFIER = "ball-classifier.onnx"
N_OUTPUTS = 5
"""Probabilities of cue, black, solid, stripe (detector class ids 0-3) and "no ball"."""
OUTPUT_NAME = "probs"
"""Name of the classifier's ONNX output."""
NUMBER_PROBS = "number_probs"
"""Key of the ball-number reader's chances (n, 16) in :attr:`Detections.data`."""
IN_VIEW_ABSENT_ODDS = 0.5
"""Weight of "this table's cue ball (or 8) is not in the photo" in the raw scores' at-most-one weighing
(:func:`~pix2pockets.vision.detect.postprocess.at_most_one_posterior`): in a photo of a game both are nearly always
there. Chosen on fresh validation renders (seeds 171-173); 0.5 against 1 lifts cue AP50 before and after the
paper's post-processing on the validation and test renders (``docs/benchmarks-detector.md``)."""


class BallClassifier(CropModel):
    """Classifies ball detections from crops of the original photo (``pix2pockets train-ball-classifier``).

    See :class:`~pix2pockets.vision.stages.base.CropModel` for the arguments; the crop side is the model's own
    (32 px for the shipped one).
    """

    what = "ball classifier model"
    file_name = DEFAULT_CLASSIFIER
    output_name = OUTPUT_NAME
    n_outputs = N_OUTPUTS

    def classify(self, image_rgb: np.ndarray, boxes: np.ndarray, aspect: float | None = None) -> np.ndarray:
        """Probabilities (n, 5) of cue, black, solid, stripe and no ball for xyxy boxes (n, 4) [px].

        ``aspect``: width over height of one pixel; by default read from the boxes
        (:func:`~pix2pockets.vision.table.pixel_aspect.pixel_aspect_of_balls`), so the balls of a photo stretched by an
        export are cropped round again.
        """
        return self.run(crops_of_boxes(image_rgb, boxes, self.crop_size, aspect))


def own_class_scores(ball_score: np.ndarray, class_heat: np.ndarray, probs: np.ndarray) -> np.ndarray:
    """(n, 4) each ball's own cue, black, solid and stripe scores, before any weighing across the image:
    ball score x sqrt(p_k x h_k / sum(h)) (:func:`classified_balls`)."""
    n, k = len(ball_score), len(BALL_IDS)
    probs = np.asarray(probs, dtype=float).reshape(n, N_OUTPUTS)
    heat = np.asarray(class_heat, dtype=float).reshape(n, k)
    share = heat / np.maximum(heat.sum(axis=1, keepdims=True), 1e-9)
    return np.asarray(ball_score, dtype=float)[:, None] * np.sqrt(probs[:, :k] * share)


def classified_balls(
    balls: Detections,
    class_heat: np.ndarray,
    probs: np.ndarray,
    conf_threshold: float = 0.05,
    number_probs: np.ndarray | None = None,
) -> Detections:
    """Ball detections with one entry per ball and class, scored by the detector and the classifier together.

    Score of class k = ball score x sqrt(p_k x h_k / sum(h)): the geometric mean of the classifier's
    probability p_k and the detector's class heatmap share h_k. Either alone did worse on the synthetic test
    splits (``docs/benchmarks-detector.md``); the "no ball" probability lowers every class score of a doubtful
    ball.

    A table holds one cue ball and one 8, so their scores are then weighed across the image
    (:func:`pix2pockets.vision.detect.postprocess.at_most_one_posterior`): a stripe that looks as much like the cue
    ball as the real one splits the chance with it, and a lone clear cue ball scores a little above its own
    score, the kind being usually in view (:data:`IN_VIEW_ABSENT_ODDS`). The scores before that are kept as
    ``own_score``, and each entry's ball score (whatever its class) as ``ball_score``.

    With the ball-number reader's chances for the same balls, the scores of every class are weighed across the
    image instead, each of the 16 numbers being on the table once
    (:func:`pix2pockets.vision.stages.number_posterior.table_class_scores`): a ball read as much like the 12 as like
    the 4
    is the 4 when another ball is clearly the 12. On a table whose balls do not read as a numbered set (pub reds
    and yellows) the two weighings are blended, or the first is kept
    (:func:`pix2pockets.vision.stages.number_posterior.numbered_table_weight`).

    Args:
        balls: class-agnostic ball detections (the "any ball" heatmap peaks), class ids ignored.
        class_heat: (n, 4) the detector's cue, black, solid and stripe heatmap scores at those peaks.
        probs: (n, 5) classifier output for those balls (cue, black, solid, stripe, no ball).
        conf_threshold: entries below this score are dropped.
        number_probs: (n, 16) the ball-number reader's chances of numbers 0-15 for those balls, or None.
    """
    own = own_class_scores(balls.confidence, class_heat, probs)
    score = own.copy()
    for kind in ONE_PER_TABLE:  # score columns are the ball class ids (BALL_IDS, 0-3)
        score[:, kind] = at_most_one_posterior(own[:, kind], IN_VIEW_ABSENT_ODDS)
    weight = 0.0 if number_probs is None else numbered_table_weight(own, number_probs)
    if weight > 0:
        score = weight * table_class_scores(own, number_probs, IN_VIEW_ABSENT_ODDS) + (1 - weight) * score
    keep = own >= conf_threshold
    rows, cls = np.nonzero(keep)
    classes = np.asarray(BALL_IDS)[cls]
    data = {key: value[rows] for key, value in balls.data.items()}
    if number_probs is not None:
        data[NUMBER_PROBS] = np.asarray(number_probs, dtype=float)[rows]
    return Detections(
        balls.boxes[rows],
        score[keep],
        classes,
        balls.contact[rows],
        own[keep],
        balls.confidence[rows],
        data,
        balls.pixel_aspect,
    )

"""Ball class scores for a whole table from its ball numbers: each of the 16 numbers is on the table at most once.

A rack has one ball of each number, so when one ball is clearly the 12 no other ball can be, and a ball that
looks half like the 12 and half like the 4 is then the 4. The class of a ball alone (cue, black, solid, stripe)
cannot carry that: seven solids look alike as a class. :func:`table_class_scores` spreads each ball's class
scores over the numbers of its class by the ball-number reader's chances, finds the chance of every pairing
of ball and number under "at most one number per ball, at most one ball per number", and sums them back per
class. Loopy belief propagation gives those chances; with one number in play it is exact, and then equal to
:func:`~pix2pockets.vision.detect.postprocess.at_most_one_posterior`. A table whose balls do not read as a numbered set
(pub reds and yellows, snooker) is not weighed this way (:func:`numbered_table_weight`).
"""

from __future__ import annotations

import numpy as np

from pix2pockets.vision.classes import BALL_IDS
from pix2pockets.vision.stages.ball_numbers import (
    CLASS_ID_OF_NUMBER,
    N_NUMBERS,
    NUMBERS_OF_CLASS,
    numbered_set_weight,
    numbering_strain,
)

SET_EVIDENCE_SCORE = 0.3
"""Candidates whose class scores sum to at least this show whether the table's set is numbered
(:func:`numbered_table_weight`)."""

BP_ITERATIONS = 30
"""Belief-propagation rounds: on random tables of 2-20 balls the chances after 30 rounds are within 0.001 of those
after 100 (after 10, within 0.05)."""

BP_DAMPING = 0.5
"""Share of the previous round kept in each message, so that the rounds settle instead of swinging."""

_CHANCE_LIMIT = 1e-6


def matching_marginals(
    odds: np.ndarray,
    absent_odds: float | np.ndarray,
    iterations: int = BP_ITERATIONS,
    damping: float = BP_DAMPING,
) -> np.ndarray:
    """Chance that ball i is number j when each ball is at most one number and each number at most one ball.

    Args:
        odds: (n, m) >= 0, ball i's own odds of being number j against being no numbered ball at all.
        absent_odds: weight of "number j is not in view" against one ball at even odds (> 0), one for all numbers
            or (m,) one per number.
        iterations: belief-propagation rounds.
        damping: share of the previous round kept in each message, in [0, 1).

    Returns:
        (n, m) chances in [0, 1); each row sums to at most 1 (the rest: no numbered ball) and so does each column
        (the rest: the number is not in view), up to the approximation.
    """
    odds = np.asarray(odds, dtype=float)
    if odds.ndim != 2 or (odds < 0).any() or not np.isfinite(odds).all():
        raise ValueError(f"odds must be a finite (n, m) array >= 0, got shape {odds.shape}")
    absent_odds = np.broadcast_to(np.asarray(absent_odds, dtype=float), odds.shape[1:])
    if not (absent_odds > 0).all() or not 0 <= damping < 1:
        raise ValueError(f"need absent_odds > 0 and damping in [0, 1), got {absent_odds}, {damping}")
    from_row = np.ones_like(odds)  # each ball's "at most one number" message to its pairings, as odds factors
    from_column = np.ones_like(odds)  # each number's "at most one ball" message
    for _ in range(iterations):
        to_row = odds * from_column
        from_row = damping * from_row + (1 - damping) / (1.0 + to_row.sum(axis=1, keepdims=True) - to_row)
        to_column = odds * from_row
        from_column = damping * from_column + (1 - damping) / (
            absent_odds + to_column.sum(axis=0, keepdims=True) - to_column
        )
    belief = odds * from_row * from_column
    return belief / (1.0 + belief)


def table_class_scores(own: np.ndarray, number_probs: np.ndarray, absent_odds: float | np.ndarray) -> np.ndarray:
    """One table's ball class scores with every number used at most once.

    Args:
        own: (n, 4) each candidate ball's own scores for cue, black, solid and stripe (detector class ids 0-3),
            each in [0, 1] and summing to at most 1; the rest is the chance that it is no ball.
        number_probs: (n, 16) the ball-number reader's chances of numbers 0-15 for the same candidates.
        absent_odds: weight of "this number is not in the photo" (see :func:`matching_marginals`).

    Returns:
        (n, 4) scores: the chance that each candidate is a ball of each class, given all the others.
    """
    own = np.asarray(own, dtype=float)
    probs = np.asarray(number_probs, dtype=float)
    n_classes = len(BALL_IDS)
    if own.ndim != 2 or own.shape[1] != n_classes or probs.shape != (len(own), N_NUMBERS):
        raise ValueError(f"need own (n, {n_classes}) and number_probs (n, {N_NUMBERS}), got {own.shape}, {probs.shape}")
    if len(own) == 0:
        return own.copy()
    of_class = [list(numbers) for numbers in NUMBERS_OF_CLASS]
    class_total = np.stack([probs[:, numbers].sum(axis=1) for numbers in of_class], axis=1)
    within_class = probs / np.maximum(class_total[:, CLASS_ID_OF_NUMBER], _CHANCE_LIMIT)
    own = np.clip(own, 0.0, 1.0)
    no_ball = np.clip(1.0 - own.sum(axis=1, keepdims=True), _CHANCE_LIMIT, 1.0)
    marginals = matching_marginals(own[:, CLASS_ID_OF_NUMBER] * within_class / no_ball, absent_odds)
    return np.stack([marginals[:, numbers].sum(axis=1) for numbers in of_class], axis=1)


def numbered_table_weight(own: np.ndarray, number_probs: np.ndarray) -> float:
    """How far to trust "each number once" on this table, 0-1.

    :func:`pix2pockets.vision.stages.ball_numbers.numbered_set_weight` of the numbering strain of the candidates that
    are
    likely balls (class scores summing to at least :data:`SET_EVIDENCE_SCORE`). Pub reds and yellows and snooker
    balls carry no numbers; weighing them as if each number were there once would split the look-alikes' scores.
    """
    sure = np.asarray(own, dtype=float).sum(axis=1) >= SET_EVIDENCE_SCORE
    return numbered_set_weight(numbering_strain(np.asarray(number_probs)[sure]))

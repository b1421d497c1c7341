"""Class scores weighed across the table with every ball number on it at most once."""

import numpy as np
import pytest

from pix2pockets.vision.detect.postprocess import at_most_one_posterior
from pix2pockets.vision.stages.ball_numbers import N_NUMBERS
from pix2pockets.vision.stages.number_posterior import matching_marginals, numbered_table_weight, table_class_scores

CUE, BLACK, SOLID, STRIPE = range(4)


def _numbers(*chances: dict[int, float]) -> np.ndarray:
    """(n, 16) reader chances from {number: chance} per ball, the rest spread evenly."""
    out = np.zeros((len(chances), N_NUMBERS))
    for row, given in zip(out, chances, strict=True):
        rest = [n for n in range(N_NUMBERS) if n not in given]
        row[rest] = (1.0 - sum(given.values())) / len(rest)
        for n, c in given.items():
            row[n] = c
    return out


def test_one_number_in_play_is_the_at_most_one_posterior():
    chance = np.array([0.9, 0.5, 0.2])
    odds = np.zeros((3, N_NUMBERS))
    odds[:, 0] = chance / (1 - chance)
    np.testing.assert_allclose(matching_marginals(odds, 0.5)[:, 0], at_most_one_posterior(chance, 0.5))


def test_marginals_keep_each_ball_and_each_number_at_most_once():
    rng = np.random.default_rng(3)
    odds = rng.exponential(2.0, size=(12, N_NUMBERS))
    m = matching_marginals(odds, 0.5)
    assert np.all(m >= 0)
    assert np.all(m.sum(axis=1) <= 1 + 1e-6)
    assert np.all(m.sum(axis=0) <= 1 + 0.05)  # loopy belief propagation: close, not exact


def test_a_number_taken_by_a_clear_ball_goes_to_the_other_reading():
    odds = np.zeros((2, N_NUMBERS))
    odds[0, 12] = 50.0  # clearly the 12
    odds[1, [4, 12]] = 5.0  # half the 4, half the 12
    m = matching_marginals(odds, 0.5)
    assert m[1, 4] > 3 * m[1, 12]
    alone = matching_marginals(odds[1:], 0.5)
    assert alone[0, 4] == pytest.approx(alone[0, 12])


def test_a_ball_between_solid_and_stripe_is_a_solid_when_its_stripe_is_taken():
    own = np.array([[0.0, 0.0, 0.45, 0.45], [0.0, 0.0, 0.0, 0.95]])  # ball 0: orange, 5 or 13
    numbers = _numbers({5: 0.45, 13: 0.45}, {13: 0.95})
    both = table_class_scores(own, numbers, 0.5)
    assert both[0, SOLID] > 2 * both[0, STRIPE]
    alone = table_class_scores(own[:1], numbers[:1], 0.5)
    assert alone[0, SOLID] == pytest.approx(alone[0, STRIPE])
    assert both[1, STRIPE] > 0.9


def test_two_cue_like_balls_share_the_cue():
    own = np.array([[0.8, 0.0, 0.0, 0.1], [0.8, 0.0, 0.0, 0.1]])
    numbers = _numbers({0: 0.9}, {0: 0.9})
    scores = table_class_scores(own, numbers, 0.5)
    assert scores[0, CUE] == pytest.approx(scores[1, CUE])
    assert scores[0, CUE] < 0.6
    lone = table_class_scores(own[:1], numbers[:1], 0.5)
    assert lone[0, CUE] > 0.8


def test_empty_table_and_bad_shapes():
    assert table_class_scores(np.zeros((0, 4)), np.zeros((0, N_NUMBERS)), 0.5).shape == (0, 4)
    with pytest.raises(ValueError, match="number_probs"):
        table_class_scores(np.zeros((2, 4)), np.zeros((2, 10)), 0.5)
    with pytest.raises(ValueError, match="odds"):
        matching_marginals(-np.ones((2, 3)), 0.5)
    with pytest.raises(ValueError, match="absent_odds"):
        matching_marginals(np.ones((2, 3)), 0.0)


def test_only_likely_balls_show_whether_the_set_is_numbered():
    own = np.array([[0.0, 0.0, 0.9, 0.0]] * 3 + [[0.0, 0.0, 0.1, 0.0]] * 3)
    reads = _numbers({1: 0.9}, {2: 0.9}, {3: 0.9}, {3: 0.9}, {3: 0.9}, {3: 0.9})
    assert numbered_table_weight(own, reads) == 1.0  # the three faint candidates reading "3" do not count
    own[3:, 2] = 0.9
    assert numbered_table_weight(own, reads) < 0.5

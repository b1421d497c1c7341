"""Ball numbers: each ball gets a number of its class, each number at most once, the likeliest numbering wins."""

import numpy as np
import pytest

from pix2pockets.vision.classes import CLASS_NAMES
from pix2pockets.vision.stages.ball_classifier import BallClassifier
from pix2pockets.vision.stages.ball_numbers import (
    N_NUMBERS,
    STRAIN_OF_A_NUMBERED_SET,
    STRAIN_OF_AN_UNNUMBERED_SET,
    UNKNOWN,
    BallNumberReader,
    assign_numbers,
    class_mask,
    numbered_set_weight,
    numbering_strain,
)

CUE, BLACK, SOLID, STRIPE = (CLASS_NAMES.index(k) for k in ("cue", "black", "solid", "stripe"))


def _probs(*peaks: dict[int, float]) -> np.ndarray:
    """Rows of chances with the given weights on some numbers and a little on all."""
    out = np.full((len(peaks), N_NUMBERS), 0.001)
    for row, peak in zip(out, peaks, strict=True):
        for n, p in peak.items():
            row[n] = p
    return out / out.sum(axis=1, keepdims=True)


def test_class_mask_allows_only_the_class_numbers():
    mask = class_mask(np.array([CUE, BLACK, SOLID, STRIPE]))
    assert np.flatnonzero(mask[0]).tolist() == [0]
    assert np.flatnonzero(mask[1]).tolist() == [8]
    assert np.flatnonzero(mask[2]).tolist() == list(range(1, 8))
    assert np.flatnonzero(mask[3]).tolist() == list(range(9, 16))
    with pytest.raises(ValueError, match="0-3"):
        class_mask(np.array([4]))


def test_a_ball_gets_a_number_of_its_class_even_if_it_looks_like_another():
    # the reader sees a red ball (3), but the detector says stripe: the red stripe is the 11
    numbers, chance = assign_numbers(_probs({3: 0.6, 11: 0.3}), np.array([STRIPE]))
    assert numbers.tolist() == [11]
    assert 0.9 < chance[0] <= 1.0


def test_each_number_once_the_likeliest_numbering_of_the_table():
    # two solids both look most like the 3; the second looks much more like the 7 than the first does
    probs = _probs({3: 0.9, 7: 0.05}, {3: 0.5, 7: 0.45}, {0: 0.9}, {8: 0.9})
    numbers, _ = assign_numbers(probs, np.array([SOLID, SOLID, CUE, BLACK]))
    assert numbers.tolist() == [3, 7, 0, 8]


def test_more_balls_of_a_class_than_the_set_holds_leaves_the_least_likely_unknown():
    others = ({3: 0.9}, {8: 0.9}, {11: 0.9}, {5: 0.9}, {13: 0.9}, {2: 0.9})  # the rest of the table reads plainly
    probs = _probs({0: 0.9}, {0: 0.4}, *others)
    numbers, chance = assign_numbers(probs, np.array([CUE, CUE, SOLID, BLACK, STRIPE, SOLID, STRIPE, SOLID]))
    assert numbers.tolist() == [0, UNKNOWN, 3, 8, 11, 5, 13, 2]
    assert chance[1] == 0.0


def test_a_standard_set_reads_as_numbered_and_look_alike_balls_do_not():
    standard = _probs(*({n: 0.8} for n in range(16)))
    assert numbering_strain(standard) == pytest.approx(0.0)
    assert numbered_set_weight(numbering_strain(standard)) == 1.0
    pub = _probs(*([{3: 0.8, 7: 0.1}] * 7 + [{1: 0.7, 9: 0.2}] * 7))  # seven reds, seven yellows, no numbers
    assert numbering_strain(pub) > STRAIN_OF_AN_UNNUMBERED_SET
    numbers, chance = assign_numbers(pub, np.array([SOLID] * 7 + [STRIPE] * 7))
    assert np.all(numbers == UNKNOWN) and np.all(chance == 0.0)
    snooker = _probs(*([{3: 0.9}] * 15 + [{n: 0.9} for n in (0, 1, 2, 4, 5, 6, 10)]))  # 22 balls, 15 reds
    assert numbered_set_weight(numbering_strain(snooker)) == 0.0
    assert numbering_strain(np.zeros((0, N_NUMBERS))) == 0.0


def test_the_trust_in_numbers_falls_linearly_between_the_two_strains():
    assert numbered_set_weight(STRAIN_OF_A_NUMBERED_SET) == 1.0
    assert numbered_set_weight(STRAIN_OF_AN_UNNUMBERED_SET) == 0.0
    middle = (STRAIN_OF_A_NUMBERED_SET + STRAIN_OF_AN_UNNUMBERED_SET) / 2
    assert numbered_set_weight(middle) == pytest.approx(0.5)


def test_empty_table_and_mismatched_rows():
    numbers, chance = assign_numbers(np.zeros((0, N_NUMBERS)), np.zeros(0, int))
    assert numbers.shape == (0,) and chance.shape == (0,)
    with pytest.raises(ValueError, match="class ids"):
        assign_numbers(_probs({1: 1.0}), np.array([SOLID, SOLID]))


def test_reader_refuses_a_missing_file_and_another_kind_of_model(tmp_path):
    with pytest.raises(ValueError, match="not found"):
        BallNumberReader(tmp_path / "nope.onnx")

    if BallClassifier.default_path().is_file():
        with pytest.raises(ValueError, match="ball-number reader"):
            BallNumberReader(BallClassifier.default_path())


@pytest.mark.skipif(not BallNumberReader.default_path().is_file(), reason="no bundled ball-number reader")
def test_bundled_reader_reads_the_balls_of_a_fresh_render():
    from pix2pockets.synth.renderer import render

    rend = render((5155, 1), (960, 540))
    balls = [b for b in rend.labels["balls"] if b["labelled"] and b["visible_fraction"] > 0.9]
    if len(balls) < 4:
        pytest.skip("render holds fewer than 4 clearly visible balls")
    boxes = np.array([b["box_px"] for b in balls], dtype=float)
    truth = np.array([b["number"] for b in balls])
    classes = np.array([b["class_id"] for b in balls])
    reader = BallNumberReader.from_default()
    probs = reader.read(rend.image, boxes)
    assert probs.shape == (len(balls), N_NUMBERS)
    assert np.allclose(probs.sum(axis=1), 1.0, atol=1e-4)
    numbers, _ = assign_numbers(probs, classes)
    assert np.mean(numbers == truth) >= 0.75

"""Ball-number reader training: settings are checked, accuracy is counted overall and within the true class."""

import numpy as np
import pytest

pytest.importorskip("torch")

from pix2pockets.vision.train.ball_numbers import NumberTrainConfig, number_accuracy


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"data": ()}, "--data"),
        ({"epochs": 0}, "epochs"),
        ({"copies": 0}, "copies"),
        ({"widths": (8, 8)}, "widths"),
        ({"min_visible": 1.5}, "min_visible"),
        ({"centre_jitter": 0.7}, "centre_jitter"),
    ],
)
def test_bad_settings_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        NumberTrainConfig(**{"data": ("d",), "out": "o", **kwargs})


def test_accuracy_within_class_forgives_a_number_of_the_other_group():
    probs = np.full((3, 16), 0.01)
    probs[0, 3] = 1.0  # a 3 read as a 3
    probs[1, 3], probs[1, 11] = 1.0, 0.5  # an 11 read as a 3 first, an 11 second: right within its class
    probs[2, 5], probs[2, 7] = 1.0, 0.5  # a 7 read as a 5: wrong either way
    acc = number_accuracy(probs, np.array([3, 11, 7]))
    assert acc["n"] == 3
    assert acc["accuracy"] == pytest.approx(1 / 3, abs=1e-4)
    assert acc["accuracy_within_class"] == pytest.approx(2 / 3, abs=1e-4)
    assert acc["within_class_by_number"] == {"3": 1.0, "7": 0.0, "11": 1.0}
    assert number_accuracy(np.zeros((0, 16)), np.zeros(0, int)) == {"n": 0}

"""The top-down diagram: balls located unsurely carry a ring as wide as their position error."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from pix2pockets.pipeline.draw import UNSURE, UNSURE_SIGMA, draw_diagram
from pix2pockets.pipeline.photo import suggest
from pix2pockets.testing import SPEC, LabelDetector, NearestPocketPlanner, blank_image, camera, example_layout

HEIGHT = 400


def with_sigma(result, sigma):
    return replace(result, balls=tuple(replace(b, position_sigma_m=sigma) for b in result.balls))


def test_unsure_balls_get_a_ring_and_sure_ones_none():
    cam = camera("top")
    res = suggest(blank_image(cam), "solids", LabelDetector(cam, example_layout()), NearestPocketPlanner(), SPEC)
    sure = draw_diagram(with_sigma(res, UNSURE_SIGMA / 2), HEIGHT)
    unknown = draw_diagram(with_sigma(res, None), HEIGHT)
    unsure = draw_diagram(with_sigma(res, 3 * UNSURE_SIGMA), HEIGHT)
    np.testing.assert_array_equal(sure, unknown)
    changed = np.any(sure != unsure, axis=-1)
    ring_coloured = np.all(np.abs(unsure.astype(int) - UNSURE) <= 30, axis=-1)
    assert (changed & ring_coloured).sum() > 20 * len(res.balls)

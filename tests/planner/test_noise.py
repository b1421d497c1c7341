"""Noise models: presets, determinism, statistics, validation."""

import math

import numpy as np
import pytest

from pix2pockets.planner.noise import FASTFIZ, NO_NOISE, GaussianNoise, aim_noise, noise_model
from pix2pockets.state import Shot

SHOT = Shot(angle=0.3, speed=2.0)


def test_none_is_identity_and_fastfiz_values():
    assert NO_NOISE.perturb(SHOT, np.random.default_rng(0)) == SHOT
    assert FASTFIZ.angle_sigma == pytest.approx(math.radians(0.125))
    assert FASTFIZ.speed_sigma == 0.075
    assert FASTFIZ.elevation_sigma == pytest.approx(math.radians(0.1))
    assert FASTFIZ.tip_sigma == 0.0005
    assert noise_model("fastfiz5x").angle_sigma == pytest.approx(5 * FASTFIZ.angle_sigma)


def test_seeded_and_statistics():
    a = FASTFIZ.perturb_many(SHOT, np.random.default_rng(1), 2000)
    b = FASTFIZ.perturb_many(SHOT, np.random.default_rng(1), 2000)
    assert a == b
    angles = np.array([s.angle for s in a])
    speeds = np.array([s.speed for s in a])
    assert np.std(angles) == pytest.approx(FASTFIZ.angle_sigma, rel=0.1)
    assert np.std(speeds) == pytest.approx(0.075, rel=0.1)
    assert all(s.elevation >= 0 and math.hypot(s.side, s.height) <= 0.5 + 1e-9 for s in a)


def test_aim_only():
    shots = aim_noise(1.0).perturb_many(SHOT, np.random.default_rng(2), 500)
    assert all(s.speed == SHOT.speed for s in shots)
    assert np.std([s.angle for s in shots]) == pytest.approx(math.radians(1.0), rel=0.15)
    assert noise_model("aim:0.5").angle_sigma == pytest.approx(math.radians(0.5))
    assert noise_model("gauss:1:0.1").speed_sigma == 0.1


@pytest.mark.parametrize("name", ["bogus", "aim:x", "gauss:1", "aim:-1"])
def test_bad_names(name):
    with pytest.raises(ValueError):
        noise_model(name)


def test_bad_sigma():
    with pytest.raises(ValueError, match="angle_sigma"):
        GaussianNoise(angle_sigma=-1.0)

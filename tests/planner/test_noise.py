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


def test_skill_levels_ordered_and_pro_is_fastfiz():
    from pix2pockets.planner.noise import SKILLS

    assert list(SKILLS) == ["pro", "club", "beginner"]
    pro, club, beginner = SKILLS.values()
    assert (pro.angle_sigma, pro.speed_sigma, pro.elevation_sigma, pro.tip_sigma) == (
        pytest.approx(FASTFIZ.angle_sigma),
        pytest.approx(FASTFIZ.speed_sigma),
        pytest.approx(FASTFIZ.elevation_sigma),
        pytest.approx(FASTFIZ.tip_sigma),
    )
    for field in ("angle_sigma", "speed_sigma", "elevation_sigma", "tip_sigma"):
        assert getattr(pro, field) < getattr(club, field) < getattr(beginner, field)
    assert noise_model("club") is SKILLS["club"]


def test_noise_file(tmp_path):
    from pix2pockets.planner.noise import load_noise_file

    path = tmp_path / "me.json"
    path.write_text('{"aim_deg": 0.3, "speed_mps": 0.1, "tip_mm": 2}')
    noise = noise_model(str(path))
    assert noise.name == "me"
    assert noise.angle_sigma == pytest.approx(math.radians(0.3))
    assert noise.speed_sigma == 0.1 and noise.elevation_sigma == 0.0 and noise.tip_sigma == pytest.approx(0.002)
    assert load_noise_file(path) == noise


@pytest.mark.parametrize(
    "text, match",
    [
        ("not json", "cannot read"),
        ("[1, 2]", "JSON object"),
        ('{"speed_mps": 0.1}', "aim_deg"),
        ('{"aim_deg": 0.2, "spin": 1}', "unknown keys"),
        ('{"aim_deg": "x"}', "must be a number"),
        ('{"aim_deg": -0.2}', "angle_sigma"),
    ],
)
def test_bad_noise_file(tmp_path, text, match):
    path = tmp_path / "bad.json"
    path.write_text(text)
    with pytest.raises(ValueError, match=match):
        noise_model(str(path))


def test_missing_noise_file(tmp_path):
    with pytest.raises(ValueError, match="cannot read"):
        noise_model(str(tmp_path / "nope.json"))

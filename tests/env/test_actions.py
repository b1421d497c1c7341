"""Action spaces and their mapping to strokes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pix2pockets.env.actions import ActionMap, ActionType


def test_discrete_mapping_matches_the_paper() -> None:
    amap = ActionMap()
    assert amap.space.nvec.tolist() == [36000, 30]
    angle, speed = amap.decode(np.array([18000, 0]))
    assert angle == pytest.approx(0.0)
    assert speed == pytest.approx(0.2)
    angle, speed = amap.decode(np.array([0, 29]))
    assert angle == pytest.approx(-math.pi)
    assert speed == pytest.approx(8.0)
    angle, _ = amap.decode(np.array([27000, 5]))
    assert math.degrees(angle) == pytest.approx(90.0)
    assert np.allclose(np.diff(amap.speeds), (8.0 - 0.2) / 29)


def test_bins_round_trip() -> None:
    amap = ActionMap()
    bins = np.array([0, 1, 17999, 18000, 35999])
    assert np.array_equal(amap.bin_of_angle(amap.angle_of_bin(bins)), bins)
    assert amap.bin_of_angle(math.pi) == 0  # +180 deg wraps to the -180 bin


def test_continuous_mapping() -> None:
    amap = ActionMap(ActionType.CONTINUOUS)
    assert amap.space.shape == (2,)
    angle, speed = amap.decode(np.array([0.5, -1.0], dtype=np.float32))
    assert math.degrees(angle) == pytest.approx(90.0)
    assert speed == pytest.approx(0.2)
    _, speed = amap.decode(np.array([0.0, 1.0]))
    assert speed == pytest.approx(8.0)


def test_noise_is_seeded_and_centred() -> None:
    amap = ActionMap(aim_noise_deg=0.5, speed_noise=0.1)
    a = [amap.to_shot(np.array([18000, 10]), np.random.default_rng(3)) for _ in range(2)]
    assert a[0] == a[1]
    rng = np.random.default_rng(0)
    angles = [amap.to_shot(np.array([18000, 10]), rng).angle for _ in range(400)]
    assert abs(np.degrees(np.mean(angles))) < 0.1
    assert np.degrees(np.std(angles)) == pytest.approx(0.5, rel=0.2)
    assert amap.to_shot(np.array([18000, 10])).angle == 0.0  # no rng: no noise


@pytest.mark.parametrize("action", [[36000, 0], [-1, 0], [0, 30], [0.5, 1], [1, 2, 3]])
def test_bad_discrete_actions(action: list) -> None:
    with pytest.raises(ValueError):
        ActionMap().decode(np.array(action))


@pytest.mark.parametrize(
    "kw", [{"min_speed": 0.0}, {"min_speed": 5.0, "max_speed": 4.0}, {"n_powers": 1}, {"aim_noise_deg": -1.0}]
)
def test_bad_action_maps(kw: dict) -> None:
    with pytest.raises(ValueError):
        ActionMap(**kw)

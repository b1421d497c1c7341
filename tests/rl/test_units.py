"""Pure helpers of the RL package (no torch needed)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from pix2pockets.rl import missing_rl_modules
from pix2pockets.rl.envs import EnvChoice, MaxPowerMask, env_kwargs, read_outcome
from pix2pockets.rl.evaluate import wilson_interval

from .standin import N_DIR, N_POW, register_standin


def test_wilson_interval_known_values():
    lo, hi = wilson_interval(50, 100)
    assert lo == pytest.approx(0.4038, abs=1e-3)
    assert hi == pytest.approx(0.5962, abs=1e-3)
    assert wilson_interval(0, 10)[0] == 0.0
    assert wilson_interval(10, 10)[1] == 1.0
    assert wilson_interval(0, 0) == (0.0, 1.0)
    with pytest.raises(ValueError):
        wilson_interval(5, 3)


@pytest.mark.parametrize(
    ("terminated", "info", "expected"),
    [
        (True, {"shot_success": False, "outcome": "end_turn"}, (False, False)),
        (False, {"shot_success": True, "outcome": "continue"}, (True, False)),
        (True, {"shot_success": True, "outcome": "win", "is_success": True}, (True, True)),
        (True, {"shot_success": True, "outcome": "loss"}, (True, False)),
        (False, {}, (True, False)),
        (True, {}, (False, False)),
    ],
)
def test_read_outcome(terminated, info, expected):
    assert read_outcome(terminated, False, info) == expected


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"mask": "bank"}, "mask must be"),
        ({"max_power": True}, "needs a mask"),
        ({"continuous": True, "mask": "direct"}, "discrete"),
        ({"env": ""}, "env must be"),
        ({"physics": "pymunk"}, "physics must be"),
    ],
)
def test_env_choice_rejects_bad_input(kwargs, message):
    with pytest.raises(ValueError, match=message):
        EnvChoice(**kwargs)


def test_env_choice_maps_short_names():
    assert EnvChoice("all").env_id == "pix2pockets/AllBall-v0"
    assert EnvChoice.from_dict(EnvChoice("two", mask="mirror").to_dict()) == EnvChoice("two", mask="mirror")


def test_env_choice_physics():
    paper = EnvChoice("all", physics="paper")
    assert EnvChoice.from_dict(paper.to_dict()) == paper
    assert env_kwargs(paper)["physics"] == "paper" and "physics" not in env_kwargs(EnvChoice("all"))
    legacy = {"env": "all", "continuous": False, "mask": None, "max_power": False}  # agent files without it
    assert EnvChoice.from_dict(legacy).physics == "event"


def test_max_power_mask_keeps_directions_and_only_top_power():
    env = MaxPowerMask(gym.make(register_standin(), mask_kind="direct"))
    env.reset(seed=0)
    base = env.unwrapped.action_masks()
    mask = env.action_masks()
    assert np.array_equal(mask[:N_DIR], base[:N_DIR])
    assert mask[N_DIR:].tolist() == [False] * (N_POW - 1) + [True]


def test_rl_modules_present_in_this_venv():
    # CI installs the rl extra; if this fails the extra is missing there.
    assert missing_rl_modules() == []


def test_masked_sample_stays_inside_the_mask():
    from pix2pockets.rl.evaluate import masked_sample

    rng = np.random.default_rng(0)
    mask = np.zeros(10 + 3, dtype=bool)
    mask[[2, 7]] = True
    mask[12] = True
    draws = {tuple(masked_sample(mask, np.array([10, 3]), rng)) for _ in range(50)}
    assert draws == {(2, 2), (7, 2)}


def test_cli_explains_a_missing_rl_extra(monkeypatch, capsys, tmp_path):
    import pix2pockets.rl as rl
    from pix2pockets.cli.main import main

    monkeypatch.setattr(rl, "missing_rl_modules", lambda: ["torch", "stable_baselines3"])
    argv = ["rl", "train", "--algo", "ppo", "--env", "one", "--steps", "10", "--out", str(tmp_path / "r")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "install the rl extra" in err and "Traceback" not in err
    assert not (tmp_path / "r").exists()

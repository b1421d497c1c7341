"""The agents shipped in ``pix2pockets/data/agents`` load, are small, and play their environment."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("sb3_contrib")

from pix2pockets.rl.bundle import read_meta
from pix2pockets.rl.evaluate import evaluate_model

AGENTS = sorted(Path(str(resources.files("pix2pockets.data.agents"))).glob("*.zip"))
EXPECTED = {"one-ball.zip": "one", "two-ball.zip": "two", "all-ball.zip": "all"}


def test_one_agent_per_environment():
    assert {p.name for p in AGENTS} == set(EXPECTED)


@pytest.mark.parametrize("path", AGENTS, ids=lambda p: p.name)
def test_bundled_agent(path):
    assert path.stat().st_size < 5_000_000
    meta = read_meta(path)
    assert meta.choice.env == EXPECTED[path.name]
    result = evaluate_model(str(path), episodes=5, seed=0)
    assert result.shot_success.trials >= 5

"""The environment benchmark scripts run (tiny sizes) and report what they promise."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _load(name: str):
    spec = importlib.util.spec_from_file_location(f"bench_{name}", ROOT / "benchmarks" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_env_benchmark_writes_json(tmp_path: Path) -> None:
    out = tmp_path / "env.json"
    assert _load("env").main(["--steps", "3", "--physics", "event", "--masks", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert set(data["backends"]["event"]) == {"one-discrete", "two-discrete", "all-discrete", "all-continuous"}
    assert all(v["steps_per_s"] > 0 for v in data["backends"]["event"].values())


def test_soak_counts_steps_without_failures(tmp_path: Path) -> None:
    out = tmp_path / "soak.json"
    assert _load("env_soak").main(["--steps", "48", "--chunk", "2", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["steps"] == 48 and data["failures"] == 0 and data["complete"]


@pytest.mark.parametrize("argv", [["--steps", "0"], ["--physics", "nope"]])
def test_env_benchmark_rejects_bad_input(argv: list[str]) -> None:
    assert _load("env").main(argv) == 2

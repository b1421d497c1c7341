"""The RL grid driver with ``--ray``: one run per worker of a local Ray instance, resumable, skipping finished runs.

Skipped without the ``ray`` and ``rl`` extras.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("ray")
pytest.importorskip("stable_baselines3")

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "rl_grid.py"


def grid(root: Path, *extra: str) -> subprocess.CompletedProcess:
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(SCRIPT.parents[1] / "src"), os.environ.get("PYTHONPATH", "")]),
    }
    argv = [sys.executable, str(SCRIPT), "train", "--only", "one-a2c", "--steps", "40", "--checkpoint-every", "20"]
    return subprocess.run([*argv, "--root", str(root), *extra], capture_output=True, text=True, env=env, timeout=600)


def test_grid_trains_each_run_on_a_ray_worker_and_skips_it_when_done(tmp_path):
    first = grid(tmp_path, "--ray", "--workers", "1")
    assert first.returncode == 0, first.stderr[-2000:]
    assert "one-a2c: trained" in first.stdout
    assert (tmp_path / "one-a2c" / "model.zip").is_file()
    again = grid(tmp_path, "--ray", "--workers", "1")
    assert again.returncode == 0 and "= one-a2c: done (40 steps)" in again.stdout

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from pix2pockets.cli import warmup_cmd
from pix2pockets.cli.main import main
from pix2pockets.physics.event import warm

SRC = str(Path(warmup_cmd.__file__).parents[2])


def test_warmup_loads_or_compiles_the_engine(capsys):
    assert main(["warmup", "--no-example"]) == 0
    out = capsys.readouterr().out
    assert out.strip().splitlines()[-1].startswith("physics engine: ")
    assert warm.kernels_cached()


def test_first_run_notice_comes_first_and_the_answer_is_unchanged(monkeypatch, capsys, tmp_path):
    """A cold cache: one line on stderr before anything else, then the usual answer."""
    assert main(["suggest", "--json", str(tmp_path / "warm.json")]) == 0
    capsys.readouterr()
    calls = []
    monkeypatch.setattr(warm, "kernels_cached", lambda: False)
    monkeypatch.setattr(warm, "compile_kernels", lambda: calls.append(1) or 0.0)
    assert main(["suggest", "--json", str(tmp_path / "cold.json")]) == 0
    captured = capsys.readouterr()
    assert captured.err.splitlines()[0] == warmup_cmd.FIRST_RUN_NOTICE and calls == [1]
    cold, warmed = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("cold", "warm"))
    assert cold["suggestion"] == warmed["suggestion"]


def test_no_notice_when_compiled(capsys, tmp_path):
    assert warm.kernels_cached() or main(["warmup", "--no-example"]) == 0
    capsys.readouterr()
    assert main(["suggest", "--json", str(tmp_path / "s.json")]) == 0
    assert warmup_cmd.FIRST_RUN_NOTICE not in capsys.readouterr().err


COLD_CHECK = """
import json
from pix2pockets.physics.event import _detect, _engine, _motion, _roots, warm
before = warm.kernels_cached()
seconds = warm.compile_kernels()
twice = {f"{m.__name__}.{k}": len(v.signatures) for m in (_engine, _motion, _detect, _roots)
         for k, v in vars(m).items() if hasattr(v, "signatures") and len(v.signatures) > 1}
print(json.dumps({"before": before, "after": warm.kernels_cached(), "twice": twice, "seconds": seconds}))
"""


def test_cold_cache_compiles_once_per_kernel_and_later_processes_load(tmp_path):
    """A fresh numba cache in new processes: the split compile gives each kernel one signature, and caches it."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "PYTHONPATH": SRC}
    run = subprocess.run([sys.executable, "-c", COLD_CHECK], env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    doc = json.loads(run.stdout.strip().splitlines()[-1])
    assert doc["before"] is False and doc["after"] is True and doc["twice"] == {}
    again = subprocess.run(
        [sys.executable, "-m", "pix2pockets.cli.main", "warmup", "--no-example"],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert again.returncode == 0 and "physics engine: loaded from the cache" in again.stdout, again.stderr[-2000:]


@pytest.mark.parametrize("part", ["event-times", "motion"])
def test_helper_parts_run(part, monkeypatch):
    called = []
    monkeypatch.setattr(warm, "_compile_event_times", lambda: called.append("event-times"))
    monkeypatch.setattr(warm, "_compile_motion", lambda: called.append("motion"))
    assert warm.main(["--part", part]) == 0 and called == [part]

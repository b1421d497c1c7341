"""`rl train` as a new user meets it: the progress bar, a failed first start, rounded step counts, subprocess
environments, devices and threads; `rl plot` / `rl export` say what they wrote."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("sb3_contrib")

from pix2pockets.cli.main import main
from pix2pockets.rl import algos
from pix2pockets.rl import train as train_module
from pix2pockets.rl.bundle import read_meta
from pix2pockets.rl.train import TrainConfig, planned_steps, train

from .standin import register_standin

ROOT = Path(__file__).resolve().parents[2]
SMALL_PPO = {"n_steps": 64, "batch_size": 32, "n_epochs": 1}


@pytest.fixture(scope="module")
def env_id() -> str:
    return register_standin()


def test_rl_extra_installs_the_progress_bar() -> None:
    """SB3's progress bar needs tqdm and rich; `rl train` shows it by default."""
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    names = {d.split(">")[0].split("=")[0].split("[")[0].strip() for d in meta["optional-dependencies"]["rl"]}
    base = {d.split(">")[0].split("=")[0].strip() for d in meta["dependencies"]}
    assert "rich" in names
    assert "tqdm" in names | base


def test_train_with_progress_bar(env_id: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The default (a progress bar) trains; CI runs this with the `rl` extra installed."""
    pytest.importorskip("rich")
    argv = ["rl", "train", "--algo", "a2c", "--env", env_id, "--steps", "40", "--out", str(tmp_path / "r")]
    assert main(argv) == 0
    assert "saved" in capsys.readouterr().out
    assert read_meta(tmp_path / "r" / "model.zip").steps == 40


def test_train_without_rich_warns_and_trains(
    env_id: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(train_module, "progress_bar_missing", lambda: ["rich"])
    argv = ["rl", "train", "--algo", "a2c", "--env", env_id, "--steps", "40", "--out", str(tmp_path / "r")]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "no progress bar" in err and "pip install rich" in err
    assert (tmp_path / "r" / "model.zip").is_file()


def test_failed_start_does_not_demand_resume(env_id: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A run that fails before its first checkpoint leaves no run behind: the retry starts afresh."""
    config = TrainConfig("a2c", env_id, steps=40, seed=0, out=str(tmp_path / "r"), progress=False)

    def boom(*args: object, **kwargs: object) -> None:
        raise RuntimeError("interrupted")

    with monkeypatch.context() as m:
        m.setattr(algos.algo_class("a2c"), "learn", boom)
        with pytest.raises(RuntimeError):
            train(config)
    assert not (tmp_path / "r" / "checkpoint.zip").exists()
    assert read_meta(train(config)).steps == 40
    with pytest.raises(ValueError, match="--resume"):
        train(config)  # a run that did save is protected


@pytest.mark.parametrize(
    ("done", "target", "rollout", "end"),
    [(0, 256, 2048, 2048), (0, 4096, 2048, 4096), (0, 3000, 2048, 4096), (2048, 3000, 2048, 4096), (10, 5, 64, 10)],
)
def test_planned_steps(done: int, target: int, rollout: int, end: int) -> None:
    assert planned_steps(done, target, rollout) == end


def test_rounded_steps_are_announced(env_id: str, tmp_path: Path) -> None:
    """PPO collects whole rollouts: asking for fewer steps than one rollout says how many it trains."""
    notes: list[str] = []
    config = TrainConfig("ppo", env_id, steps=40, seed=0, out=str(tmp_path / "r"), progress=False, overrides=SMALL_PPO)
    path = train(config, log=notes.append)
    assert read_meta(path).steps == 64
    assert any("training to 64 steps, not 40" in n for n in notes)
    notes.clear()
    exact = TrainConfig("ppo", env_id, steps=64, seed=0, out=str(tmp_path / "e"), progress=False, overrides=SMALL_PPO)
    train(exact, log=notes.append)
    assert not notes


def test_subprocess_envs_train_and_resume(tmp_path: Path) -> None:
    """Two environments in subprocesses (the real 1-ball env: subprocesses import the registered ids)."""
    out = tmp_path / "r"
    small = {"n_steps": 16, "batch_size": 16, "n_epochs": 1}
    config = TrainConfig("ppo", "one", steps=32, seed=0, out=str(out), progress=False, n_envs=2, overrides=small)
    assert read_meta(train(config)).steps == 32
    rows = (out / "monitor.csv").read_text().splitlines()
    assert "ep_shots" in rows[1] and len(rows) == 2 + 32  # one shot per 1-ball episode
    more = TrainConfig("ppo", "one", steps=64, seed=0, out=str(out), progress=False, n_envs=2, overrides=small)
    assert read_meta(train(more, resume=True)).steps == 64
    rows = (out / "monitor.csv").read_text().splitlines()
    assert len(rows) == 2 + 64  # appended, not restarted
    stints = [json.loads(line) for line in (out / "stints.jsonl").read_text().splitlines()]
    assert [s["n_envs"] for s in stints] == [2, 2]


def test_resume_with_other_envs_keeps_the_rollout(tmp_path: Path) -> None:
    """A one-environment run (32-step rollouts) resumed with two environments collects 16 steps in each and so
    updates every 32 steps as before, and again with one; ``rollout_steps`` sets another rollout."""
    out = tmp_path / "r"
    small = {"batch_size": 16, "n_epochs": 1}

    def stint(steps: int, n_envs: int, rollout: int | None = None) -> int:
        config = TrainConfig(
            "ppo", "one", steps=steps, seed=0, out=str(out), progress=False, n_envs=n_envs, overrides=small,
            rollout_steps=rollout,
        )  # fmt: skip
        return read_meta(train(config, resume=out.exists())).steps

    assert stint(32, 1, rollout=32) == 32
    assert stint(64, 2) == 64
    assert stint(96, 1) == 96
    assert stint(97, 3) == 96 + 3 * 32  # 3 envs cannot share the 32-step rollout: each collects the saved 32
    assert stint(208, 2, rollout=16) == 208  # an explicit rollout: 8 steps per env
    stints = [json.loads(line) for line in (out / "stints.jsonl").read_text().splitlines()]
    assert [(s["n_envs"], s["rollout_steps"]) for s in stints] == [(1, 32), (2, 32), (1, 32), (3, 96), (2, 16)]


@pytest.mark.parametrize(
    ("algo", "options", "message"),
    [
        ("td3", {"rollout_steps": 64}, "on-policy"),
        ("ppo", {"rollout_steps": 63, "n_envs": 2}, "multiple of n_envs"),
        ("ppo", {"rollout_steps": 0}, "multiple of n_envs"),
        ("ppo", {"rollout_steps": 64, "overrides": {"n_steps": 32}}, "not both"),
    ],
)
def test_bad_rollout_steps(algo: str, options: dict, message: str, tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=message):
        TrainConfig(algo, "one", steps=10, seed=0, out=str(tmp_path), **options)


def test_threads() -> None:
    assert algos.torch_threads(1, cpus=2) == 1
    assert algos.torch_threads(1, cpus=16) == 8
    assert algos.torch_threads(8, cpus=16) == 4
    assert algos.torch_threads(16, cpus=16) == 1


@pytest.mark.parametrize("bad", [{"n_envs": 0}, {"threads": 0}])
def test_bad_options(bad: dict[str, int], tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="must be >= 1"):
        TrainConfig("ppo", "one", steps=10, seed=0, out=str(tmp_path), **bad)


def test_plot_and_export_say_what_they_wrote(env_id: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run = tmp_path / "r"
    train(TrainConfig("a2c", env_id, steps=40, seed=0, out=str(run), progress=False))
    capsys.readouterr()
    png = tmp_path / "c.png"
    assert main(["rl", "plot", str(run), "--out", str(png), "--window", "10"]) == 0
    assert f"wrote {png}" in capsys.readouterr().out
    slim = tmp_path / "slim.zip"
    assert main(["rl", "export", "--model", str(run / "model.zip"), "--out", str(slim)]) == 0
    assert f"wrote {slim}" in capsys.readouterr().out

"""Pieces of a job give the whole job's result: layout ranges of `evaluate planner`, scenes of `synth`.

No Ray needed here; tests/scale/test_ray.py runs the same on a local Ray instance.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

import pytest

from pix2pockets.cli.evaluate_planner import PlannerJob, evaluate_layouts
from pix2pockets.cli.main import main
from pix2pockets.planner.evaluation import merge_summaries
from pix2pockets.scale import split_range
from pix2pockets.synth.dataset import SceneFiles, SceneJob, scene_files, write_dataset

JOB = PlannerJob(planner="oracle", physics="event", balls=16, seed=3, noise="fastfiz")


@pytest.mark.parametrize(
    ("start", "count", "pieces", "expected"),
    [
        (0, 10, 3, [range(0, 3), range(3, 6), range(6, 10)]),
        (5, 2, 4, [range(5, 6), range(6, 7)]),
        (0, 1, 1, [range(0, 1)]),
        (0, 0, 3, []),
    ],
)
def test_split_range(start: int, count: int, pieces: int, expected: list[range]) -> None:
    assert split_range(start, count, pieces) == expected


@pytest.mark.parametrize(("count", "pieces"), [(-1, 2), (3, 0)])
def test_split_range_bad_input(count: int, pieces: int) -> None:
    with pytest.raises(ValueError, match="count >= 0"):
        split_range(0, count, pieces)


def counts(summary) -> dict:
    data = summary.to_dict()
    return {k: v for k, v in data.items() if not k.startswith("decision_time")} | {
        "n_times": len(summary.decision_times)
    }


def test_merged_pieces_equal_one_run() -> None:
    whole = evaluate_layouts(range(0, 10), JOB)
    parts = [evaluate_layouts(r, JOB) for r in split_range(0, 10, 3)]
    assert counts(merge_summaries(parts)) == counts(whole)
    assert whole.shots > 10  # the 16-ball turns go on after a pot


def test_merge_refuses_different_evaluations() -> None:
    a = evaluate_layouts(range(0, 1), JOB)
    b = evaluate_layouts(range(1, 2), PlannerJob(planner="oracle", physics="event", balls=16, seed=4))
    with pytest.raises(ValueError, match="different settings"):
        merge_summaries([a, b])
    with pytest.raises(ValueError, match="nothing to merge"):
        merge_summaries([])


def tree(root: Path) -> dict[str, bytes]:
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


@pytest.mark.parametrize("views", [1, 3])
def test_synth_scene_map_writes_the_same_bytes(views: int, tmp_path: Path) -> None:
    """Scenes rendered elsewhere (as bytes, out of order of work) give the local run's files exactly."""

    def elsewhere(job: SceneJob, scenes: Sequence[tuple[int, str]]) -> list[SceneFiles]:
        return [f for i in range(len(scenes)) for f in scene_files(job, [scenes[i]])]

    options = {"seed": 5, "size": (96, 64), "split": (0.5, 0.25, 0.25), "views": views}
    write_dataset(tmp_path / "local", 4, **options)
    write_dataset(tmp_path / "mapped", 4, scene_map=elsewhere, **options)
    assert tree(tmp_path / "local") == tree(tmp_path / "mapped")
    assert len(tree(tmp_path / "local")) == 3 * 4 * views + 2


@pytest.mark.parametrize("command", ["synth --n 1 --out {tmp}/o", "evaluate planner --layouts 1"])
def test_workers_needs_ray(command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = [*command.replace("{tmp}", str(tmp_path)).split(), "--workers", "2"]
    assert main(argv) == 2
    assert "--workers applies with --ray" in capsys.readouterr().err


def test_ray_missing_is_a_clean_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray raises ImportError
    assert main(["evaluate", "planner", "--layouts", "1", "--ray", "--no-progress"]) == 2
    assert 'pip install ".[ray]"' in capsys.readouterr().err

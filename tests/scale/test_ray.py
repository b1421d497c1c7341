"""`--ray` on a local Ray instance (small sizes): the same numbers and the same bytes as one process.

Skipped when ray is not installed (it is the optional ``ray`` extra).
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest

from pix2pockets.cli.main import main
from pix2pockets.scale import RayPool, split_range

ray = pytest.importorskip("ray")

WORKERS = 2


@pytest.fixture(scope="module")
def pool() -> Iterator[RayPool]:
    """One local instance for the module; the commands join it instead of starting their own."""
    with RayPool("local", WORKERS) as started:
        yield started


def test_pool_maps_in_order(pool: RayPool) -> None:
    assert pool.cpus == WORKERS
    got = list(pool.map(split_range, [10, 0, 5], 4, 2))
    assert got == [split_range(10, 4, 2), split_range(0, 4, 2), split_range(5, 4, 2)]


def test_evaluate_planner_on_ray_matches_one_process(pool: RayPool, tmp_path: Path) -> None:
    argv = ["evaluate", "planner", "--planner", "oracle", "--layouts", "12", "--seed", "2", "--noise", "fastfiz"]
    argv += ["--no-progress"]
    assert main([*argv, "--json", str(tmp_path / "one.json")]) == 0
    assert main([*argv, "--ray", "--json", str(tmp_path / "ray.json")]) == 0
    one, on_ray = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("one", "ray"))
    for data in (one, on_ray):
        for key in [k for k in data if k.startswith("decision_time")]:
            del data[key]
    assert one == on_ray
    assert one["layouts"] == 12


def test_synth_on_ray_writes_the_same_bytes(pool: RayPool, tmp_path: Path) -> None:
    argv = ["synth", "--n", "5", "--seed", "7", "--size", "96x64", "--no-progress"]
    assert main([*argv, "--out", str(tmp_path / "one")]) == 0
    assert main([*argv, "--out", str(tmp_path / "ray"), "--ray"]) == 0

    def tree(root: Path) -> dict[str, bytes]:
        return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}

    one, on_ray = tree(tmp_path / "one"), tree(tmp_path / "ray")
    assert one == on_ray
    assert sum(k.endswith(".jpg") for k in one) == 5


def test_a_command_starts_and_stops_its_own_instance(tmp_path: Path) -> None:
    """Without a running instance `--ray` starts one for the command and stops it after."""
    ray.shutdown()
    argv = ["evaluate", "planner", "--planner", "oracle", "--layouts", "2", "--no-progress", "--ray", "--workers", "1"]
    assert main(argv) == 0
    assert not ray.is_initialized()

"""``synth --ray``: scenes rendered on Ray workers, written by the command; the same bytes as one process."""

from __future__ import annotations

from collections.abc import Iterator, Sequence

from pix2pockets.scale.ray_pool import RayPool
from pix2pockets.synth.dataset import SceneFiles, SceneJob, SceneMap, scene_files

SCENES_PER_TASK = 4
"""Scenes per Ray task: enough to amortise a task's overhead, few enough to balance the workers."""


def _render_chunk(scenes: Sequence[tuple[int, str]], job: SceneJob) -> list[SceneFiles]:
    return scene_files(job, scenes)


def ray_scene_map(pool: RayPool, scenes_per_task: int = SCENES_PER_TASK) -> SceneMap:
    """A :data:`~pix2pockets.synth.dataset.SceneMap` rendering on ``pool``'s workers, in scene order.

    Workers return the files' bytes, so no shared file system is needed; only the command writes.
    """
    if scenes_per_task < 1:
        raise ValueError(f"scenes_per_task must be >= 1, got {scenes_per_task}")

    def render_all(job: SceneJob, scenes: Sequence[tuple[int, str]]) -> Iterator[SceneFiles]:
        chunks = [list(scenes[k : k + scenes_per_task]) for k in range(0, len(scenes), scenes_per_task)]
        for chunk in pool.map(_render_chunk, chunks, job):
            yield from chunk

    return render_all

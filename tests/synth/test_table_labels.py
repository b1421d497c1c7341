"""Table labels of renders: the six pockets and the playing-surface corners sit where the camera puts them."""

from __future__ import annotations

import numpy as np
import pytest

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.synth import render
from pix2pockets.synth import scene_codes as sc
from pix2pockets.synth.labels import POCKET_SURFACE_IDS
from pix2pockets.synth.renderer import scene_of

SIZE = (320, 180)
SEEDS = list(range(6))


def camera_of(labels: dict) -> PinholeCamera:
    c = labels["camera"]
    return PinholeCamera(np.array(c["K"]), np.array(c["R"]), np.array(c["t"]), tuple(c["image_size"]))


@pytest.fixture(scope="module")
def renders():
    return {s: render(s, SIZE) for s in SEEDS}


def test_pockets_project_where_the_camera_puts_the_spec_s_pockets(renders):
    for seed, rend in renders.items():
        spec = scene_of(seed).spec
        cam = camera_of(rend.labels)
        pockets = rend.labels["pockets"]
        assert [p["index"] for p in pockets] == list(range(6))
        assert [p["kind"] for p in pockets] == [p.kind.value for p in spec.pockets]
        for entry, pocket in zip(pockets, spec.pockets, strict=True):
            assert entry["name"] == pocket.name
            assert np.allclose(entry["table_m"], [*pocket.aim, 0.0], atol=1e-6)
            want = cam.project_table(pocket.aim)
            if entry["px"] is None:
                assert not entry["in_frame"] and not entry["visible"]
                continue
            assert np.allclose(entry["px"], want, atol=2e-3)
            u, v = entry["px"]
            assert entry["in_frame"] == bool(0 <= u < SIZE[0] and 0 <= v < SIZE[1])
            assert entry["visible"] <= entry["in_frame"]


def test_pocket_visibility_reads_the_id_buffer(renders):
    seen = 0
    for rend in renders.values():
        for entry in rend.labels["pockets"]:
            if not entry["in_frame"]:
                continue
            u, v = (int(c) for c in entry["px"])
            shows = rend.ids[v, u] in POCKET_SURFACE_IDS and not rend.occluded[v, u]
            assert entry["visible"] == shows
            seen += entry["visible"]
    assert seen >= 12


def test_top_view_sees_every_pocket_mouth_on_the_cloth():
    """From above, each in-frame pocket mouth centre is on the cloth or the hole, never on the rail."""
    for seed in range(3):
        rend = render(seed, SIZE, camera_kind="top")
        for entry in rend.labels["pockets"]:
            if entry["in_frame"]:
                u, v = (int(c) for c in entry["px"])
                assert rend.ids[v, u] in (*POCKET_SURFACE_IDS, *range(sc.ID_BALL0, sc.ID_BALL0 + 16)), entry


def test_corners_project_at_cloth_level(renders):
    for seed, rend in renders.items():
        spec = scene_of(seed).spec
        cam = camera_of(rend.labels)
        for entry, xy in zip(rend.labels["corners"], spec.corners, strict=True):
            if entry["px_cloth"] is not None:
                assert np.allclose(entry["px_cloth"], cam.project_table(xy), atol=2e-3)

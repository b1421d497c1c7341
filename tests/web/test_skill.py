"""The page's skill level: offered, validated, carried to the worker's planner."""

import pytest
from fastapi.testclient import TestClient

from pix2pockets.testing import LabelsDetector, NearestPocketPlanner
from pix2pockets.web.app import create_app
from pix2pockets.web.worker import SKILLS, Engine, EngineSpec, job_group, split_group


@pytest.mark.parametrize("group, skill", [("auto", "pro"), ("solids", "club"), ("stripes", "beginner")])
def test_group_field_round_trip(group, skill):
    assert split_group(job_group(group, skill)) == (group, skill)
    assert job_group("auto") == "auto"


def test_engine_planner_per_skill():
    engine = Engine(EngineSpec(None, None))
    assert engine.planner_for("club").noise.name == "club"
    assert engine.planner_for("club") is engine.planner_for("club")
    given = NearestPocketPlanner()
    assert Engine(EngineSpec(None, given)).planner_for("beginner") is given


def test_page_offers_skills_and_rejects_unknown(rendered):
    client = TestClient(create_app(LabelsDetector(rendered[1]), NearestPocketPlanner()))
    html = client.get("/").text
    assert all(f'value="{s}"' in html for s in SKILLS)
    assert client.get("/api/health").json()["skills"] == list(SKILLS)
    r = client.post("/api/suggest", files={"file": ("t.png", rendered[0], "image/png")}, data={"skill": "wizard"})
    assert r.status_code == 400 and "unknown skill" in r.json()["error"]
    r = client.post("/api/suggest", files={"file": ("t.png", rendered[0], "image/png")}, data={"skill": "club"})
    assert r.status_code == 200

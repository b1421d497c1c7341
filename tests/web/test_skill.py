"""The page's skill level: offered, validated, carried to the worker's planner."""

import pytest
from fastapi.testclient import TestClient

from pix2pockets.testing import LabelsDetector, NearestPocketPlanner
from pix2pockets.web.app import create_app
from pix2pockets.web.worker import SKILLS, TABLES, Engine, EngineSpec, JobOptions


@pytest.mark.parametrize("options", ["auto", JobOptions("solids", "club", "7ft")])
def test_job_options_from_a_group_or_given(options):
    got = JobOptions.of(options)
    assert got == (JobOptions(group="auto") if options == "auto" else options)


def test_page_offers_table_sizes_and_rejects_unknown(rendered):
    client = TestClient(create_app(LabelsDetector(rendered[1]), NearestPocketPlanner()))
    assert all(f'value="{t}"' in client.get("/").text for t in TABLES)
    assert client.get("/api/health").json()["tables"] == list(TABLES)
    r = client.post("/api/suggest", files={"file": ("t.png", rendered[0], "image/png")}, data={"table": "12ft"})
    assert r.status_code == 400 and "unknown table" in r.json()["error"]
    r = client.post("/api/suggest", files={"file": ("t.png", rendered[0], "image/png")}, data={"table": "7ft"})
    assert r.status_code == 200 and r.json()["table"]["size"]["name"] == "7ft"
    assert r.json()["table"]["size_source"] == "given"


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

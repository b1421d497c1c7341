"""The page's choices (skill level, table size, ball in hand): offered, validated, carried to the worker."""

import pytest
from fastapi.testclient import TestClient

from pix2pockets.testing import LabelsDetector, NearestPocketPlanner
from pix2pockets.web.app import IN_HAND, create_app
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


def test_page_offers_ball_in_hand_and_rejects_unknown(rendered):
    client = TestClient(create_app(LabelsDetector(rendered[1]), NearestPocketPlanner()))
    html = client.get("/").text
    assert all(f'value="{a}"' in html for a in IN_HAND) and 'name="in_hand"' in html
    assert client.get("/api/health").json()["ball_in_hand"] == list(IN_HAND) == ["none", "table", "baulk"]
    photo = {"file": ("t.png", rendered[0], "image/png")}
    r = client.post("/api/suggest", files=photo, data={"in_hand": "pocket"})
    assert r.status_code == 400 and "unknown ball in hand 'pocket'" in r.json()["error"]
    r = client.post("/api/suggest", files=photo, data={"in_hand": "table"})
    assert r.status_code == 200 and r.json()["ball_in_hand"] == "table" and r.json()["balls"][-1]["in_hand"]
    assert r.json()["text"].startswith("Ball in hand")
    r = client.post("/api/suggest", files=photo)
    assert r.status_code == 200 and r.json()["ball_in_hand"] is None


def test_without_a_cue_ball_ball_in_hand_still_gives_a_shot(rendered):
    client = TestClient(create_app(LabelsDetector(rendered[1], ("cue",)), NearestPocketPlanner()))
    photo = {"file": ("t.png", rendered[0], "image/png")}
    r = client.post("/api/suggest", files=photo)
    assert r.status_code == 422 and "ask for ball in hand" in r.json()["error"]
    r = client.post("/api/suggest", files=photo, data={"in_hand": "baulk"})
    assert r.status_code == 200 and r.json()["ball_in_hand"] == "baulk"

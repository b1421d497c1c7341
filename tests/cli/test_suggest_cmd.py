import json
from importlib import resources

import cv2
import numpy as np
import pytest

from pix2pockets.cli.main import main
from pix2pockets.pipeline import photo
from pix2pockets.testing import LabelDetector, NearestPocketPlanner, blank_image, camera, example_layout


@pytest.fixture
def standins(monkeypatch):
    cam = camera("45")
    det = LabelDetector(cam, example_layout())
    monkeypatch.setattr(photo, "default_detector", lambda: det)
    monkeypatch.setattr(photo, "default_planner", lambda: NearestPocketPlanner())
    return cam, det


@pytest.fixture
def photo_file(tmp_path, standins):
    path = tmp_path / "table.png"
    cv2.imwrite(str(path), blank_image(standins[0]))
    return path


def test_suggest_writes_picture_and_json(tmp_path, photo_file, capsys):
    out, js = tmp_path / "out.png", tmp_path / "out.json"
    assert main(["suggest", str(photo_file), "--group", "solids", "--out", str(out), "--json", str(js)]) == 0
    doc = json.loads(js.read_text())
    assert doc["image"]["width"] == 1280 and len(doc["table"]["corners_px"]) == 4
    assert doc["suggestion"]["kind"] == "direct"
    picture = cv2.imread(str(out))
    assert picture is not None and picture.shape[1] > 1280
    assert "pocket" in capsys.readouterr().out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.json", "out.png", "table.png"]  # no temp files


def test_suggest_json_to_stdout(photo_file, capsys):
    assert main(["suggest", str(photo_file), "--json", "-"]) == 0
    assert json.loads(capsys.readouterr().out)["suggestion"]["group"] in ("solids", "stripes")


def test_refuses_to_overwrite_without_force(tmp_path, photo_file, capsys):
    out = tmp_path / "out.png"
    out.write_bytes(b"mine")
    assert main(["suggest", str(photo_file), "--out", str(out)]) == 2
    assert "exists" in capsys.readouterr().err
    assert out.read_bytes() == b"mine"
    assert main(["suggest", str(photo_file), "--out", str(out), "--force"]) == 0
    assert out.read_bytes() != b"mine"


def write_bomb(path):
    # a tiny PNG that claims a huge size: refused before decoding
    from PIL import Image

    Image.new("L", (12000, 12000)).save(path, optimize=True)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda p: p.write_text("not an image"), "not an image"),
        (lambda p: p.write_bytes(b""), "not an image"),
        (lambda p: p.write_bytes(cv2.imencode(".png", np.zeros((300, 300, 3), np.uint8))[1].tobytes()[:200]), "trunc"),
        (write_bomb, "too large"),
    ],
)
def test_bad_images_fail_cleanly(tmp_path, standins, capsys, make, match):
    img = tmp_path / "bad.png"
    make(img)
    out, js = tmp_path / "o.png", tmp_path / "o.json"
    assert main(["suggest", str(img), "--out", str(out), "--json", str(js)]) == 2
    err = capsys.readouterr().err
    assert match in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not out.exists() and not js.exists()


@pytest.mark.parametrize(
    ("detector_kwargs", "match"),
    [({"drop": (0,)}, "no cue ball"), ({"diamonds": False}, "too few table points")],
)
def test_pipeline_errors_fail_cleanly(tmp_path, monkeypatch, photo_file, capsys, detector_kwargs, match):
    det = LabelDetector(camera("45"), example_layout(), **detector_kwargs)
    monkeypatch.setattr(photo, "default_detector", lambda: det)
    out = tmp_path / "o.png"
    assert main(["suggest", str(photo_file), "--out", str(out)]) == 2
    assert match in capsys.readouterr().err
    assert not out.exists()


def test_ball_in_hand_places_a_missing_cue_ball(tmp_path, monkeypatch, photo_file, capsys):
    det = LabelDetector(camera("45"), example_layout(), drop=(0,))
    monkeypatch.setattr(photo, "default_detector", lambda: det)
    assert main(["suggest", str(photo_file), "--json", "-"]) == 2
    assert "ask for ball in hand" in capsys.readouterr().err
    assert main(["suggest", str(photo_file), "--ball-in-hand", "table", "--json", "-"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["ball_in_hand"] == "table" and doc["balls"][-1]["class"] == "cue" and doc["balls"][-1]["in_hand"]
    with pytest.raises(SystemExit) as exc:
        main(["suggest", str(photo_file), "--ball-in-hand", "pocket"])
    assert exc.value.code == 2 and "invalid choice: 'pocket'" in capsys.readouterr().err


def test_bad_output_paths(tmp_path, photo_file, capsys):
    assert main(["suggest", str(photo_file), "--out", str(tmp_path / "x.txt")]) == 2
    assert main(["suggest", str(photo_file), "--out", str(tmp_path / "missing" / "x.png")]) == 2
    assert main(["suggest", str(tmp_path / "nope.png")]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 3


def test_without_image_uses_the_bundled_example(tmp_path, standins, capsys):
    js = tmp_path / "o.json"
    assert main(["suggest", "--json", str(js)]) == 0
    doc = json.loads(js.read_text())
    assert doc["image"]["path"].endswith("table_example.jpg")
    assert doc["image"]["width"] == 1280


def test_agent_planner_file_errors(tmp_path, photo_file, capsys):
    out = tmp_path / "out.png"
    assert main(["suggest", str(photo_file), "--agent", str(tmp_path / "missing.zip"), "--out", str(out)]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert not out.exists()


def test_agent_planner_plans_the_shot(tmp_path, photo_file, capsys):
    pytest.importorskip("stable_baselines3")
    from pix2pockets.rl.agent import load_agent

    agents = resources.files("pix2pockets.data.agents")
    bundled = sorted(p for p in agents.iterdir() if p.name.endswith(".zip"))
    if not bundled:
        pytest.skip("no bundled agent in this build")
    load_agent(str(bundled[0]))  # loads without error
    assert main(["suggest", str(photo_file), "--agent", str(bundled[0]), "--json", "-"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["suggestion"]["power_level"] in range(1, 31)


def test_bad_time_budget(tmp_path, photo_file, capsys):
    assert main(["suggest", str(photo_file), "--time-budget", "-1"]) == 2
    assert "--time-budget" in capsys.readouterr().err


def test_outputs_get_normal_permissions(tmp_path, photo_file):
    import os
    import stat

    out = tmp_path / "out.png"
    assert main(["suggest", str(photo_file), "--out", str(out)]) == 0
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(out.stat().st_mode) == 0o666 & ~mask


def test_a_blackball_set_names_its_balls_and_groups(photo_file, capsys):
    assert main(["suggest", str(photo_file), "--set", "blackball", "--group", "reds", "--json", "-"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["ball_set"] == "blackball" and doc["suggestion"]["group"] == "reds"
    assert {b["class"] for b in doc["balls"]} <= {"cue", "black", "red", "yellow"}
    assert "red" in {b["class"] for b in doc["balls"]}


def test_a_group_of_another_set_is_one_line(photo_file, capsys):
    assert main(["suggest", str(photo_file), "--set", "blackball", "--group", "solids"]) == 2
    err = capsys.readouterr().err
    assert "unknown group 'solids' for the blackball set; choose auto, reds, yellows" in err
    assert len(err.strip().splitlines()) == 1

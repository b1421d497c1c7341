import pytest

from pix2pockets.cli import serve_cmd
from pix2pockets.cli.main import main
from pix2pockets.pipeline import photo, planning
from pix2pockets.testing import NearestPocketPlanner


def test_help(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["serve", "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert "--host" in out and "--port" in out


def test_missing_web_extra_is_one_clear_line(monkeypatch, capsys):
    monkeypatch.setattr(serve_cmd.importlib.util, "find_spec", lambda name: None)
    assert main(["serve"]) == 2
    err = capsys.readouterr().err
    assert "fastapi, uvicorn, python-multipart" in err and "pix2pockets[web]" in err
    assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize(("args", "match"), [(["--port", "70000"], "--port"), (["--max-upload-mb", "0"], "positive")])
def test_bad_options(args, match, capsys):
    assert main(["serve", *args]) == 2
    assert match in capsys.readouterr().err


def test_missing_model_fails_before_serving(monkeypatch, capsys):
    uvicorn = pytest.importorskip("uvicorn")

    def no_model():
        raise ValueError("detector model not found: detector.onnx")

    monkeypatch.setattr(photo, "default_detector", no_model)
    monkeypatch.setattr(uvicorn, "run", lambda *a, **k: pytest.fail("served without a model"))
    assert main(["serve"]) == 2
    assert "detector model not found" in capsys.readouterr().err


def test_serves_the_app(monkeypatch, capsys):
    uvicorn = pytest.importorskip("uvicorn")
    pytest.importorskip("fastapi")
    calls = []
    monkeypatch.setattr(photo, "default_detector", lambda: object())
    monkeypatch.setattr(planning, "default_planner", lambda: NearestPocketPlanner())
    monkeypatch.setattr(uvicorn, "run", lambda app, **kw: calls.append((app, kw)))
    assert main(["serve", "--port", "8123", "--max-upload-mb", "2"]) == 0
    ((app, kw),) = calls
    assert kw["host"] == "127.0.0.1" and kw["port"] == 8123
    assert "http://127.0.0.1:8123/" in capsys.readouterr().out
    from fastapi.testclient import TestClient

    assert TestClient(app).get("/api/health").json()["max_upload_bytes"] == 2_000_000

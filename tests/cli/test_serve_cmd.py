import json
import os
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

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
    for option in ("--host", "--port", "--workers", "--queue", "--max-wait", "--job-timeout"):
        assert option in out


def test_missing_web_extra_is_one_clear_line(monkeypatch, capsys):
    monkeypatch.setattr(serve_cmd.importlib.util, "find_spec", lambda name: None)
    assert main(["serve"]) == 2
    err = capsys.readouterr().err
    assert "fastapi, uvicorn, python-multipart" in err and "pix2pockets[web]" in err
    assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["--port", "70000"], "--port"),
        (["--max-upload-mb", "0"], "positive"),
        (["--workers", "-1"], "--workers must be 0 or more"),
        (["--queue", "-2"], "--queue must be 0 or more"),
        (["--job-timeout", "0"], "--job-timeout must be positive"),
        (["--max-wait", "-1"], "--max-wait must be 0 or more"),
    ],
)
def test_bad_options(args, match, capsys):
    assert main(["serve", *args]) == 2
    err = capsys.readouterr().err
    assert match in err and len(err.strip().splitlines()) == 1


def test_unparsable_option_is_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["serve", "--workers", "many"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("pix2pockets serve: error: argument --workers: invalid int value: 'many'")
    assert len(err.strip().splitlines()) == 1


def test_missing_model_fails_before_serving(monkeypatch, capsys):
    uvicorn = pytest.importorskip("uvicorn")

    def no_model():
        raise ValueError("detector model not found: detector.onnx")

    monkeypatch.setattr(photo, "default_detector", no_model)
    monkeypatch.setattr(uvicorn.Server, "run", lambda *a, **k: pytest.fail("served without a model"))
    assert main(["serve", "--workers", "0"]) == 2
    err = capsys.readouterr().err
    assert "no detector available: detector model not found" in err and len(err.strip().splitlines()) == 1


def test_a_worker_process_without_its_model_fails_before_serving(monkeypatch, capsys, tmp_path):
    uvicorn = pytest.importorskip("uvicorn")
    monkeypatch.setattr(uvicorn.Server, "run", lambda *a, **k: pytest.fail("served without a model"))
    assert main(["serve", "--workers", "1", "--model", str(tmp_path / "missing.onnx")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("pix2pockets serve: error: no detector available:") and "missing.onnx" in err
    assert len(err.strip().splitlines()) == 1


def test_serves_the_app(monkeypatch, capsys):
    uvicorn = pytest.importorskip("uvicorn")
    pytest.importorskip("fastapi")
    calls = []
    monkeypatch.setattr(photo, "default_detector", lambda: object())
    monkeypatch.setattr(planning, "default_planner", lambda: NearestPocketPlanner())
    monkeypatch.setattr(uvicorn.Server, "run", lambda self, **kw: calls.append(self.config))
    assert main(["serve", "--port", "8123", "--max-upload-mb", "2", "--workers", "0", "--queue", "5"]) == 0
    (config,) = calls
    assert config.host == "127.0.0.1" and config.port == 8123
    assert "http://127.0.0.1:8123/" in capsys.readouterr().out
    from fastapi.testclient import TestClient

    health = TestClient(config.app).get("/api/health").json()
    assert health["max_upload_bytes"] == 2_000_000 and health["queue"] == 5 and health["workers"] == 1


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_serve_end_to_end_and_stop_on_ctrl_c(tmp_path):
    """The real command with one worker process and the bundled models: warm-up, an upload, Ctrl+C."""
    pytest.importorskip("uvicorn")
    from pix2pockets.data.examples import example_photo_path
    from pix2pockets.vision.detect.onnx_detector import default_model_path

    if not default_model_path().is_file():
        pytest.skip("no bundled detector model in this build")
    port = _free_port()
    log = tmp_path / "serve.log"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(serve_cmd.__file__).parents[2]), *sys.path])}
    cmd = [sys.executable, "-m", "pix2pockets.cli.main", "serve", "--port", str(port), "--workers", "1"]
    with log.open("w") as out:
        server = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, env=env)
    try:
        base = f"http://127.0.0.1:{port}"
        end = time.monotonic() + 240
        while True:
            assert server.poll() is None, log.read_text()
            try:
                health = json.load(urllib.request.urlopen(f"{base}/api/health", timeout=5))
                break
            except OSError:
                assert time.monotonic() < end, log.read_text()
                time.sleep(0.25)
        assert health["workers"] == 1 and health["status"] == "ok"
        photo_bytes = Path(example_photo_path()).read_bytes()
        boundary = "p2pboundary"
        body = (
            (
                f'--{boundary}\r\nContent-Disposition: form-data; name="file"; filename="table.jpg"\r\n'
                f"Content-Type: image/jpeg\r\n\r\n"
            ).encode()
            + photo_bytes
            + f"\r\n--{boundary}--\r\n".encode()
        )
        request = urllib.request.Request(
            f"{base}/api/suggest", data=body, headers={"Content-Type": f"multipart/form-data; boundary={boundary}"}
        )
        t = time.perf_counter()
        doc = json.load(urllib.request.urlopen(request, timeout=120))
        assert "pocket" in doc["text"] and doc["picture_png_base64"], doc.get("error")
        assert time.perf_counter() - t < 30  # warmed up: no compile on the first upload
        server.send_signal(signal.SIGINT)
        assert server.wait(60) == 0, log.read_text()
    finally:
        if server.poll() is None:
            server.kill()
            server.wait()
    text = log.read_text()
    assert "ready in" in text and "Traceback" not in text

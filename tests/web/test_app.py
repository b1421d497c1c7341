import base64
import io
import json
import time

import anyio
import numpy as np
import pytest
from PIL import Image

pytest.importorskip("fastapi")
pytest.importorskip("python_multipart")
from fastapi.testclient import TestClient

from pix2pockets.pipeline import photo
from pix2pockets.testing import LabelsDetector, NearestPocketPlanner
from pix2pockets.vision.image_io import decode_image_rgb
from pix2pockets.web import app as web_app
from pix2pockets.web.app import create_app
from pix2pockets.web.jobs import STAGES
from tests.web.standins import GatedDetector


def client_for(labels, drop=(), **kwargs) -> TestClient:
    return TestClient(create_app(LabelsDetector(labels, drop), NearestPocketPlanner(), **kwargs))


def png_bytes(shape=(120, 160, 3)) -> bytes:
    buf = io.BytesIO()
    Image.fromarray(np.full(shape, 90, np.uint8)).save(buf, format="PNG")
    return buf.getvalue()


def post(client, data: bytes, group="auto", name="table.png"):
    return client.post("/api/suggest", files={"file": (name, data, "image/png")}, data={"group": group})


def test_page_is_self_contained(rendered):
    r = client_for(rendered[1]).get("/")
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    html = r.text
    for needle in ('type="file"', 'value="solids"', 'value="stripes"', 'value="auto"', "api/jobs", "api/example"):
        assert needle in html
    # nothing is fetched from elsewhere: no external scripts, styles, fonts or images
    assert "http://" not in html and "https://" not in html and "<script src" not in html and "<link" not in html
    assert "{{" not in html
    assert 'capture="environment"' in html and "@media (max-width: 700px)" in html  # phones: camera, stacked panels
    assert "default-src 'none'" in r.headers["content-security-policy"]


def test_health(rendered):
    doc = client_for(rendered[1], max_upload_bytes=12345, queue=3).get("/api/health").json()
    assert doc["status"] == "ok" and doc["max_upload_bytes"] == 12345
    assert doc["groups"] == ["auto", "solids", "stripes", "reds", "yellows"] == list(web_app.GROUPS)
    assert doc["ball_sets"] == ["auto", "american", "blackball"]
    assert doc["workers"] == 1 and doc["queue"] == 3 and doc["running"] == doc["queued"] == 0


def test_favicon(rendered):
    r = client_for(rendered[1]).get("/favicon.ico")
    assert r.status_code == 200 and r.headers["content-type"] == "image/x-icon"
    assert Image.open(io.BytesIO(r.content)).size == (32, 32)


@pytest.mark.parametrize("group", ["auto", "stripes", "solids"])
def test_good_photo_gives_issue_8_json_and_picture(rendered, group):
    data, labels = rendered
    r = post(client_for(labels), data, group, name="table.jpg")
    assert r.status_code == 200, r.text
    doc = r.json()
    width, height = labels["image_size"]
    assert doc["image"] == {"width": width, "height": height, "filename": "table.jpg"}
    assert len(doc["table"]["corners_px"]) == 4 and np.array(doc["table"]["homography"]).shape == (3, 3)
    truth = np.array([b["centre_table_m"][:2] for b in labels["balls"] if b["labelled"]])
    assert len(truth) - 2 <= len(doc["balls"]) <= len(truth)  # balls frozen on a cushion may be dropped
    assert {"class", "confidence", "bbox_px", "contact_px", "table_xy_m"} <= set(doc["balls"][0])
    s = doc["suggestion"]
    assert set(s) >= {"target_ball", "pocket", "kind", "cue_angle_deg", "speed_mps", "power_level"}
    assert "success_probability" in s and 1 <= s["power_level"] <= 30
    if group != "auto":
        assert s["group"] == group and doc["balls"][s["target_ball"]]["class"] in (group[:-1], "black")
    assert "pocket" in doc["text"] and set(doc["timings_s"]) >= {"detect", "plan", "total"}
    # the balls are where the renderer put them (table frame [m]; a photo cannot tell the table's two ends
    # apart, so the located frame may be the true one turned by 180 degrees)
    got = np.array([b["table_xy_m"] for b in doc["balls"]])
    size = np.array([labels["table"]["length_m"], labels["table"]["width_m"]])
    err = min(np.linalg.norm(got[:, None] - t[None], axis=2).min(axis=1).max() for t in (truth, size - truth))
    assert err < 0.02
    picture = Image.open(io.BytesIO(base64.b64decode(doc["picture_png_base64"])))
    assert picture.format == "PNG" and picture.width > width


def test_same_answer_as_the_python_api(rendered):
    data, labels = rendered
    doc = post(client_for(labels), data, "solids").json()
    rgb = photo.load_image(decode_image_rgb(data))
    want = photo.suggest(rgb, "solids", LabelsDetector(labels), NearestPocketPlanner()).to_dict()
    doc["image"].pop("filename")
    assert {k: doc[k] for k in want} == json.loads(json.dumps(want))


def write_bomb() -> bytes:
    # a small PNG that claims 144 megapixels: refused before decoding
    buf = io.BytesIO()
    Image.new("L", (12000, 12000)).save(buf, format="PNG", optimize=True)
    return buf.getvalue()


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: b"", "table.png is empty"),
        (lambda: b"this is not an image", "not an image file: table.png"),
        (lambda: png_bytes()[:100], "truncated or corrupt"),
        (lambda: png_bytes((32, 32, 3)), "too small"),
        (write_bomb, "too large (144000000 pixels; the limit is 64000000 pixels)"),
    ],
)
def test_bad_images_are_400(rendered, make, match):
    r = post(client_for(rendered[1]), make())
    assert r.status_code == 400
    assert match in r.json()["error"] and "\n" not in r.json()["error"]


@pytest.mark.parametrize(
    ("drop", "group", "match"),
    [
        (("cue",), "auto", "no cue ball"),
        (("solid", "black"), "solids", "no solids"),
        (("solid", "stripe", "black"), "auto", "no object balls"),
    ],
)
def test_photos_without_what_is_needed_are_422(rendered, drop, group, match):
    data, labels = rendered
    r = post(client_for(labels, drop), data, group)
    assert r.status_code == 422 and match in r.json()["error"]


def test_a_photo_without_a_table_is_422(rendered):
    r = post(client_for(rendered[1], ("dot",)), png_bytes((360, 640, 3)))
    assert r.status_code == 422 and "no table found" in r.json()["error"]


def test_a_table_whose_diamonds_are_not_seen_is_found_from_its_surface(rendered):
    data, labels = rendered
    if not photo.TableModel.default_path().is_file():
        pytest.skip("no table model committed")
    r = post(client_for(labels, ("dot",)), data)
    assert r.status_code == 200
    assert r.json()["table"]["source"] == "surface" and r.json()["table"]["size_source"] == "balls"


@pytest.mark.parametrize("group", ["", "spots", "SOLIDS and more", "x" * 500])
def test_bad_group_is_400(rendered, group):
    r = post(client_for(rendered[1]), png_bytes(), group)
    assert r.status_code == 400 and "choose auto, solids, stripes" in r.json()["error"]


def test_missing_file_is_400(rendered):
    c = client_for(rendered[1])
    for r in (
        c.post("/api/suggest", data={"group": "auto"}),
        c.post("/api/suggest", content=b"{}", headers={"content-type": "application/json"}),
        c.post("/api/suggest", data={"group": "auto", "file": "not a file"}),
    ):
        assert r.status_code == 400 and "no photo uploaded" in r.json()["error"]


def test_malformed_multipart_is_400(rendered):
    body = b"--xyz\r\nContent-Disposition: form-data\r\n\r\nbroken"
    r = client_for(rendered[1]).post(
        "/api/suggest", content=body, headers={"content-type": "multipart/form-data; boundary=xyz"}
    )
    assert r.status_code == 400 and r.json()["error"]


def test_upload_limit_by_declared_length(rendered):
    r = post(client_for(rendered[1], max_upload_bytes=5000), b"\0" * 6000)
    assert r.status_code == 413 and "too large" in r.json()["error"]


def test_upload_limit_enforced_while_reading(rendered):
    """A chunked body (no Content-Length) is refused once it passes the limit, without reading the rest."""
    app = create_app(LabelsDetector(rendered[1]), NearestPocketPlanner(), max_upload_bytes=5000)
    head = b'--xyz\r\nContent-Disposition: form-data; name="file"; filename="a.png"\r\n\r\n'
    chunks = [head] + [b"\0" * 1000] * 100
    received, sent = [], []

    async def receive():
        received.append(1)
        return {"type": "http.request", "body": chunks[len(received) - 1], "more_body": len(received) < len(chunks)}

    async def send(message):
        sent.append(message)

    scope = {
        "type": "http",
        "asgi": {"version": "3.0"},
        "http_version": "1.1",
        "method": "POST",
        "scheme": "http",
        "path": "/api/suggest",
        "raw_path": b"/api/suggest",
        "query_string": b"",
        "root_path": "",
        "headers": [(b"content-type", b"multipart/form-data; boundary=xyz"), (b"transfer-encoding", b"chunked")],
        "client": ("127.0.0.1", 1234),
        "server": ("127.0.0.1", 8000),
    }
    anyio.run(app, scope, receive, send)
    assert sent[0]["status"] == 413
    assert "too large" in json.loads(b"".join(m.get("body", b"") for m in sent[1:]))["error"]
    assert len(received) <= 7  # stopped right after the limit, not after 100 kB


def test_missing_model_is_503_and_bugs_are_500_without_traceback(rendered, monkeypatch):
    data = rendered[0]

    def no_model():
        raise ValueError("detector model not found")

    monkeypatch.setattr(photo, "default_detector", no_model)
    r = post(TestClient(create_app(planner=NearestPocketPlanner())), data)
    assert r.status_code == 503 and "detector model not found" in r.json()["error"]

    class Broken:
        def detect(self, image_rgb):
            raise RuntimeError("boom")

    r = post(TestClient(create_app(Broken(), NearestPocketPlanner())), data)
    assert r.status_code == 500 and r.json() == {"error": "internal error: RuntimeError: boom"}


def test_example_photo(rendered, tmp_path):
    data, labels = rendered
    c = client_for(labels, example_photo=tmp_path / "missing.png")
    r = c.get("/api/example")
    assert r.status_code == 404 and "missing" in r.json()["error"]
    assert c.get("/api/health").json()["example"] is False
    (tmp_path / "ex.png").write_bytes(data)
    r = client_for(labels, example_photo=tmp_path / "ex.png").get("/api/example")
    assert r.status_code == 200 and r.content == data
    c = client_for(labels)  # the bundled example
    assert c.get("/api/health").json()["example"] is True
    assert c.get("/api/example").content == data


def test_unknown_routes_and_methods_answer_json(rendered):
    c = client_for(rendered[1])
    r = c.get("/nope")
    assert r.status_code == 404 and r.json() == {"error": "Not Found"}
    r = c.get("/api/suggest")
    assert r.status_code == 405 and "error" in r.json()


def test_bad_limits():
    with pytest.raises(ValueError, match="positive"):
        create_app(max_upload_bytes=0)


def test_long_messages_are_one_short_line(rendered):
    class Chatty:
        def detect(self, image_rgb):
            raise RuntimeError("line one\nline two " + "x" * 2000)

    err = post(TestClient(create_app(Chatty(), NearestPocketPlanner())), rendered[0]).json()["error"]
    assert err.startswith("internal error: RuntimeError: line one line two") and len(err) <= 500


def test_unexpected_errors_outside_the_pipeline_answer_json(rendered, monkeypatch):
    def broken(upload):
        raise KeyError("oops")

    monkeypatch.setattr(web_app, "_upload_name", broken)
    r = post(TestClient(create_app(LabelsDetector(rendered[1])), raise_server_exceptions=False), rendered[0])
    assert r.status_code == 500 and r.json() == {"error": "internal error: KeyError"}


def test_bundled_model_and_planner_on_the_example(rendered):
    """The defaults end to end (skipped in builds without the detector model)."""
    from pix2pockets.vision.detect.onnx_detector import default_model_path

    if not default_model_path().is_file():
        pytest.skip("no bundled detector model in this build")
    doc = post(TestClient(create_app()), rendered[0], "auto", name="table.jpg").json()
    assert "error" not in doc, doc
    assert doc["suggestion"]["group"] in ("solids", "stripes") and len(doc["balls"]) >= 8
    assert doc["picture_png_base64"]


def follow(client, job: dict, timeout: float = 60.0) -> dict:
    """Poll ``GET /api/jobs/{id}?since=`` as the page does, until the job is over."""
    end = time.monotonic() + timeout
    while job["state"] in ("queued", "running"):
        assert time.monotonic() < end
        r = client.get(f"/api/jobs/{job['job']}", params={"since": job["version"]})
        assert r.status_code == 200, r.text
        job = r.json()
    return job


def test_jobs_api_gives_the_same_answer_as_suggest(rendered):
    data, labels = rendered
    c = client_for(labels)
    r = c.post("/api/jobs", files={"file": ("table.jpg", data, "image/jpeg")}, data={"group": "solids"})
    assert r.status_code == 202 and r.json()["state"] in ("queued", "running", "done")
    assert r.json()["url"] == f"api/jobs/{r.json()['job']}"
    job = follow(c, r.json())
    assert job["state"] == "done" and job["status"] == 200 and set(job["stages"]) == set(STAGES)
    direct = post(c, data, "solids", name="table.jpg").json()
    for doc in (job["result"], direct):
        doc.pop("timings_s")
    assert job["result"] == direct
    assert c.get(f"/api/jobs/{job['job']}").json()["state"] == "done"  # kept for a while


def test_jobs_api_failures_carry_status_and_message(rendered):
    data, labels = rendered
    c = client_for(labels, ("cue",))
    job = follow(c, c.post("/api/jobs", files={"file": ("t.jpg", data)}).json())
    assert job["state"] == "failed" and job["status"] == 422 and "no cue ball" in job["error"]
    r = c.post("/api/jobs", files={"file": ("notes.txt", b"hello")})
    assert r.status_code == 400 and r.json() == {"error": "not an image file: notes.txt"}  # refused at once
    r = c.get("/api/jobs/no-such-job")
    assert r.status_code == 404 and "no such job" in r.json()["error"]


def test_busy_server_refuses_at_once_with_retry_after_and_recovers(rendered, tmp_path):
    data, labels = rendered
    gate = tmp_path / "go"
    c = TestClient(create_app(GatedDetector(labels, gate), NearestPocketPlanner(), queue=1))
    first = c.post("/api/jobs", files={"file": ("a.jpg", data)}).json()
    second = c.post("/api/jobs", files={"file": ("b.jpg", data)}).json()
    assert second["state"] == "queued"
    t = time.perf_counter()
    r = post(c, data)
    assert time.perf_counter() - t < 1.0
    assert r.status_code == 503 and "busy" in r.json()["error"] and int(r.headers["retry-after"]) >= 1
    assert c.get(f"/api/jobs/{second['job']}").json()["ahead"] == 0
    assert c.get("/api/health").json()["refused"] == 1
    gate.touch()
    assert follow(c, first)["status"] == follow(c, second)["status"] == 200
    assert post(c, data).status_code == 200  # room again


def test_picture_parts_tile_the_picture(rendered):
    data, labels = rendered
    doc = post(client_for(labels), data).json()
    picture = np.asarray(Image.open(io.BytesIO(base64.b64decode(doc["picture_png_base64"]))).convert("RGB"))
    parts = doc["picture_parts"]
    (px, py, pw, ph), (dx, dy, dw, dh), (cx, cy, cw, chh) = parts["photo"], parts["diagram"], parts["caption"]
    assert (px, py, dy, cx) == (0, 0, 0, 0) and dx == pw and dh == ph and cy == ph
    assert abs(pw + dw - picture.shape[1]) <= 1 and abs(ph + chh - picture.shape[0]) <= 1 and cw == picture.shape[1]
    width, height = labels["image_size"]
    assert abs(pw / ph - width / height) < 0.01  # the photo keeps its shape
    photo_mean = decode_image_rgb(data).mean()
    assert abs(picture[:ph, :pw].mean() - photo_mean) < 10  # the photo (lines drawn on it), not the diagram


def sixteen_bit_grey(data: bytes) -> tuple[bytes, np.ndarray]:
    grey = np.asarray(Image.open(io.BytesIO(data)).convert("L")).astype(np.uint16) * 257
    buf = io.BytesIO()
    Image.fromarray(grey).save(buf, format="PNG")
    return buf.getvalue(), (grey // 257).astype(np.uint8)


def test_16_bit_greyscale_png_reads_as_the_photo(rendered):
    data, labels = rendered
    png16, grey8 = sixteen_bit_grey(data)
    assert Image.open(io.BytesIO(png16)).mode.startswith("I")
    rgb = decode_image_rgb(png16, "grey16.png")
    assert rgb.dtype == np.uint8 and rgb.shape == (*grey8.shape, 3)
    assert np.abs(rgb[:, :, 0].astype(int) - grey8).max() <= 1 and (rgb[:, :, 0] == rgb[:, :, 2]).all()
    r = post(client_for(labels), png16, name="grey16.png")
    assert r.status_code == 200, r.text


@pytest.mark.parametrize(
    ("mode", "values", "expect"),
    [
        ("I", np.array([[0, 65535]], np.int32), [0, 255]),
        ("I", np.array([[3, 200]], np.int32), [3, 200]),
        ("I", np.array([[-100, 100]], np.int32), [0, 255]),
        ("F", np.array([[0.0, 1.0]], np.float32), [0, 255]),
        ("F", np.array([[10.0, 20.0]], np.float32), [0, 255]),
    ],
)
def test_deep_images_are_scaled_not_clipped(mode, values, expect):
    buf = io.BytesIO()
    Image.fromarray(np.repeat(np.repeat(values, 40, axis=0), 40, axis=1), mode=mode).save(buf, format="TIFF")
    rgb = decode_image_rgb(buf.getvalue(), "deep.tif")
    assert [int(rgb[0, 0, 0]), int(rgb[0, -1, 0])] == expect


def test_an_iphone_heic_photo_gets_a_shot(rendered):
    pillow_heif = pytest.importorskip("pillow_heif")
    data, labels = rendered
    heic = io.BytesIO()
    pillow_heif.from_pillow(Image.open(io.BytesIO(data)).convert("RGB")).save(heic, quality=95)
    r = client_for(labels).post(
        "/api/suggest", files={"file": ("IMG_0042.HEIC", heic.getvalue(), "image/heic")}, data={"group": "auto"}
    )
    assert r.status_code == 200, r.text
    width, height = labels["image_size"]
    assert r.json()["image"] == {"width": width, "height": height, "filename": "IMG_0042.HEIC"}
    assert "suggestion" in r.json()

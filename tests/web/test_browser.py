"""The page in a real browser: headless Chromium driven by selenium (Debian's chromium and chromium-driver).

Skipped when selenium, chromium or chromedriver is missing, unless ``PIX2POCKETS_BROWSER_TESTS=require`` (set by
``.ci/run``, which installs them), where a missing browser fails. Screenshots are kept in
``build/test-artifacts/browser`` (or ``$PIX2POCKETS_TEST_ARTIFACTS/browser``).
"""

from __future__ import annotations

import base64
import os
import shutil
import socket
import threading
import time
from pathlib import Path

import pytest

pytest.importorskip("fastapi")
pytest.importorskip("python_multipart")
uvicorn = pytest.importorskip("uvicorn")

from pix2pockets.testing import LabelsDetector, NearestPocketPlanner  # noqa: E402
from pix2pockets.web.app import create_app  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
DESKTOP = (1280, 900)
PHONE = (390, 844)  # CSS pixels of a common phone


def _missing(what: str) -> None:
    if os.environ.get("PIX2POCKETS_BROWSER_TESTS") == "require":
        pytest.fail(f"browser tests are required here but {what} is missing")
    pytest.skip(f"{what} is missing (apt-get install chromium chromium-driver; pip install selenium)")


@pytest.fixture(scope="module")
def artifacts() -> Path:
    root = Path(os.environ.get("PIX2POCKETS_TEST_ARTIFACTS") or REPO / "build" / "test-artifacts")
    out = root / "browser"
    out.mkdir(parents=True, exist_ok=True)
    return out


@pytest.fixture(scope="module")
def server(rendered):
    """The app on a free port of 127.0.0.1 (stand-in detector and planner), served by uvicorn in a thread."""
    yield from _serve(create_app(LabelsDetector(rendered[1]), NearestPocketPlanner()))


@pytest.fixture(scope="module")
def server_without_cue(rendered):
    """As :func:`server`, with a detector that does not see the cue ball."""
    yield from _serve(create_app(LabelsDetector(rendered[1], ("cue",)), NearestPocketPlanner()))


def _serve(app):
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    config = uvicorn.Config(app, log_level="warning", lifespan="on")
    srv = uvicorn.Server(config)
    thread = threading.Thread(target=srv.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    end = time.monotonic() + 30
    while not srv.started:
        assert time.monotonic() < end, "server did not start"
        time.sleep(0.05)
    yield f"http://127.0.0.1:{sock.getsockname()[1]}/"
    srv.should_exit = True
    thread.join(10)
    sock.close()


def _browser(size: tuple[int, int], phone: bool):
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        _missing("selenium")
    binary = shutil.which("chromium") or shutil.which("chromium-browser")
    driver = shutil.which("chromedriver")
    if not binary:
        _missing("chromium")
    if not driver:
        _missing("chromedriver")
    options = webdriver.ChromeOptions()
    options.binary_location = binary
    for flag in (
        "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--disable-quic",
        "--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--disable-extensions", "--hide-scrollbars", f"--window-size={size[0]},{size[1]}",
    ):  # fmt: skip
        options.add_argument(flag)
    if phone:
        options.add_experimental_option(
            "mobileEmulation", {"deviceMetrics": {"width": size[0], "height": size[1], "pixelRatio": 2, "touch": True}}
        )
    return webdriver.Chrome(options=options, service=Service(executable_path=driver))


@pytest.fixture(params=["desktop", "phone"])
def page(request, server):
    phone = request.param == "phone"
    browser = _browser(PHONE if phone else DESKTOP, phone)
    browser.get(server)
    yield browser, request.param
    browser.quit()


def _wait(browser, condition, timeout: float = 60.0):
    from selenium.webdriver.support.ui import WebDriverWait

    return WebDriverWait(browser, timeout, poll_frequency=0.1).until(condition)


def _rect(browser, css: str) -> dict:
    return browser.execute_script(
        "const r = document.querySelector(arguments[0]).getBoundingClientRect();"
        "return {left: r.left, top: r.top, width: r.width, height: r.height, bottom: r.bottom, right: r.right};",
        css,
    )


def _screenshot(browser, path: Path) -> None:
    """The whole page, below the fold too (DevTools ``Page.captureScreenshot``)."""
    size = browser.execute_script(
        "const e = document.documentElement; return {width: e.scrollWidth, height: e.scrollHeight};"
    )
    shot = browser.execute_cdp_cmd(
        "Page.captureScreenshot",
        {"format": "png", "captureBeyondViewport": True, "clip": {"x": 0, "y": 0, "scale": 1, **size}},
    )
    path.write_bytes(base64.b64decode(shot["data"]))


def test_example_photo_gives_the_suggestion_and_the_picture(page, artifacts):
    browser, kind = page
    from selenium.webdriver.common.by import By

    browser.find_element(By.ID, "example").click()
    _wait(browser, lambda b: b.execute_script("return document.body.dataset.shown"))
    answer = browser.find_element(By.ID, "answer").text
    assert "pocket" in answer and "power" in answer
    assert browser.find_element(By.ID, "status").text.startswith("Done in")
    stages = [li.get_attribute("class") for li in browser.find_elements(By.CSS_SELECTOR, "#stages li")]
    assert stages == ["done"] * 5
    photo, diagram = _rect(browser, "#photo-panel"), _rect(browser, "#diagram-panel")
    view = browser.execute_script("return document.documentElement.clientWidth")
    assert photo["height"] > 100 and diagram["height"] > 100
    if kind == "desktop":  # side by side, as tall as each other
        assert abs(photo["top"] - diagram["top"]) < 2 and photo["right"] <= diagram["left"] + 1
        assert abs(photo["height"] - diagram["height"]) < 3
    else:  # stacked, each filling the width
        assert diagram["top"] >= photo["bottom"] - 1
        assert photo["width"] > 0.9 * view - 40 and diagram["width"] > 0.9 * view - 40
        # every control on one line of its own
        for css in ("fieldset", "#go", "#example", "#camera-button"):
            assert _rect(browser, css)["height"] < 50, css
        assert browser.find_element(By.ID, "camera-button").is_displayed()
    assert browser.execute_script("return document.documentElement.scrollWidth") <= view + 1  # no sideways scroll
    _screenshot(browser, artifacts / f"example-{kind}.png")


def test_a_bad_file_shows_its_error(page, artifacts, tmp_path):
    browser, kind = page
    from selenium.webdriver.common.by import By

    bad = tmp_path / "notes.txt"
    bad.write_text("not a photo")
    browser.find_element(By.ID, "file").send_keys(str(bad))
    browser.find_element(By.ID, "go").click()
    status = _wait(browser, lambda b: b.find_element(By.CSS_SELECTOR, "#status.bad"), 30)
    assert status.text == "Not an image file: notes.txt"
    assert not browser.find_element(By.ID, "result").is_displayed()
    assert all(b.is_enabled() for b in browser.find_elements(By.TAG_NAME, "button"))
    _screenshot(browser, artifacts / f"bad-file-{kind}.png")


def test_a_photo_without_a_cue_ball_offers_ball_in_hand(server_without_cue, artifacts):
    from selenium.webdriver.common.by import By

    browser = _browser(DESKTOP, False)
    try:
        browser.get(server_without_cue)
        retry = browser.find_element(By.ID, "in-hand-retry")
        assert not retry.is_displayed()
        browser.find_element(By.ID, "example").click()
        status = _wait(browser, lambda b: b.find_element(By.CSS_SELECTOR, "#status.bad"), 60)
        assert "ask for ball in hand" in status.text and retry.is_displayed()
        retry.click()
        _wait(browser, lambda b: b.execute_script("return document.body.dataset.shown"))
        assert browser.find_element(By.ID, "answer").text.startswith("Ball in hand: cue ball at")
        assert browser.find_element(By.ID, "in-hand").get_attribute("value") == "table"
        assert not retry.is_displayed()
        _screenshot(browser, artifacts / "ball-in-hand-desktop.png")
    finally:
        browser.quit()

"""Teleoperation end to end in headless Chromium: keys pressed in the page move the knife in the
simulator (read back with Observe, not through the page), recording saves a demonstration file that
holds the path and the rating given in the page, and a second page watches the session read only."""
from __future__ import annotations

import json
import time

import numpy as np
import pytest
from culinarycut import Client
from culinarycut.datasets.demo import load_demonstration

from teleop_support import start_teleop


@pytest.fixture
def teleop(address, tmp_path):
    app = start_teleop(address, tmp_path / "demos")
    yield {"url": app.url, "page": app.page, "session": app.session, "demos": app.demos}
    app.stop()


@pytest.fixture
def browser():
    from selenium import webdriver
    options = webdriver.ChromeOptions()
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"):
        options.add_argument(flag)
    driver = webdriver.Chrome(options=options)
    yield driver
    driver.quit()


def _tcp(client: Client, session: str) -> np.ndarray:
    return np.asarray(client.observe(session).observation.tcp_pose[:3])


def _wait(condition, timeout_s: float, what: str):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(0.1)
    pytest.fail(f"timed out waiting for {what}")


def test_keys_in_the_page_move_the_knife_and_record_a_demonstration(teleop, browser, address):
    from selenium.webdriver.common.action_chains import ActionChains
    client = Client(address, timeout_s=60)
    start = _tcp(client, teleop["session"])
    browser.get(teleop["page"])  # the printed URL: its token becomes the cookie
    _wait(lambda: browser.execute_script(
        "const i = document.getElementById('camera-front'); return i && i.complete && i.naturalWidth;"),
        30, "the front camera image")
    assert browser.execute_script("return document.getElementById('camera-front').naturalWidth") == 64
    _wait(lambda: browser.find_element("id", "force").text not in ("", "-"), 10, "the force readout")

    browser.find_element("id", "record").click()
    _wait(lambda: browser.find_element("id", "status").text == "recording", 10, "recording to start")
    body = browser.find_element("tag name", "body")
    ActionChains(browser).move_to_element(body).key_down("q").pause(1.5).key_up("q").perform()  # up
    ActionChains(browser).key_down("a").pause(1.0).key_up("a").perform()                      # +y, robot's left
    _wait(lambda: int(browser.find_element("id", "steps").text) >= 10, 20, "steps from the keys")
    time.sleep(0.5)
    moved = _tcp(client, teleop["session"]) - start
    assert moved[2] > 0.02, f"Q should raise the knife: moved {moved} m"
    assert moved[1] > 0.01, f"A should move it to +y: moved {moved} m"

    browser.find_element("id", "record").click()
    _wait(lambda: browser.find_element("id", "status").text.startswith("saved demo_"), 20, "the saved file")
    browser.find_element("id", "good").click()
    _wait(lambda: "marked good" in browser.find_element("id", "status").text, 10, "the rating")

    files = sorted(teleop["demos"].glob("demo_*.json"))
    assert len(files) == 1
    demo = load_demonstration(files[0])
    assert demo.rating == "good" and demo.control_mode == "pd_ee_delta_pose"
    assert demo.spec["target_object"] == "cucumber" and demo.spec["ratio"] == pytest.approx(0.3)
    relative = np.asarray(demo.relative_pose)
    assert len(relative) >= 10 and relative[-1, 2] > relative[0, 2]  # higher above the object at the end
    assert json.loads(files[0].read_text())["resolved_scene"]["objects"][0]["food"] == "cucumber"

    # a read-only view of the same session: no controls, and keys there do not step it
    steps_before = int(browser.find_element("id", "steps").text)
    browser.get(teleop["url"] + f"/watch/{teleop['session']}")
    assert browser.find_element("tag name", "h1").text.startswith("Watching (read only)")
    assert not browser.find_element("id", "controls").is_displayed()
    frame = client.observe(teleop["session"]).stamp.frame_id
    ActionChains(browser).key_down("q").pause(0.5).key_up("q").perform()
    _wait(lambda: browser.find_element("id", "frame").text == str(frame), 10, "the watched frame id")
    assert client.observe(teleop["session"]).stamp.frame_id == frame
    assert frame >= steps_before
    client.close()


# A gamepad in the standard mapping, stubbed into the page: navigator.getGamepads answers this object.
GAMEPAD_STUB = """
window.stubPad = {axes: [0, 0, 0, 0], buttons: Array.from({length: 17}, () => ({pressed: false, value: 0}))};
Object.defineProperty(navigator, "getGamepads", {value: () => [window.stubPad], configurable: true});
"""
PAD_A, PAD_X, DPAD_UP = 0, 2, 12


def _pad(browser, axes=(0, 0, 0, 0), pressed=()):
    browser.execute_script("window.stubPad.axes = arguments[0]; window.stubPad.buttons.forEach((b, i) => {"
                           " b.pressed = arguments[1].includes(i); b.value = b.pressed ? 1 : 0; });",
                           list(axes), list(pressed))


def _status(browser) -> str:
    return browser.find_element("id", "status").text


def _rotation_rad(a, b) -> float:
    return 2.0 * float(np.arccos(min(1.0, abs(float(np.dot(a, b))))))


def test_gamepad_reset_and_a_recording_too_short_to_save(teleop, browser, address):
    from selenium.webdriver.common.action_chains import ActionChains
    client = Client(address, timeout_s=60)
    start = np.asarray(client.observe(teleop["session"]).observation.tcp_pose)
    browser.get(teleop["page"])  # the printed URL: its token becomes the cookie
    _wait(lambda: browser.find_element("id", "force").text not in ("", "-"), 30, "the force readout")
    browser.execute_script(GAMEPAD_STUB)

    # started and stopped without a step: one sample, which is no demonstration; nothing is saved
    browser.find_element("id", "record").click()
    _wait(lambda: _status(browser) == "recording", 10, "recording to start")
    browser.find_element("id", "record").click()
    _wait(lambda: "nothing saved" in _status(browser), 10, "the refusal")
    assert browser.find_element("id", "record").text == "Start recording"
    assert not list(teleop["demos"].glob("demo_*.json"))

    # the gamepad: A records, the left stick pushed forward drives +x and the D-pad pitches, X rates
    _pad(browser, pressed=[PAD_A])
    _wait(lambda: _status(browser) == "recording", 10, "A to start recording")
    _pad(browser, axes=(0, -1, 0, 0), pressed=[DPAD_UP])
    _wait(lambda: int(browser.find_element("id", "steps").text) >= 8, 20, "steps from the gamepad")
    _pad(browser)
    time.sleep(0.5)
    moved = np.asarray(client.observe(teleop["session"]).observation.tcp_pose)
    assert moved[0] - start[0] > 0.01, f"the stick should move the knife to +x: {moved[:3] - start[:3]} m"
    assert _rotation_rad(moved[3:], start[3:]) > 0.1, "the D-pad should pitch the knife"
    _pad(browser, pressed=[PAD_A])
    _wait(lambda: _status(browser).startswith("saved demo_"), 20, "A to stop and save")
    _pad(browser, pressed=[PAD_X])
    _wait(lambda: "marked good" in _status(browser), 10, "X to rate it good")
    _pad(browser)
    first = load_demonstration(sorted(teleop["demos"].glob("demo_*.json"))[0])
    assert first.rating == "good" and len(first.time_s) >= 8

    # R resets to the seed: the knife is back where it started, and the next recording starts there too
    ActionChains(browser).send_keys("r").perform()
    _wait(lambda: _status(browser) == "reset to the seed", 20, "the reset")
    np.testing.assert_allclose(client.observe(teleop["session"]).observation.tcp_pose, start, atol=1e-9)
    browser.find_element("id", "record").click()
    _wait(lambda: _status(browser) == "recording", 10, "the second recording")
    ActionChains(browser).key_down("q").pause(0.5).key_up("q").perform()
    _wait(lambda: int(browser.find_element("id", "steps").text) >= 3, 20, "steps after the reset")
    browser.find_element("id", "record").click()
    _wait(lambda: _status(browser).startswith("saved demo_"), 20, "the second file")
    files = sorted(teleop["demos"].glob("demo_*.json"))
    assert len(files) == 2
    second = load_demonstration(files[1])
    np.testing.assert_allclose(second.relative_pose[0], first.relative_pose[0], atol=1e-9)
    client.close()

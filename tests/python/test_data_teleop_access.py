"""Who can use the teleoperation app, with raw HTTP requests as another site's page, a DNS-rebinding page
or a script would send them: a foreign Origin, a foreign Host, a text/plain or form body, a missing or
wrong token, another session's id and malformed bodies are each refused with their status and a JSON
message, and none of them steps the robot or writes a demonstration."""
from __future__ import annotations

import contextlib
import http.client
import json

import pytest
from culinarycut import Client

from teleop_support import start_teleop

TOKEN_HEADER = "X-CulinaryCut-Token"
EVIL = "http://evil.example"
STEP = b'{"action": [0, 0, 1, 0, 0, 0]}'
# The requests a recording takes, in order: what a forged page would send to save a demonstration rated good.
RECORD_AND_RATE = [("/api/teleop/record", b'{"on": true}'), ("/api/teleop/step", STEP),
                   ("/api/teleop/step", STEP), ("/api/teleop/record", b'{"on": false}'),
                   ("/api/teleop/rate", b'{"rating": "good"}'), ("/api/teleop/reset", b"{}")]


@pytest.fixture(scope="module")
def app(address, tmp_path_factory):
    teleop = start_teleop(address, tmp_path_factory.mktemp("teleop") / "demos")
    yield teleop
    teleop.stop()


@pytest.fixture(scope="module")
def sim(address):
    with Client(address, timeout_s=60) as client:
        yield client


def send(app, method: str, path: str, body: bytes | None = None, **headers) -> tuple[int, dict, dict]:
    """(status, JSON reply or {}, reply headers); header names with _ for -."""
    connection = http.client.HTTPConnection("127.0.0.1", app.port, timeout=30)
    try:
        connection.request(method, path, body=body, headers={k.replace("_", "-"): v for k, v in headers.items()})
        reply = connection.getresponse()
        data = reply.read()
        with contextlib.suppress(ValueError):
            return reply.status, json.loads(data), dict(reply.getheaders())
        return reply.status, {}, dict(reply.getheaders())
    finally:
        connection.close()


def own(app) -> dict:
    """The headers the app's own page sends with a POST."""
    return {"Origin": app.url, "Content_Type": "application/json", TOKEN_HEADER.replace("-", "_"): app.token}


def robot(sim, app) -> tuple:
    observed = sim.observe(app.session)
    return observed.stamp.frame_id, observed.stamp.sim_time, tuple(observed.observation.tcp_pose)


def folder(app) -> dict:
    return {p.name: p.read_bytes() for p in app.demos.glob("*")} if app.demos.exists() else {}


@contextlib.contextmanager
def untouched(sim, app):
    """The block neither moves the robot nor changes the demonstration folder."""
    before_robot, before_files = robot(sim, app), folder(app)
    yield
    assert robot(sim, app) == before_robot, "a refused request stepped or reset the robot"
    assert folder(app) == before_files, "a refused request wrote a demonstration"


def refused(status: int, reply: dict, expected: int, what: str) -> None:
    assert status == expected, f"{what}: answered {status} {reply}, expected {expected}"
    assert reply.get("error"), f"{what}: the refusal has no JSON error message: {reply}"


def test_the_pages_own_requests_are_served(app, sim):
    status, _, headers = send(app, "GET", "/?token=" + app.token)
    assert status == 303 and headers["Location"] == "/"
    cookie = headers["Set-Cookie"]
    assert "HttpOnly" in cookie and "SameSite=Strict" in cookie, cookie
    status, _, _ = send(app, "GET", "/", Cookie=cookie.split(";")[0])
    assert status == 200
    status, view, _ = send(app, "GET", f"/api/sessions/{app.session}/view", Cookie=cookie.split(";")[0])
    assert status == 200 and "frame_id" in view
    frame = robot(sim, app)[0]
    status, state, _ = send(app, "POST", "/api/teleop/step", STEP, **own(app))
    assert status == 200 and state["steps"] >= 1, state
    assert robot(sim, app)[0] > frame


def test_a_foreign_origin_can_neither_drive_nor_record(app, sim):
    with untouched(sim, app):
        for path, body in RECORD_AND_RATE:  # the shape a cross-site form or no-cors fetch sends
            status, reply, _ = send(app, "POST", path, body, Origin=EVIL, Content_Type="text/plain")
            refused(status, reply, 403, f"{path} from {EVIL}")
        for path, body in RECORD_AND_RATE:  # even with the token, another origin is not this app's page
            status, reply, _ = send(app, "POST", path, body, **{**own(app), "Origin": EVIL})
            refused(status, reply, 403, f"{path} from {EVIL} with the token")
        status, reply, _ = send(app, "POST", "/api/teleop/step", STEP, **{**own(app), "Origin": "null"})
        refused(status, reply, 403, "a sandboxed page's null origin")


def test_a_rebinding_host_is_refused(app, sim):
    rebound = f"rebind.evil.example:{app.port}"
    with untouched(sim, app):
        for method, path, body in [("GET", "/", None), ("GET", f"/api/sessions/{app.session}/view", None),
                                   ("POST", "/api/teleop/step", STEP)]:
            status, reply, _ = send(app, method, path, body,
                                    **{**own(app), "Host": rebound, "Origin": f"http://{rebound}"})
            refused(status, reply, 403, f"{method} {path} with Host {rebound}")
            assert "DNS rebinding" in reply["error"]
        status, reply, _ = send(app, "POST", "/api/teleop/step", STEP, **{**own(app), "Host": "127.0.0.1:1"})
        refused(status, reply, 403, "another port in Host")


def multipart(body: bytes) -> bytes:
    """The JSON as a form field's name, as an HTML form posting to this app could send it."""
    return b'--x\r\nContent-Disposition: form-data; name="' + body + b'"\r\n\r\n\r\n--x--\r\n'


def test_text_and_form_bodies_are_refused(app, sim):
    with untouched(sim, app):
        for content_type, encode in [("text/plain", bytes), ("application/x-www-form-urlencoded", bytes),
                                     ("multipart/form-data; boundary=x", multipart)]:
            for path, body in RECORD_AND_RATE:
                status, reply, _ = send(app, "POST", path, encode(body),
                                        **{**own(app), "Content_Type": content_type})
                refused(status, reply, 415, f"{path} as {content_type}")
        headers = own(app)
        del headers["Content_Type"]
        status, reply, _ = send(app, "POST", "/api/teleop/step", STEP, **headers)
        refused(status, reply, 415, "a body without Content-Type")


def test_a_missing_or_wrong_token_is_refused(app, sim):
    wrong = {**own(app), TOKEN_HEADER.replace("-", "_"): "x" * len(app.token)}
    missing = {k: v for k, v in own(app).items() if k != TOKEN_HEADER.replace("-", "_")}
    cookie_only = {**missing, "Cookie": f"culinarycut_teleop_{app.port}={app.token}"}
    with untouched(sim, app):
        for name, headers in [("no token", missing), ("a wrong token", wrong),
                              ("the cookie without the header", cookie_only)]:
            for path, body in RECORD_AND_RATE:
                status, reply, _ = send(app, "POST", path, body, **headers)
                refused(status, reply, 403, f"{path} with {name}")
        for path in ("/", f"/watch/{app.session}", f"/api/sessions/{app.session}/view",
                     f"/api/sessions/{app.session}/front.jpg", "/?token=wrong"):
            status, reply, _ = send(app, "GET", path)
            refused(status, reply, 403, f"GET {path} without the token")
        status, reply, _ = send(app, "GET", "/", Cookie=f"culinarycut_teleop_{app.port}=wrong")
        refused(status, reply, 403, "GET / with a wrong cookie")


def test_only_the_apps_own_session_is_shown(app, sim):
    other = sim.create_session(None).session_id
    try:
        sim.reset(other, seed=0)
        frame = sim.observe(other).stamp.frame_id
        with untouched(sim, app):
            for path in (f"/watch/{other}", f"/api/sessions/{other}/view", f"/api/sessions/{other}/front.jpg"):
                status, reply, _ = send(app, "GET", path, **{TOKEN_HEADER.replace("-", "_"): app.token})
                refused(status, reply, 403, f"GET {path} (a session this app did not create)")
            status, _, _ = send(app, "GET", f"/watch/{app.session}", **{TOKEN_HEADER.replace("-", "_"): app.token})
            assert status == 200, "the app's own session is watchable"
        assert sim.observe(other).stamp.frame_id == frame
    finally:
        sim.close_session(other)


MALFORMED = [
    ("/api/teleop/step", b"[0, 0, 1, 0, 0, 0]", "must be a JSON object"),
    ("/api/teleop/step", b"{}", "missing field 'action'"),
    ("/api/teleop/step", b'{"action": "up"}', "'action' must be a list"),
    ("/api/teleop/step", b'{"action": {"z": 1}}', "'action' must be a list"),
    ("/api/teleop/step", b'{"action": [0, 0, 1]}', "has 3 value(s)"),
    ("/api/teleop/step", b'{"action": [0, 0, 1, 0, 0, 0, 0]}', "has 7 value(s)"),
    ("/api/teleop/step", b'{"action": [NaN, 0, 1, 0, 0, 0]}', "NaN"),
    ("/api/teleop/step", b'{"action": [0, 0, Infinity, 0, 0, 0]}', "Infinity"),
    ("/api/teleop/step", b'{"action": [0, 0, "1", 0, 0, 0]}', "'action'[2]"),
    ("/api/teleop/step", b'{"action": [0, 0, true, 0, 0, 0]}', "'action'[2]"),
    ("/api/teleop/step", b'{"action": [0, 0, 1, 0, 0, 0], "repeat": 100}', "unknown field(s) 'repeat'"),
    ("/api/teleop/step", b'{"action": [0, 0, 1,', "not JSON"),
    ("/api/teleop/step", b"\xff\xfe", "not JSON"),
    ("/api/teleop/record", b'{"on": "yes"}', "'on' must be true or false"),
    ("/api/teleop/record", b'{"on": 1}', "'on' must be true or false"),
    ("/api/teleop/record", b"{}", "missing field 'on'"),
    ("/api/teleop/rate", b'{"rating": "great"}', "'rating' must be one of"),
    ("/api/teleop/rate", b'{"rating": ["good"]}', "'rating' must be one of"),
    ("/api/teleop/rate", b"{}", "missing field 'rating'"),
    ("/api/teleop/reset", b'{"seed": 3}', "unknown field(s) 'seed'"),
    ("/api/teleop/reset", b"null", "must be a JSON object"),
]


def test_malformed_bodies_are_400_with_a_message_and_do_nothing(app, sim):
    wrong = []
    with untouched(sim, app):
        for path, body, message in MALFORMED:
            status, reply, _ = send(app, "POST", path, body, **own(app))
            if status != 400 or message not in reply.get("error", ""):
                wrong.append(f"{path} {body!r}: {status} {reply} (expected 400 saying {message!r})")
    assert not wrong, "\n".join(wrong)
    status, reply, _ = send(app, "POST", "/api/teleop/record", b'{"on": false}', **own(app))
    assert status == 409 and "not recording" in reply["error"], "a malformed body started a recording"


def test_the_names_served_follow_the_bind():
    from culinarycut.datasets.teleop.access import AccessPolicy, Refused
    loopback = AccessPolicy("127.0.0.1", 8008, "t")
    for host in ("127.0.0.1:8008", "localhost:8008", "LOCALHOST:8008", "[::1]:8008"):
        loopback.check_host(host)
    for host in ("127.0.0.1", "127.0.0.1:8009", "10.0.0.5:8008", "evil.example:8008", "", "[::1", "a:b:c"):
        with pytest.raises(Refused):
            loopback.check_host(host)
    one = AccessPolicy("10.0.0.5", 80, "t", extra_hosts=("sim.lab",))
    for host in ("10.0.0.5", "10.0.0.5:80", "sim.lab"):
        one.check_host(host)
    with pytest.raises(Refused):
        one.check_host("localhost")  # bound to 10.0.0.5 only: loopback does not reach it
    with pytest.raises(Refused, match="origin 'https://127.0.0.1:8008'"):
        loopback.check_origin("https://127.0.0.1:8008")
    loopback.check_origin("http://localhost:8008")

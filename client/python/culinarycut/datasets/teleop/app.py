"""The teleoperation web app (tornado), served next to the simulator.

    GET  /                                   the page: live view and, for its own session, the controls
    GET  /watch/<session>                    the page, read only, for this app's session
    GET  /api/sessions/<session>/view        JSON: frame, time, TCP position (m), wrist force (N), contact
    GET  /api/sessions/<session>/<camera>.jpg   the camera's last image
    POST /api/teleop/step      {"action": [6 values in -1..1]}    one pd_ee_delta_pose step
    POST /api/teleop/record    {"on": true|false}                 start / stop (stop saves the file)
    POST /api/teleop/rate      {"rating": "good"|"bad"}           rates the last saved demonstration
    POST /api/teleop/reset     {}                                 the scene back to its seed, recording off
The views read the server with Observe only, so watching never changes a session. Every request passes
access.py's checks (Host, Origin, the launch's token) and only this app's own session is shown; POSTs take
JSON bodies only (bodies.py): anything else is refused before it reaches the session.
"""
from __future__ import annotations

import asyncio
import json
from pathlib import Path

import numpy as np
import tornado.web

from culinarycut.client import Client, cameras_to_dict, food_to_dict
from culinarycut.datasets.teleop import bodies
from culinarycut.datasets.teleop.access import TOKEN_HEADER, TOKEN_QUERY, AccessPolicy, Refused
from culinarycut.datasets.teleop.session import TeleopSession
from culinarycut.errors import CulinaryCutError

PAGE = Path(__file__).with_name("page.html")
JPEG_QUALITY = 85


class _Base(tornado.web.RequestHandler):
    @property
    def client(self) -> Client:
        return self.application.settings["client"]

    @property
    def teleop(self) -> TeleopSession:
        return self.application.settings["teleop"]

    @property
    def access(self) -> AccessPolicy:
        return self.application.settings["access"]

    def set_default_headers(self):
        self.set_header("Referrer-Policy", "no-referrer")  # a page's first URL carries the token
        self.set_header("X-Frame-Options", "DENY")  # no other site frames the controls (clickjacking)
        self.set_header("Content-Security-Policy", "frame-ancestors 'none'")
        self.set_header("X-Content-Type-Options", "nosniff")
        self.set_header("Cache-Control", "no-store")

    def prepare(self):
        """Host, Origin and token before any handler runs; POSTs must be JSON."""
        try:
            self.access.check_host(self.request.headers.get("Host", ""))
            self.access.check_origin(self.request.headers.get("Origin"))
            self.authenticate()
            if self.request.method not in ("GET", "HEAD"):
                bodies.check_content_type(self.request.headers.get("Content-Type"))
        except Refused as err:
            raise tornado.web.HTTPError(err.status, "%s", err) from None
        except bodies.NotJson as err:
            raise tornado.web.HTTPError(415, "%s", err) from None

    def authenticate(self):
        self.access.check_token(self.request.headers.get(TOKEN_HEADER), self.get_cookie(self.access.cookie),
                                state_changing=self.request.method not in ("GET", "HEAD"))

    def own_session(self, session: str) -> str:
        """Only the session this app created is shown: the token opens this app, not the whole server."""
        if session != self.teleop.session_id:
            raise tornado.web.HTTPError(403, "session %s was not created by this teleoperation app", session)
        return session

    def parsed(self, read):
        try:
            return read(self.request.body)
        except bodies.BadBody as err:
            raise tornado.web.HTTPError(400, "%s", err) from None

    async def blocking(self, function, *args):
        return await asyncio.get_running_loop().run_in_executor(None, function, *args)

    def write_error(self, status_code, **kwargs):
        error = kwargs.get("exc_info", (None, None))[1]
        if isinstance(error, tornado.web.HTTPError) and error.log_message:
            message = error.log_message % error.args if error.args else error.log_message
        else:
            message = str(error) if error else self._reason
        self.finish({"error": message})


class PageHandler(_Base):
    def authenticate(self):
        """The printed URL's ?token= becomes the cookie, then the same path without it (out of the
        address bar and the history's last entry)."""
        given = self.get_query_argument(TOKEN_QUERY, None)
        if given is None:
            return super().authenticate()
        if not self.access.token_matches(given):
            raise Refused(403, "the URL's token is not this launch's: open the URL the command printed")
        self.set_cookie(self.access.cookie, given, httponly=True, samesite="Strict", path="/")
        self.redirect(self.request.path, status=303)

    def get(self, session: str | None = None):
        if session is not None:
            self.own_session(session)
        page = PAGE.read_text()
        config = {"session": session or self.teleop.session_id, "control": session is None,
                  "cameras": [c["name"] for c in self.teleop.resolved.get("cameras", [])],
                  "token": self.access.token, "token_header": TOKEN_HEADER}
        self.set_header("Content-Type", "text/html; charset=utf-8")
        # "</" escaped: no value can close the page's <script> early
        self.finish(page.replace("/*CONFIG*/null", json.dumps(config).replace("</", "<\\/")))


class ViewHandler(_Base):
    async def get(self, session: str):
        try:
            response = await self.blocking(self.client.observe, self.own_session(session))
        except CulinaryCutError as err:
            raise tornado.web.HTTPError(404 if err.code.name == "NOT_FOUND" else 502, err.details) from None
        obs = response.observation
        self.finish({"frame_id": response.stamp.frame_id, "sim_time_s": response.stamp.sim_time,
                     "tcp_position_m": list(obs.tcp_pose[:3]),
                     "force_n": float(np.linalg.norm(list(obs.wrist_wrench[:3]))) if obs.wrist_wrench else 0.0,
                     "knife_contact": food_to_dict(obs)["knife_contact"],
                     "cameras": [c.name for c in obs.cameras]})


class CameraHandler(_Base):
    async def get(self, session: str, camera: str):
        import cv2
        try:
            response = await self.blocking(self.client.observe, self.own_session(session))
        except CulinaryCutError as err:
            raise tornado.web.HTTPError(404, err.details) from None
        images, _ = cameras_to_dict(response.observation)
        if "rgb" not in images.get(camera, {}):
            raise tornado.web.HTTPError(404, f"no RGB camera {camera!r} in session {session}")
        ok, jpeg = cv2.imencode(".jpg", images[camera]["rgb"][:, :, ::-1], [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
        self.set_header("Content-Type", "image/jpeg")
        self.set_header("Cache-Control", "no-store")
        self.finish(jpeg.tobytes())


class StepHandler(_Base):
    async def post(self):
        action = self.parsed(bodies.action)
        self.finish(await self.blocking(self.teleop.step, action))


class RecordHandler(_Base):
    async def post(self):
        on = self.parsed(bodies.recording)
        try:
            if on:
                await self.blocking(self.teleop.start_recording)
                self.finish(self.teleop.state())
            else:
                path = await self.blocking(self.teleop.stop_recording)
                self.finish({**self.teleop.state(), "file": path.name})
        except ValueError as err:
            raise tornado.web.HTTPError(409, "%s", err) from None


class ResetHandler(_Base):
    async def post(self):
        self.parsed(bodies.empty)
        self.finish(await self.blocking(self.teleop.reset))


class RateHandler(_Base):
    async def post(self):
        rating = self.parsed(bodies.rating)
        try:
            path = await self.blocking(self.teleop.rate_last, rating)
        except ValueError as err:  # nothing saved yet to rate
            raise tornado.web.HTTPError(409, "%s", err) from None
        self.finish({"file": path.name})


def make_app(client: Client, teleop: TeleopSession, access: AccessPolicy) -> tornado.web.Application:
    session = r"([A-Za-z0-9_-]+)"
    return tornado.web.Application([
        (r"/", PageHandler), (rf"/watch/{session}", PageHandler),
        (rf"/api/sessions/{session}/view", ViewHandler),
        (rf"/api/sessions/{session}/([A-Za-z0-9_-]+)\.jpg", CameraHandler),
        (r"/api/teleop/step", StepHandler), (r"/api/teleop/record", RecordHandler),
        (r"/api/teleop/rate", RateHandler), (r"/api/teleop/reset", ResetHandler),
    ], client=client, teleop=teleop, access=access)

"""The teleoperation web app (tornado), served next to the simulator.

    GET  /                                   the page: live view and, for its own session, the controls
    GET  /watch/<session>                    the page, read only, for any session on the server
    GET  /api/sessions/<session>/view        JSON: frame, time, TCP position (m), wrist force (N), contact
    GET  /api/sessions/<session>/<camera>.jpg   the camera's last image
    POST /api/teleop/step      {"action": [6 values in -1..1]}    one pd_ee_delta_pose step
    POST /api/teleop/record    {"on": true|false}                 start / stop (stop saves the file)
    POST /api/teleop/rate      {"rating": "good"|"bad"}           rates the last saved demonstration
    POST /api/teleop/reset     {}                                 the scene back to its seed, recording off
The views read the server with Observe only, so watching never changes a session.
"""
from __future__ import annotations

import asyncio
import json
from pathlib import Path

import numpy as np
import tornado.web

from culinarycut.client import Client, cameras_to_dict, food_to_dict
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

    async def blocking(self, function, *args):
        return await asyncio.get_running_loop().run_in_executor(None, function, *args)

    def write_error(self, status_code, **kwargs):
        error = kwargs.get("exc_info", (None, None))[1]
        self.finish({"error": str(error) if error else self._reason})

    def body(self) -> dict:
        try:
            return json.loads(self.request.body or b"{}")
        except ValueError:
            raise tornado.web.HTTPError(400, "the body is not JSON") from None


class PageHandler(_Base):
    def get(self, session: str | None = None):
        page = PAGE.read_text()
        config = {"session": session or self.teleop.session_id, "control": session is None,
                  "cameras": [c["name"] for c in self.teleop.resolved.get("cameras", [])]}
        self.set_header("Content-Type", "text/html; charset=utf-8")
        self.finish(page.replace("/*CONFIG*/null", json.dumps(config)))


class ViewHandler(_Base):
    async def get(self, session: str):
        try:
            response = await self.blocking(self.client.observe, session)
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
            response = await self.blocking(self.client.observe, session)
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
        try:
            state = await self.blocking(self.teleop.step, self.body().get("action", []))
        except ValueError as err:
            raise tornado.web.HTTPError(400, str(err)) from None
        self.finish(state)


class RecordHandler(_Base):
    async def post(self):
        try:
            if self.body().get("on"):
                await self.blocking(self.teleop.start_recording)
                self.finish(self.teleop.state())
            else:
                path = await self.blocking(self.teleop.stop_recording)
                self.finish({**self.teleop.state(), "file": path.name})
        except ValueError as err:
            raise tornado.web.HTTPError(409, str(err)) from None


class ResetHandler(_Base):
    async def post(self):
        self.finish(await self.blocking(self.teleop.reset))


class RateHandler(_Base):
    async def post(self):
        try:
            path = await self.blocking(self.teleop.rate_last, self.body().get("rating", ""))
        except ValueError as err:
            raise tornado.web.HTTPError(400, str(err)) from None
        self.finish({"file": path.name})


def make_app(client: Client, teleop: TeleopSession) -> tornado.web.Application:
    session = r"([A-Za-z0-9_-]+)"
    return tornado.web.Application([
        (r"/", PageHandler), (rf"/watch/{session}", PageHandler),
        (rf"/api/sessions/{session}/view", ViewHandler),
        (rf"/api/sessions/{session}/([A-Za-z0-9_-]+)\.jpg", CameraHandler),
        (r"/api/teleop/step", StepHandler), (r"/api/teleop/record", RecordHandler),
        (r"/api/teleop/rate", RateHandler), (r"/api/teleop/reset", ResetHandler),
    ], client=client, teleop=teleop)

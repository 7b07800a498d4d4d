"""A server with openpi's websocket_policy_server.py behaviour on the wire: on connect it sends its metadata;
each binary frame (msgpack + numpy observation) is answered with the action dict plus `server_timing`
(`infer_ms`, and `prev_total_ms` from the second query on); when inference raises, the traceback goes
out as a text frame and the connection closes with 1011. `GET /healthz` answers 200 "OK". With an
`api_key`, a handshake without `Authorization: Api-Key <key>` is refused with 401 (openpi's own server
accepts anyone; its client sends the header). The real-model scripts in policies/servers/ use it too, and
so does the trained policy of culinarycut_learning, whose model keeps a history per connection (one
connection per episode: the adapters connect at reset): `connection_model` makes one model per connection."""
from __future__ import annotations

import asyncio
import http
import logging
import threading
import time
import traceback
from typing import Any, Callable

import websockets.asyncio.server as ws_server
import websockets.exceptions
import websockets.frames

from culinarycut_policies.transports import msgpack_numpy

log = logging.getLogger("culinarycut_policies.websocket")


class WebsocketPolicyServer:
    """Serves `model(observation) -> action dict` on host:port (port 0: a free one, known after start()).
    With `connection_model`, each connection is answered by its own `connection_model()` instead (a model
    with state that lasts one episode, such as a history of observations); `model` is then unused."""

    def __init__(self, model: Callable[[dict], dict] | None, metadata: dict | None = None, host: str = "127.0.0.1",
                 port: int = 0, api_key: str | None = None,
                 connection_model: Callable[[], Callable[[dict], dict]] | None = None):
        if model is None and connection_model is None:
            raise ValueError("WebsocketPolicyServer needs a model or a connection_model")
        self.model = model
        self.connection_model = connection_model
        self.metadata = metadata or {}
        self.host, self.port = host, port
        self.api_key = api_key
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stop: asyncio.Event | None = None
        self._thread: threading.Thread | None = None
        self._ready = threading.Event()

    @property
    def url(self) -> str:
        return f"ws://{self.host}:{self.port}"

    def serve_forever(self) -> None:
        asyncio.run(self._run())

    def start(self) -> "WebsocketPolicyServer":
        """Serves on a background thread (tests, benchmarks) once the port is bound; stop() ends it."""
        self._thread = threading.Thread(target=self.serve_forever, name="websocket-standin", daemon=True)
        self._thread.start()
        if not self._ready.wait(10.0):
            raise RuntimeError(f"websocket stand-in did not start on {self.host}:{self.port}")
        return self

    def stop(self) -> None:
        if self._loop is not None and self._stop is not None:
            self._loop.call_soon_threadsafe(self._stop.set)
        if self._thread is not None:
            self._thread.join(10.0)

    async def _run(self) -> None:
        self._loop = asyncio.get_running_loop()
        self._stop = asyncio.Event()
        async with ws_server.serve(self._handler, self.host, self.port, compression=None, max_size=None,
                                   process_request=self._process_request) as server:
            self.port = server.sockets[0].getsockname()[1]
            self._ready.set()
            await self._stop.wait()

    def _process_request(self, connection: ws_server.ServerConnection, request):
        if request.path == "/healthz":
            return connection.respond(http.HTTPStatus.OK, "OK\n")
        if self.api_key is not None and request.headers.get("Authorization") != f"Api-Key {self.api_key}":
            return connection.respond(http.HTTPStatus.UNAUTHORIZED, "missing or wrong Authorization: Api-Key\n")
        return None

    async def _handler(self, websocket: ws_server.ServerConnection) -> None:
        model = self.connection_model() if self.connection_model is not None else self.model
        await websocket.send(msgpack_numpy.packb(self.metadata))
        previous_total_s = None
        while True:
            try:
                started = time.monotonic()
                observation = msgpack_numpy.unpackb(await websocket.recv())
                infer_started = time.monotonic()
                action: dict[str, Any] = model(observation)
                timing = {"infer_ms": (time.monotonic() - infer_started) * 1000.0}
                if previous_total_s is not None:
                    timing["prev_total_ms"] = previous_total_s * 1000.0
                action["server_timing"] = timing
                await websocket.send(msgpack_numpy.packb(action))
                previous_total_s = time.monotonic() - started
            except websockets.exceptions.ConnectionClosed:
                break
            except Exception:
                log.error(traceback.format_exc())
                await websocket.send(traceback.format_exc())
                await websocket.close(code=websockets.frames.CloseCode.INTERNAL_ERROR,
                                      reason="Internal server error. Traceback included in previous frame.")
                break

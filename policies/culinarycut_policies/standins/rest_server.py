"""A server with OpenVLA's deploy.py behaviour on the wire, in the standard library: `POST /act` with a
json-numpy body, the model's answer json-numpy encoded with HTTP 200, and on any failure the JSON string
"error" with HTTP 200 (the traceback goes to the log). As FastAPI does, a body that is not a JSON
object gets 422, unknown routes 404 and other methods on /act 405, with {"detail": ...} bodies.
HTTP/1.1 keep-alive, one thread per connection. The real-model scripts in policies/servers/ serve
through it too."""
from __future__ import annotations

import logging
import threading
import traceback
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any, Callable

import json_numpy

log = logging.getLogger("culinarycut_policies.rest")


class _Handler(BaseHTTPRequestHandler):
    protocol_version = "HTTP/1.1"
    disable_nagle_algorithm = True  # headers and body leave in two writes: no 40 ms delayed-ACK stall (uvicorn too)
    server: "JsonNumpyRestServer"

    def log_message(self, format, *args):  # noqa: A002 (the base class's name)
        log.debug("%s " + format, self.address_string(), *args)

    def _reply(self, status: int, body: str) -> None:
        data = body.encode()
        self.send_response(status)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(data)))
        self.end_headers()
        self.wfile.write(data)

    def do_POST(self):  # noqa: N802 (http.server's name)
        length = int(self.headers.get("Content-Length", 0))
        body = self.rfile.read(length)
        if self.path != self.server.route:
            self._reply(404, '{"detail":"Not Found"}')
            return
        try:
            payload = json_numpy.loads(body)
        except ValueError:  # FastAPI refuses a body that is not JSON before deploy.py sees it
            self._reply(422, '{"detail":[{"type":"json_invalid","loc":["body"],"msg":"JSON decode error"}]}')
            return
        if not isinstance(payload, dict):  # deploy.py's `payload: Dict[str, Any]`
            self._reply(422, '{"detail":[{"type":"dict_type","loc":["body"],"msg":"Input should be a valid dictionary"}]}')
            return
        try:
            # deploy.py: arrays "double-encoded" as one string under "encoded", the only key; the answer is
            # then JSONResponse(json_numpy.dumps(action)): the json-numpy text as a JSON string.
            double_encoded = "encoded" in payload
            if double_encoded:
                if len(payload.keys()) != 1:
                    raise ValueError("Only uses encoded payload!")  # deploy.py's assert
                payload = json_numpy.loads(payload["encoded"])
            answer = json_numpy.dumps(self.server.model(payload))
            self._reply(200, json_numpy.dumps(answer) if double_encoded else answer)
        except Exception:  # deploy.py's bare except: log, answer "error" with 200
            log.error(traceback.format_exc())
            self.server.errors += 1
            self._reply(200, '"error"')

    def do_GET(self):  # noqa: N802
        if self.path == self.server.route:
            self._reply(405, '{"detail":"Method Not Allowed"}')
        else:
            self._reply(404, '{"detail":"Not Found"}')


class JsonNumpyRestServer(ThreadingHTTPServer):
    """Serves `model(payload) -> answer` on host:port (port 0: a free one, see .port)."""

    daemon_threads = True

    def __init__(self, model: Callable[[dict], Any], host: str = "127.0.0.1", port: int = 0, route: str = "/act"):
        super().__init__((host, port), _Handler)
        self.model = model
        self.route = route
        self.errors = 0
        self._thread: threading.Thread | None = None

    @property
    def port(self) -> int:
        return self.server_address[1]

    @property
    def url(self) -> str:
        return f"http://{self.server_address[0]}:{self.port}"

    def start(self) -> "JsonNumpyRestServer":
        """Serves on a background thread (tests, benchmarks); stop() ends it."""
        self._thread = threading.Thread(target=self.serve_forever, name="rest-standin", daemon=True)
        self._thread.start()
        return self

    def stop(self) -> None:
        self.shutdown()
        self.server_close()
        if self._thread is not None:
            self._thread.join()

"""OpenVLA's REST protocol (vla-scripts/deploy.py in openvla and openvla-oft): `POST /act` with a JSON body
whose numpy arrays are json-numpy objects ({"__numpy__": base64, "dtype", "shape"}); the reply is the
action (or OFT's list of actions) in the same encoding. On any failure upstream's server answers the JSON
string "error" with HTTP 200, and logs the traceback on its side: we turn that into an error here.

One keep-alive HTTP/1.1 connection per policy; a connection that broke between queries is opened again
(the route is stateless), with the retries of `Timeouts`.
"""
from __future__ import annotations

import http.client
import socket
import time
from typing import Any
from urllib.parse import urlsplit

import json_numpy

from culinarycut_policies.transports.faults import (LatencyLog, PolicyServerError, PolicyServerUnreachable,
                                                    Timeouts, with_connection_retries)

# A keep-alive connection the server closed since the last query fails with one of these on reuse.
_STALE = (http.client.RemoteDisconnected, BrokenPipeError, ConnectionResetError, http.client.CannotSendRequest)


class JsonNumpyRestClient:
    """Posts observations to `url` (http://host:port, the route /act is added when the URL has no path)."""

    def __init__(self, url: str, timeouts: Timeouts = Timeouts(), route: str = "/act"):
        parts = urlsplit(url if "://" in url else f"http://{url}")
        if parts.scheme != "http" or not parts.hostname or not parts.port:
            raise ValueError(f"option url={url!r}: expected http://HOST:PORT (OpenVLA's deploy.py serves plain HTTP)")
        self.url = f"http://{parts.hostname}:{parts.port}{parts.path or route}"
        self.host, self.port, self.path = parts.hostname, parts.port, parts.path or route
        self.timeouts = timeouts
        self.latency = LatencyLog()
        self._connection: http.client.HTTPConnection | None = None

    def connect(self) -> None:
        self._connection = with_connection_retries(self._open, self.timeouts, f"OpenVLA server {self.url}")

    def _open(self) -> http.client.HTTPConnection:
        connection = http.client.HTTPConnection(self.host, self.port, timeout=self.timeouts.connect_s)
        connection.connect()
        connection.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        connection.sock.settimeout(self.timeouts.query_s)
        return connection

    def close(self) -> None:
        if self._connection is not None:
            self._connection.close()
            self._connection = None

    def query(self, payload: dict[str, Any]) -> Any:
        """The decoded reply to one observation; PolicyServerError for "error" or a non-200 answer."""
        started = time.perf_counter()
        body = json_numpy.dumps(payload).encode()
        status, reply = self._post_once_more_if_stale(body)
        if status != 200:
            raise PolicyServerError(f"OpenVLA server {self.url} answered HTTP {status}: {reply[:300]!r}")
        try:
            decoded = json_numpy.loads(reply)
        except ValueError as err:
            raise PolicyServerError(f"OpenVLA server {self.url} answered something that is not JSON ({err}): "
                                    f"{reply[:200]!r}") from None
        if isinstance(decoded, str) and decoded == "error":
            raise PolicyServerError(f"OpenVLA server {self.url} answered \"error\" (HTTP 200): the request failed on "
                                    "the model's side; its log holds the traceback (unknown unnorm_key, a wrong "
                                    "image shape or dtype, a missing key)")
        self.latency.record(started)
        return decoded

    def _post_once_more_if_stale(self, body: bytes) -> tuple[int, bytes]:
        """A keep-alive connection the server closed is opened again (with the connection retries) and the
        request sent once more: the route is stateless. A timeout is never retried."""
        for attempt in range(2):
            if self._connection is None:
                self.connect()
            try:
                return self._post(body)
            except _STALE as err:
                self.close()
                if attempt:
                    raise PolicyServerUnreachable(f"OpenVLA server {self.url} dropped the connection: {err!r}") from None
            except TimeoutError:
                self.close()
                raise TimeoutError(f"OpenVLA server {self.url} did not answer within {self.timeouts.query_s:g} s "
                                   "(option query_timeout_s)") from None
            except ConnectionError as err:
                self.close()
                raise PolicyServerUnreachable(f"OpenVLA server {self.url}: {err!r}") from None
        raise AssertionError("unreachable")

    def _post(self, body: bytes) -> tuple[int, bytes]:
        self._connection.request("POST", self.path, body=body, headers={"Content-Type": "application/json"})
        response = self._connection.getresponse()
        return response.status, response.read()

"""OpenVLA's REST protocol (vla-scripts/deploy.py in openvla and openvla-oft): `POST /act` with a JSON body
whose numpy arrays are json-numpy objects ({"__numpy__": base64, "dtype", "shape"}); the reply is the
action (or OFT's list of actions) in the same encoding; a request in deploy.py's "double-encoded" form
({"encoded": json-numpy text}) is answered with the json-numpy text as a JSON string, which is decoded
once more. On any failure upstream's server answers the JSON string "error" with HTTP 200, and logs the
traceback on its side: we turn that into an error here.

One keep-alive HTTP/1.1 connection per policy. A query is sent at most once: a connection the server
closed while idle is noticed before sending (as urllib3's is_connection_dropped: an idle keep-alive
socket that is readable was closed) and opened again, with the retries of `Timeouts`, and so is one that
fails while the request is being written; once the request's bytes are all sent, a broken connection
ends the query as PolicyServerUnreachable (the server may have acted on it).
"""
from __future__ import annotations

import http.client
import select
import socket
import time
from typing import Any
from urllib.parse import urlsplit

import json_numpy

from culinarycut_policies.transports.faults import (LatencyLog, PolicyServerError, PolicyServerUnreachable,
                                                    Timeouts, with_connection_retries)

# Writing the request to a connection the server has closed fails with one of these: nothing was received.
_NOT_SENT = (BrokenPipeError, ConnectionResetError, http.client.CannotSendRequest)


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
        status, reply = self._post_once(body)
        if status != 200:
            raise PolicyServerError(f"OpenVLA server {self.url} answered HTTP {status}: {reply[:300]!r}")
        try:
            decoded = json_numpy.loads(reply)
            if isinstance(decoded, str) and decoded != "error":
                decoded = json_numpy.loads(decoded)  # deploy.py's double-encoded answer
        except ValueError as err:
            raise PolicyServerError(f"OpenVLA server {self.url} answered something that is not JSON ({err}): "
                                    f"{reply[:200]!r}") from None
        if isinstance(decoded, str) and decoded == "error":
            raise PolicyServerError(f"OpenVLA server {self.url} answered \"error\" (HTTP 200): the request failed on "
                                    "the model's side; its log holds the traceback (unknown unnorm_key, a wrong "
                                    "image shape or dtype, a missing key)")
        self.latency.record(started)
        return decoded

    def _dropped(self) -> bool:
        """An idle keep-alive connection has nothing to read; readable means the server closed it."""
        sock = self._connection.sock if self._connection is not None else None
        if sock is None:
            return True
        return bool(select.select([sock], [], [], 0)[0])

    def _post_once(self, body: bytes) -> tuple[int, bytes]:
        """Sends the request once; a connection found closed before or while writing it is opened again."""
        for attempt in range(2):
            if self._connection is None or self._dropped():
                self.close()
                self.connect()
            try:
                self._connection.request("POST", self.path, body=body, headers={"Content-Type": "application/json"})
                break
            except _NOT_SENT as err:
                self.close()
                if attempt:
                    raise PolicyServerUnreachable(f"OpenVLA server {self.url} dropped the connection before the "
                                                  f"query was sent: {err!r}") from None
            except TimeoutError:
                self.close()
                raise TimeoutError(f"OpenVLA server {self.url} did not take the query within "
                                   f"{self.timeouts.query_s:g} s (option query_timeout_s)") from None
        try:
            response = self._connection.getresponse()
            return response.status, response.read()
        except TimeoutError:
            self.close()
            raise TimeoutError(f"OpenVLA server {self.url} did not answer within {self.timeouts.query_s:g} s "
                               "(option query_timeout_s)") from None
        except (http.client.HTTPException, ConnectionError) as err:
            self.close()
            raise PolicyServerUnreachable(f"OpenVLA server {self.url} dropped the connection after the query was "
                                          f"sent (not sent again: the model may have acted on it): {err!r}") from None

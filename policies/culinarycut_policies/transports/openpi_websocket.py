"""The openpi remote-policy protocol, client side (openpi-client's websocket_client_policy.py): a websocket
to ws://host:port (no compression, no size limit, optional `Authorization: Api-Key <key>`); the server
first sends its metadata; then each binary frame we send (an observation dict, msgpack + numpy) is
answered by one binary frame (the action dict, with `server_timing`). A text frame is the server's
traceback: it closes with 1011 right after. Octo and RDT servers (policies/servers/) speak it too.
"""
from __future__ import annotations

import time
from typing import Any
from urllib.parse import urlsplit

import websockets.exceptions
import websockets.sync.client

from culinarycut_policies.transports import msgpack_numpy
from culinarycut_policies.transports.faults import (LatencyLog, PolicyServerError, PolicyServerUnreachable,
                                                    Timeouts, with_connection_retries)


def websocket_uri(url: str) -> str:
    parts = urlsplit(url if "://" in url else f"ws://{url}")
    if parts.scheme not in ("ws", "wss") or not parts.hostname or not parts.port:
        raise ValueError(f"option url={url!r}: expected ws://HOST:PORT (an openpi policy server)")
    return f"{parts.scheme}://{parts.hostname}:{parts.port}{parts.path}"


class OpenPIWebsocketClient:
    def __init__(self, url: str, timeouts: Timeouts = Timeouts(), api_key: str | None = None):
        self.uri = websocket_uri(url)
        self.timeouts = timeouts
        self.api_key = api_key
        self.latency = LatencyLog()
        self.metadata: dict | None = None
        self._ws: websockets.sync.client.ClientConnection | None = None

    def connect(self) -> dict:
        """Opens the connection and returns the server's metadata."""
        self._ws, self.metadata = with_connection_retries(self._open, self.timeouts, f"policy server {self.uri}")
        return self.metadata

    def _open(self):
        headers = {"Authorization": f"Api-Key {self.api_key}"} if self.api_key else None
        try:
            ws = websockets.sync.client.connect(self.uri, compression=None, max_size=None, additional_headers=headers,
                                                open_timeout=self.timeouts.connect_s, close_timeout=1.0,
                                                legacy=True)  # a connection kept across queries
        except websockets.exceptions.InvalidStatus as err:
            status = err.response.status_code
            hint = " (option api_key)" if status in (401, 403) else ""
            raise PolicyServerError(f"policy server {self.uri} refused the websocket: HTTP {status}{hint}") from None
        try:
            first = ws.recv(timeout=self.timeouts.connect_s)
        except TimeoutError:
            ws.close()
            raise TimeoutError(f"no metadata within {self.timeouts.connect_s:g} s") from None
        if isinstance(first, str):
            ws.close()
            raise PolicyServerError(f"policy server {self.uri} sent text instead of its metadata: {first[:500]}")
        metadata = msgpack_numpy.unpackb(first)
        if not isinstance(metadata, dict):
            ws.close()
            raise PolicyServerError(f"policy server {self.uri}: metadata is a {type(metadata).__name__}, not a dict")
        return ws, metadata

    def close(self) -> None:
        if self._ws is not None:
            self._ws.close()
            self._ws = None

    def infer(self, observation: dict[str, Any]) -> dict[str, Any]:
        """One observation -> the server's action dict. The protocol keeps no request id, so a connection
        that breaks mid-query is not retried here: the episode ends as a policy error."""
        started = time.perf_counter()
        data = msgpack_numpy.packb(observation)
        if self._ws is None:
            self.connect()
        try:
            self._ws.send(data)
            reply = self._ws.recv(timeout=self.timeouts.query_s)
        except TimeoutError:
            self.close()
            raise TimeoutError(f"policy server {self.uri} did not answer within {self.timeouts.query_s:g} s "
                               "(option query_timeout_s)") from None
        except websockets.exceptions.ConnectionClosed as err:
            self._ws = None
            raise PolicyServerUnreachable(f"policy server {self.uri} closed the connection: {_closed(err)}") from None
        except OSError as err:  # the socket failed under the protocol (reset, broken pipe)
            self.close()
            raise PolicyServerUnreachable(f"policy server {self.uri}: {err!r}") from None
        if isinstance(reply, str):
            self.close()
            raise PolicyServerError(f"policy server {self.uri} failed:\n{reply[-2000:]}")
        action = msgpack_numpy.unpackb(reply)
        if not isinstance(action, dict):
            raise PolicyServerError(f"policy server {self.uri} answered a {type(action).__name__}, not a dict")
        timing = action.get("server_timing")
        self.latency.record(started, timing.get("infer_ms") if isinstance(timing, dict) else None)
        return action


def _closed(err: websockets.exceptions.ConnectionClosed) -> str:
    received = err.rcvd
    if received is None:
        return "without a close frame (the server process died?)"
    return f"code {received.code} {received.reason!r}".strip()

"""What every transport shares: timeouts, retries with backoff for connection errors only, and the
latency of each query."""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, TypeVar

import numpy as np

T = TypeVar("T")


class PolicyServerError(RuntimeError):
    """The model server answered with an error, or answered something its protocol does not allow."""


class PolicyServerUnreachable(ConnectionError):
    """The model server could not be reached (after the retries), or the connection broke mid-query."""


@dataclass(frozen=True)
class Timeouts:
    connect_s: float = 10.0     # TCP connect plus handshake (websocket upgrade, metadata)
    query_s: float = 30.0       # one observation -> action round trip; a 7B model on a GPU takes < 1 s
    retries: int = 3            # further connection attempts after the first fails to connect
    backoff_s: float = 0.5      # wait before the first retry, doubled before each next one

    def __post_init__(self):
        for name in ("connect_s", "query_s"):
            if getattr(self, name) <= 0:
                raise ValueError(f"option {name.replace('_s', '_timeout_s')} must be positive, "
                                 f"got {getattr(self, name)}")
        if self.retries < 0 or self.backoff_s < 0:
            raise ValueError(f"options retries ({self.retries}) and backoff_s ({self.backoff_s}) must be >= 0")


def with_connection_retries(connect: Callable[[], T], timeouts: Timeouts, what: str) -> T:
    """connect(), retried on connection errors (refused, reset, timed out) with exponential backoff; any other
    error goes straight up. Raises PolicyServerUnreachable naming `what` after the last attempt."""
    delay = timeouts.backoff_s
    errors = []
    for attempt in range(timeouts.retries + 1):
        try:
            return connect()
        except OSError as err:  # refused, reset, unreachable, timed out (all OSError subclasses)
            errors.append(f"{type(err).__name__}: {err}")
            if attempt < timeouts.retries:
                time.sleep(delay)
                delay *= 2
    raise PolicyServerUnreachable(f"{what}: no connection after {timeouts.retries + 1} attempts "
                                  f"({errors[-1]})")


@dataclass
class LatencyLog:
    """Wall time of each query (s): preprocessing excluded, encoding and the round trip included; and, where
    the server reports it (openpi's `server_timing.infer_ms`), the model's own inference time."""

    seconds: list = field(default_factory=list)
    server_infer_ms: list = field(default_factory=list)

    def record(self, started: float, server_infer_ms: float | None = None) -> None:
        self.seconds.append(time.perf_counter() - started)
        if server_infer_ms is not None:
            self.server_infer_ms.append(float(server_infer_ms))

    def summary(self) -> dict:
        if not self.seconds:
            return {"queries": 0}
        values = np.asarray(self.seconds) * 1000.0
        summary = {"queries": len(values), "mean_ms": round(float(values.mean()), 3),
                   "p50_ms": round(float(np.percentile(values, 50)), 3),
                   "p95_ms": round(float(np.percentile(values, 95)), 3), "max_ms": round(float(values.max()), 3)}
        if self.server_infer_ms:
            summary["server_infer_p50_ms"] = round(float(np.percentile(self.server_infer_ms, 50)), 3)
        return summary

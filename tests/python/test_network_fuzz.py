"""Network fuzz: a bounded run of random requests to every RPC of both services (random bytes, and
messages with random values in random fields); the server must answer each with a status (never
crash or hang) and still report SERVING on gRPC health afterwards. The requests come from
culinarycut.wire_fuzz, which bench/robustness.py uses too."""
from __future__ import annotations

import random
import time

import grpc
import pytest

from culinarycut.launch import ServerProcess, server_binary
from culinarycut.wire_fuzz import all_methods, random_request

REQUESTS = 1500           # in all; each gets a 10 s deadline
SEED = 20261124           # a fixed seed: a failure replays


@pytest.fixture
def server():
    """A server of its own: the requests create sessions nobody closes."""
    with ServerProcess(server_binary(), max_sessions=8) as own:
        yield own


def test_random_requests_never_take_the_server_down(server):
    rng = random.Random(SEED)
    channel = grpc.insecure_channel(server.address)
    methods = all_methods()
    codes: dict[str, int] = {}
    unnamed: list[str] = []  # INVALID_ARGUMENT replies that do not name their field
    started = time.monotonic()
    for _ in range(REQUESTS):
        path, _, payload = random_request(rng, methods)
        call = channel.unary_unary(path, request_serializer=None, response_deserializer=None)
        try:
            call(payload, timeout=10)
            code = "OK"
        except grpc.RpcError as err:
            code = err.code().name
            assert code != "UNKNOWN", f"{path}: {err.details()}"
            assert code != "DEADLINE_EXCEEDED", f"{path} hung for 10 s"
            assert len(err.details() or "") <= 1200, f"{path}: a {len(err.details())}-character message"
            if code == "INVALID_ARGUMENT":
                field = dict(err.trailing_metadata() or ()).get("culinarycut-field", "")
                if not field:
                    unnamed.append(f"{path}: {err.details()}")
        codes[code] = codes.get(code, 0) + 1
        assert server.proc.poll() is None, f"the server died on {path}:\n{server.output()}"
    # gRPC health, overall (an empty HealthCheckRequest); the reply {status: SERVING} is the bytes 08 01.
    health = channel.unary_unary("/grpc.health.v1.Health/Check", request_serializer=None, response_deserializer=None)
    assert health(b"", timeout=10) == b"\x08\x01"
    channel.close()
    assert codes.get("INVALID_ARGUMENT", 0) > REQUESTS // 4, codes
    assert not unnamed, f"{len(unnamed)} INVALID_ARGUMENT replies name no field, e.g.:\n" + "\n".join(unnamed[:10])
    assert time.monotonic() - started < 300

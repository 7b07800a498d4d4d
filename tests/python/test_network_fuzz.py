"""Network fuzz: a bounded run of random requests to every RPC of both services (random bytes, and
messages with random values in random fields); the server must answer each with a status (never
crash or hang) and still report SERVING on gRPC health afterwards."""
from __future__ import annotations

import random
import time

import grpc
import pytest
from google.protobuf import descriptor, message_factory

from culinarycut.launch import ServerProcess, server_binary
from culinarycut.v1 import simulator_pb2, task_pb2

SERVICES = [simulator_pb2.DESCRIPTOR.services_by_name["Simulator"], task_pb2.DESCRIPTOR.services_by_name["Tasks"]]
REQUESTS = 1500           # in all; each gets a 10 s deadline
SEED = 20261124           # a fixed seed: a failure replays
INTERESTING_NUMBERS = [0, -1, 1, 1e300, -1e300, float("nan"), float("inf"), 2**63 - 1, 2**64 - 1, 1e-300, 0.5]


def random_value(rng: random.Random, field: descriptor.FieldDescriptor):
    kind = field.type
    if kind in (field.TYPE_DOUBLE, field.TYPE_FLOAT):
        return rng.choice(INTERESTING_NUMBERS + [rng.uniform(-10, 10)])
    if kind in (field.TYPE_INT32, field.TYPE_SINT32, field.TYPE_SFIXED32):
        return rng.randint(-2**31, 2**31 - 1)
    if kind in (field.TYPE_INT64, field.TYPE_SINT64, field.TYPE_SFIXED64):
        return rng.randint(-2**63, 2**63 - 1)
    if kind in (field.TYPE_UINT32, field.TYPE_FIXED32):
        return rng.choice([0, 1, 3, 2**32 - 1, rng.randint(0, 2**32 - 1)])
    if kind in (field.TYPE_UINT64, field.TYPE_FIXED64):
        return rng.choice([0, 1, 2**64 - 1, rng.randint(0, 2**64 - 1)])
    if kind == field.TYPE_BOOL:
        return rng.random() < 0.5
    if kind == field.TYPE_STRING:
        return rng.choice(["", "cucumber", "pd_ee_delta_pose", "saw", "\x00", "x" * rng.randint(0, 5000),
                           "".join(chr(rng.randint(1, 0x2FF)) for _ in range(rng.randint(0, 40)))])
    if kind == field.TYPE_BYTES:
        return rng.randbytes(rng.randint(0, 2000))
    if kind == field.TYPE_ENUM:
        return rng.choice([v.number for v in field.enum_type.values])
    raise AssertionError(kind)


def message_class(message_descriptor):
    """The generated class of a message (protobuf >= 4.22 has GetMessageClass; Debian 12's 4.21 GetPrototype)."""
    if hasattr(message_factory, "GetMessageClass"):
        return message_factory.GetMessageClass(message_descriptor)
    return message_factory.MessageFactory().GetPrototype(message_descriptor)


def fill(rng: random.Random, message, depth: int = 0) -> None:
    for field in message.DESCRIPTOR.fields:
        if rng.random() < 0.5:
            continue
        repeated = field.label == field.LABEL_REPEATED
        if field.type == field.TYPE_MESSAGE:
            if field.message_type.GetOptions().map_entry:
                continue
            if depth > 3:
                continue
            if repeated:
                for _ in range(rng.randint(0, 3)):
                    fill(rng, getattr(message, field.name).add(), depth + 1)
            else:
                fill(rng, getattr(message, field.name), depth + 1)
        elif repeated:
            getattr(message, field.name).extend(random_value(rng, field) for _ in range(rng.randint(0, 12)))
        else:
            setattr(message, field.name, random_value(rng, field))


@pytest.fixture
def server():
    """A server of its own: the requests create sessions nobody closes."""
    with ServerProcess(server_binary(), max_sessions=8) as own:
        yield own


def test_random_requests_never_take_the_server_down(server):
    rng = random.Random(SEED)
    channel = grpc.insecure_channel(server.address)
    methods = [(f"/{service.full_name}/{method.name}", method) for service in SERVICES for method in service.methods]
    codes: dict[str, int] = {}
    unnamed: list[str] = []  # INVALID_ARGUMENT replies that do not name their field
    started = time.monotonic()
    for _ in range(REQUESTS):
        path, method = rng.choice(methods)
        if rng.random() < 0.3:
            payload = rng.randbytes(rng.randint(0, 300))  # often not even a valid message
        else:
            request = message_class(method.input_type)()
            fill(rng, request)
            payload = request.SerializeToString()
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

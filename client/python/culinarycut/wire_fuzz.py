"""Random requests to every RPC of the server's two services, for network fuzzing: random bytes (often
not even a valid message), or messages of the method's request type with random values (NaN,
infinities, 1e300, huge counts, 5,000-character strings, NUL bytes) in random fields. The same seed
gives the same requests, so a failure replays. Used by tests/python/test_network_fuzz.py and
bench/robustness.py.

    rng = random.Random(seed)
    methods = all_methods()
    path, kind, payload = random_request(rng, methods)   # send payload as the raw request bytes of path
"""
from __future__ import annotations

import random

from google.protobuf import descriptor, message_factory

from culinarycut.v1 import simulator_pb2, task_pb2

SERVICES = [simulator_pb2.DESCRIPTOR.services_by_name["Simulator"], task_pb2.DESCRIPTOR.services_by_name["Tasks"]]
INTERESTING_NUMBERS = [0, -1, 1, 1e300, -1e300, float("nan"), float("inf"), 2**63 - 1, 2**64 - 1, 1e-300, 0.5]
RANDOM_BYTES_SHARE = 0.3  # of the requests; the rest are messages with random values
RANDOM_BYTES = "random bytes"
RANDOM_MESSAGE = "random message"


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
    """Sets about half of `message`'s fields, recursively to depth 4, to random values (maps left empty)."""
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


def all_methods() -> list[tuple[str, descriptor.MethodDescriptor]]:
    """(gRPC path, method) for every RPC of both services, in declaration order."""
    return [(f"/{service.full_name}/{method.name}", method) for service in SERVICES for method in service.methods]


def random_request(rng: random.Random, methods: list[tuple[str, descriptor.MethodDescriptor]]) -> tuple[str, str, bytes]:
    """One request: (gRPC path, RANDOM_BYTES or RANDOM_MESSAGE, the serialized request)."""
    path, method = rng.choice(methods)
    if rng.random() < RANDOM_BYTES_SHARE:
        return path, RANDOM_BYTES, rng.randbytes(rng.randint(0, 300))
    request = message_class(method.input_type)()
    fill(rng, request)
    return path, RANDOM_MESSAGE, request.SerializeToString()

"""The conformance suite through the Python client's generated stubs (cases.json; the C++ runner is
conformance_cpp.cc). Usage: python conformance.py [--server BINARY]; exits 1 naming each failure."""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import grpc
from google.protobuf import json_format

from culinarycut.launch import ServerProcess, server_binary
from culinarycut.v1 import simulator_pb2, simulator_pb2_grpc, task_pb2, task_pb2_grpc

CASES = Path(__file__).with_name("cases.json")
SERVICES = [(simulator_pb2, simulator_pb2_grpc.SimulatorStub, "Simulator"), (task_pb2, task_pb2_grpc.TasksStub, "Tasks")]


def resolve(value, saved: dict):
    """Replaces "$name.path" strings (anywhere in a request) by the saved reply's value there."""
    if isinstance(value, dict):
        return {k: resolve(v, saved) for k, v in value.items()}
    if isinstance(value, list):
        return [resolve(v, saved) for v in value]
    if isinstance(value, str) and value.startswith("$"):
        name, _, path = value[1:].partition(".")
        return at_path(saved[name], path)
    return value


def at_path(reply, path: str):
    for key in path.split(".") if path else []:
        reply = reply[key]
    return reply


def same(actual, expected) -> bool:
    if isinstance(expected, bool) or expected is None:
        return actual == expected
    if isinstance(expected, (int, float)):  # proto3 JSON writes 64-bit integers as strings
        try:
            return abs(float(actual) - expected) <= 1e-9 * max(1.0, abs(expected))
        except (TypeError, ValueError):
            return False
    return actual == expected


def run(address: str) -> list[str]:
    channel = grpc.insecure_channel(address)
    methods = {}
    for module, stub_class, service in SERVICES:
        stub = stub_class(channel)
        for method in module.DESCRIPTOR.services_by_name[service].methods:
            methods[method.name] = (getattr(stub, method.name), getattr(module, method.input_type.name))
    failures = []
    for case in json.loads(CASES.read_text())["cases"]:
        saved: dict = {}
        for index, call in enumerate(case["calls"]):
            where = f"{case['name']} / call {index} {call['call']}"
            invoke, request_class = methods[call["call"]]
            request = json_format.ParseDict(resolve(call["request"], saved), request_class())
            try:
                reply = json_format.MessageToDict(invoke(request, timeout=60), preserving_proto_field_name=True,
                                                  including_default_value_fields=True)
                code, message, field = "OK", "", ""
            except grpc.RpcError as error:
                reply, code, message = {}, error.code().name, error.details() or ""
                field = dict(error.trailing_metadata() or ()).get("culinarycut-field", "")
            if "save" in call:
                saved[call["save"]] = reply
            expect = call.get("expect", {"code": "OK"})
            if code != expect.get("code", "OK"):
                failures.append(f"{where}: code {code} ({message}), expected {expect.get('code', 'OK')}")
                break
            if "message_contains" in expect and expect["message_contains"] not in message:
                failures.append(f"{where}: message {message!r} lacks {expect['message_contains']!r}")
            if "field" in expect and field != expect["field"]:
                failures.append(f"{where}: field detail {field!r}, expected {expect['field']!r}")
            for path, value in expect.get("fields", {}).items():
                try:
                    actual = at_path(reply, path)
                except (KeyError, TypeError):
                    actual = "<missing>"
                if not same(actual, value):
                    failures.append(f"{where}: {path} = {actual!r}, expected {value!r}")
            for path, values in expect.get("contains", {}).items():
                missing = [v for v in values if v not in at_path(reply, path)]
                if missing:
                    failures.append(f"{where}: {path} lacks {missing}")
    return failures


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--server", type=Path, default=None, help="culinarycut-server binary (default: the build's)")
    args = parser.parse_args()
    with ServerProcess(args.server or server_binary(), max_sessions=8) as server:
        failures = run(server.address)
    cases = len(json.loads(CASES.read_text())["cases"])
    for failure in failures:
        print(f"FAILED: {failure}")
    print(f"python conformance: {cases} cases, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

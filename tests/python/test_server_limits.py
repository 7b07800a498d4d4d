"""The server publishes its limits and keeps them: a memory budget over all sessions, checked at
CreateSession with each scene's estimate, refused with RESOURCE_EXHAUSTED naming the flag; a cap on the
threads that serve calls."""
from __future__ import annotations

import json
import os
import subprocess
import time
from pathlib import Path

import grpc
import pytest
from google.protobuf import json_format

from culinarycut import Client
from culinarycut.errors import ResourceExhausted
from culinarycut.launch import ServerProcess, cores_per_local_server, server_binary
from culinarycut.v1 import simulator_pb2, simulator_pb2_grpc


def test_limits_are_published(client):
    limits = client.server_info().limits
    assert limits.memory_budget_bytes > 0 and limits.max_handler_threads >= 4
    assert limits.max_food_particles == 2_000_000 and limits.max_mpm_substeps_per_step == 50_000
    assert limits.max_camera_pixels == 4_194_304
    assert limits.step_threads == "shared" and limits.step_cores == os.cpu_count()  # the cores shared among Steps
    # The connection gate's caps as fitted to the descriptor limit, and the scene's MPM bounds.
    assert 0 < limits.max_connections_per_address <= limits.max_connections <= 1024
    assert limits.max_mass_scaling == 1000.0 and limits.min_activity_radius_cells == 5.0


def test_cc_cut_prints_the_presets_and_bounds_the_server_publishes(client):
    from culinarycut.safety.binary import cc_cut_binary
    printed = json.loads(subprocess.run([str(cc_cut_binary()), "--presets"], capture_output=True, text=True,
                                        check=True).stdout)
    info = client.server_info()
    published = [json_format.MessageToDict(p, preserving_proto_field_name=True, including_default_value_fields=True)
                 for p in info.quality_presets]
    assert [p["name"] for p in printed["quality_presets"]] == ["draft", "standard", "fine"]
    assert printed["quality_presets"] == published  # each preset's resolution and measured accuracy, NaN included
    assert (printed["max_mass_scaling"], printed["min_activity_radius_cells"], printed["simd"]) == \
        (info.limits.max_mass_scaling, info.limits.min_activity_radius_cells, info.simd)


def test_servers_started_together_on_one_machine_share_its_cores():
    # Each server shares only the cores it is told of among its Steps: two that each took every core would run
    # twice as many MPM threads as there are cores.
    import argparse
    from culinarycut.cli_data import _servers
    assert cores_per_local_server(1) == os.cpu_count() and cores_per_local_server(10**6) == 1
    with _servers(argparse.Namespace(local_servers=2, server=None)) as addresses:
        for address in addresses:
            with Client(address) as client:
                assert client.server_info().limits.step_cores == max(1, os.cpu_count() // 2)


def test_a_unix_socket_has_no_connection_caps(tmp_path):
    with ServerProcess(server_binary(), listen=f"unix:{tmp_path}/server.sock") as server, \
            Client(server.address) as client:
        limits = client.server_info().limits
        assert (limits.max_connections, limits.max_connections_per_address) == (0, 0)


def test_the_memory_budget_bounds_the_sessions():
    # A robot-only session is estimated at 8 MB: a 60 MB budget holds seven of them.
    with ServerProcess(server_binary(), max_sessions=100, extra_args=["--memory-budget-mb", "60"]) as server, \
            Client(server.address) as client:
        sessions = [client.create_session({}).session_id for _ in range(7)]
        assert client.server_info().limits.memory_reserved_bytes == 7 * (8 << 20)
        with pytest.raises(ResourceExhausted, match="--memory-budget-mb"):
            client.create_session({})
        # A camera scene needs more than a robot-only one: refused too, naming what to lower.
        client.close_session(sessions.pop())
        with pytest.raises(ResourceExhausted, match="cameras"):
            client.create_session({"cameras": [{"name": "front", "width": 1024, "height": 1024}]})
        client.create_session({})  # the freed room takes a robot-only session again
        assert client.server_info().limits.memory_reserved_bytes == 7 * (8 << 20)


def _threads(pid: int) -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("Threads:"):
            return int(line.split()[1])
    raise AssertionError("no Threads line")


def test_concurrent_calls_never_grow_the_server_past_its_handler_thread_cap():
    """1,000 calls at once (asynchronous, over 10 connections) into one busy session: each waits for the
    session, and the server's threads stay within --max-handler-threads of where they started (gRPC's
    resource quota), answering OK or RESOURCE_EXHAUSTED, never dying."""
    cap = 8
    calls, connections = 1000, 10
    # 0.5 s of robot physics per Step (a few ms of work): the calls pile up behind the session's lock.
    scene = {"robot": {"control_frequency_hz": 2}}
    with ServerProcess(server_binary(), max_sessions=4, extra_args=["--max-handler-threads", str(cap)]) as server, \
            Client(server.address, timeout_s=120) as client:
        session = client.create_session(scene).session_id
        client.reset(session)
        baseline = _threads(server.proc.pid)
        peak = baseline
        channels = [grpc.insecure_channel(server.address) for _ in range(connections)]
        stubs = [simulator_pb2_grpc.SimulatorStub(channel) for channel in channels]
        request = simulator_pb2.StepRequest(
            session_id=session, action=simulator_pb2.Action(control_mode="pd_joint_delta_pos", values=[0.01] * 7))
        pending = [stubs[i % connections].Step.future(request, timeout=300) for i in range(calls)]
        while not all(f.done() for f in pending):
            peak = max(peak, _threads(server.proc.pid))
            time.sleep(0.01)
        codes: dict[str, int] = {}
        for future in pending:
            error = future.exception()
            code = "OK" if error is None else error.code().name
            codes[code] = codes.get(code, 0) + 1
        for channel in channels:
            channel.close()
        assert server.proc.poll() is None
        assert set(codes) <= {"OK", "RESOURCE_EXHAUSTED"} and codes.get("OK", 0) > 0, codes
        assert codes.get("RESOURCE_EXHAUSTED", 0) > 0, f"the calls never exceeded the cap: {codes}"
        assert peak <= baseline + cap, f"threads went from {baseline} to {peak} with a cap of {cap}"

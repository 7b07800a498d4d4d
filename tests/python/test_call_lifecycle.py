"""Calls that the client abandons, servers that stop, ports that are taken, ids that are absurd: the
server finishes nothing nobody waits for, exits promptly, and never echoes a huge input back."""
from __future__ import annotations

import re
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

from culinarycut import Client
from culinarycut.errors import CulinaryCutError, DeadlineExceeded, NotFound
from culinarycut.launch import ServerProcess, server_binary
from culinarycut.policies import ScriptedOracle

# A large draft cucumber with a CFL factor 25 times below the preset's (about 35,000 MPM substeps per
# control step, under the server's limit): every control step with the knife near the food is seconds
# of work, while the approach is fast.
SLOW_SCENE = {"quality": "draft", "mpm": {"cfl": 0.012},
              "effects": {"mpm": True, "damage": True, "friction": True, "topology": True, "force_sensing": True},
              "objects": [{"food": "cucumber", "scale": 1.5}]}


def approach_until_slow(address: str, session: str, deadline_s: float) -> tuple[int, str, list[float]]:
    """Steps the oracle with a `deadline_s` per call until a step misses it; returns the steps applied
    and the action of the slow step (not applied)."""
    with Client(address, timeout_s=30.0) as planner, Client(address, timeout_s=deadline_s) as hurried:
        oracle = ScriptedOracle(planner, session)
        oracle.reset("cut the cucumber in the middle")
        applied = 0
        while not oracle.finished:
            mode, values = oracle.act()
            try:
                hurried.step(session, mode, values)
            except DeadlineExceeded:
                return applied, mode, values
            applied += 1
    raise AssertionError("no step was slow: the knife never came near the food")


def test_a_step_past_its_deadline_is_not_applied():
    with ServerProcess(server_binary(), max_sessions=2) as server, Client(server.address, timeout_s=30.0) as client:
        session = client.create_session(SLOW_SCENE).session_id
        client.reset(session, seed=0)
        applied, _, _ = approach_until_slow(server.address, session, deadline_s=1.0)
        assert applied > 0
        # The abandoned step was rolled back: the state is the one after the last applied step.
        time.sleep(0.2)
        assert client.observe(session).stamp.frame_id == applied


def stop_during_a_long_step(signals: int) -> tuple[ServerProcess, int, float, list[Exception]]:
    """A server whose one session runs a long Step on a thread; 0.5 s into it the server gets SIGTERM
    `signals` times, 50 ms apart. Returns the stopped server, its exit code, the seconds from the first
    signal to the exit, and what the stepping client raised."""
    server = ServerProcess(server_binary(), max_sessions=2)
    errors: list[Exception] = []
    try:
        with Client(server.address, timeout_s=30.0) as client:
            session = client.create_session(SLOW_SCENE).session_id
            client.reset(session, seed=0)
            _, mode, values = approach_until_slow(server.address, session, deadline_s=1.0)

            def long_step():  # the same slow step again, now without a short deadline
                try:
                    client.step(session, mode, values)
                except CulinaryCutError as err:  # the server goes away mid-call
                    errors.append(err)

            stepping = threading.Thread(target=long_step)
            stepping.start()
            time.sleep(0.5)
            started = time.monotonic()
            for index in range(signals):
                if index:
                    time.sleep(0.05)
                server.proc.send_signal(signal.SIGTERM)
            code = server.proc.wait(timeout=10)
            elapsed = time.monotonic() - started
            stepping.join(timeout=10)
            assert not stepping.is_alive()
        return server, code, elapsed, errors
    finally:
        server.kill()


def test_sigterm_during_a_long_step_exits_within_2_s():
    server, code, elapsed, errors = stop_during_a_long_step(signals=1)
    assert elapsed < 2.0, f"exit took {elapsed:.2f} s; output:\n{server.output()}"
    # The step in flight was stopped at once (not at the shutdown's 1 s grace deadline) and rolled back.
    assert errors and "shutting down" in str(errors[0]) and "rolled back" in str(errors[0]), errors
    assert code == 0, server.output()
    assert "stopped cleanly" in server.output()


def test_a_second_stop_signal_never_waits():
    server, code, elapsed, _ = stop_during_a_long_step(signals=2)
    # The step stops at the first signal, so the server is usually already gone cleanly; if it is not, the
    # second signal exits at once (code 1, and the log says why) instead of waiting for calls in flight.
    assert elapsed < 2.0, f"exit took {elapsed:.2f} s; output:\n{server.output()}"
    assert code == 0 or (code == 1 and "second stop signal" in server.output()), (code, server.output())


def test_a_second_server_on_a_taken_port_fails_at_start():
    with ServerProcess(server_binary(), max_sessions=1) as first:
        port = first.address.rsplit(":", 1)[1]
        second = subprocess.run([str(server_binary()), "--listen", f"127.0.0.1:{port}", "--telemetry", ""],
                                capture_output=True, text=True, timeout=30)
        assert second.returncode == 2
        assert "cannot listen on 127.0.0.1:" + port in second.stderr and "in use" in second.stderr
        with Client(first.address) as client:  # the first one still serves
            assert client.server_info().version


def test_an_absurd_session_id_gets_a_short_answer(client):
    with pytest.raises(NotFound) as missing:
        client.step("s-" + "x" * 100_000, "pd_joint_delta_pos", np.zeros(7))
    assert len(missing.value.details) < 300
    assert re.search(r"no session 's-x+\.\.\.'", missing.value.details)


@pytest.mark.parametrize("args, flag", [(["--listen", "0.0.0.0:0", "--telemetry", ""], "--listen 0.0.0.0:0"),
                                        # a host name that merely starts with "127." is not loopback
                                        (["--listen", "127.example.com:0", "--telemetry", ""], "--listen 127.example.com:0"),
                                        (["--listen", "127.0.0.1:0", "--telemetry", "tcp://0.0.0.0:0"], "--telemetry")])
def test_off_loopback_without_tls_needs_insecure(args, flag):
    refused = subprocess.run([str(server_binary()), *args], capture_output=True, text=True, timeout=30)
    assert refused.returncode == 2 and flag in refused.stderr and "--insecure" in refused.stderr
    # With --insecure it starts, and warns.
    with ServerProcess(server_binary(), max_sessions=1, extra_args=["--insecure"]) as server:
        assert server.address


def test_echoed_input_comes_back_short_and_escaped(client):
    with pytest.raises(CulinaryCutError) as huge:
        client.create_session({"effects": {"mpm": True}, "objects": [{"food": "x" * 1_600_000}]})
    assert huge.value.code.name == "INVALID_ARGUMENT"
    assert len(huge.value.details) < 300 and "scene.objects[0].food" in huge.value.details
    with pytest.raises(CulinaryCutError) as nul:
        client.create_session({"effects": {"mpm": True}, "objects": [{"food": "dur\x00ian"}]})
    assert "scene.objects[0].food" in nul.value.details and "control character" in nul.value.details


def test_a_huge_instruction_is_not_echoed_back_whole(client):
    with pytest.raises(CulinaryCutError) as refused:
        client.tasks.parse_instruction("cut the " + "zucchini " * 20_000)
    assert refused.value.code.name == "INVALID_ARGUMENT" and len(refused.value.details) < 1100


def test_a_request_grpc_cannot_decode_is_explained_as_the_clients_fault(address):
    """A session id that is not UTF-8: gRPC refuses it before the server's code runs (INTERNAL, no message);
    the client's error says what happened instead of looking like an engine failure."""
    import grpc
    from culinarycut.errors import Internal, from_rpc_error
    with grpc.insecure_channel(address) as channel:
        raw_step = channel.unary_unary("/culinarycut.v1.Simulator/Step", request_serializer=lambda b: b,
                                       response_deserializer=lambda b: b)
        with pytest.raises(grpc.RpcError) as refused:
            raw_step(b"\x0a\x02\xff\xfe", timeout=10)  # field 1 (session_id): two bytes that are not UTF-8
    error = from_rpc_error(refused.value)
    assert isinstance(error, Internal) and "could not decode the request" in error.details
    assert "not UTF-8" in error.details and "not in the engine" in error.details


def test_a_connection_flood_past_the_soft_descriptor_limit_leaves_the_server_serving():
    """Started with a soft limit of 64 descriptors: 300 idle TCP connections would exhaust it, and gRPC's
    listener never accepts again after EMFILE; the server raises its soft limit to the hard one at start,
    so a new client is served during the flood and after it."""
    import resource
    import socket
    hard = resource.getrlimit(resource.RLIMIT_NOFILE)[1]
    if hard != resource.RLIM_INFINITY and hard < 1024:
        pytest.skip(f"the hard descriptor limit here is {hard}: no room above the flood")

    def low_soft_limit():
        resource.setrlimit(resource.RLIMIT_NOFILE, (64, hard))

    process = subprocess.Popen([str(server_binary()), "--listen", "127.0.0.1:0"], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, preexec_fn=low_soft_limit)
    flood = []
    try:
        lines = [process.stdout.readline() for _ in range(3)]
        address = next(m.group(1) for line in lines if (m := re.search(r"listening on (\S+:\d+)", line)))
        assert any("descriptor limit raised from 64" in line for line in lines), lines
        host, port = address.rsplit(":", 1)
        for _ in range(300):
            flood.append(socket.create_connection((host, int(port)), timeout=5))
        with Client(address, timeout_s=10) as during:
            assert during.server_info().version
        for connection in flood:
            connection.close()
        with Client(address, timeout_s=10) as after:
            assert after.server_info().version
    finally:
        for connection in flood:
            connection.close()
        process.terminate()
        process.wait(timeout=10)

"""The server publishes its limits and keeps them: a memory budget over all sessions, checked at
CreateSession with each scene's estimate, refused with RESOURCE_EXHAUSTED naming the flag; a cap on the
threads that serve calls."""
from __future__ import annotations

import concurrent.futures
import time
from pathlib import Path

import pytest

from culinarycut import Client, errors
from culinarycut.errors import ResourceExhausted
from culinarycut.launch import ServerProcess, server_binary


def test_limits_are_published(client):
    limits = client.server_info().limits
    assert limits.memory_budget_bytes > 0 and limits.max_handler_threads >= 4
    assert limits.max_food_particles == 2_000_000 and limits.max_mpm_substeps_per_step == 50_000
    assert limits.max_camera_pixels == 4_194_304


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
    """200 calls at once into one busy session: each waits for the session, and the server's threads stay
    within --max-handler-threads of where they started (gRPC's resource quota), answering OK or
    RESOURCE_EXHAUSTED, never dying."""
    cap = 8
    scene = {"quality": "draft", "effects": {"mpm": True}, "objects": [{"food": "cucumber"}]}
    with ServerProcess(server_binary(), max_sessions=4, extra_args=["--max-handler-threads", str(cap)]) as server, \
            Client(server.address, timeout_s=120) as client:
        session = client.create_session(scene).session_id
        client.reset(session)
        baseline = _threads(server.proc.pid)
        peak = baseline
        codes: dict[str, int] = {}

        def call(_):
            try:
                client.step(session, "pd_joint_delta_pos", [0.01] * 7)
                return "OK"
            except errors.CulinaryCutError as err:
                return err.code.name

        with concurrent.futures.ThreadPoolExecutor(200) as pool:
            pending = [pool.submit(call, i) for i in range(200)]
            while not all(f.done() for f in pending):
                peak = max(peak, _threads(server.proc.pid))
                time.sleep(0.01)
            for future in pending:
                codes[future.result()] = codes.get(future.result(), 0) + 1
        assert server.proc.poll() is None
        assert set(codes) <= {"OK", "RESOURCE_EXHAUSTED"} and codes.get("OK", 0) > 0, codes
        assert peak <= baseline + cap, f"threads went from {baseline} to {peak} with a cap of {cap}"

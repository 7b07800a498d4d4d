"""The server publishes its limits and keeps them: a memory budget over all sessions, checked at
CreateSession with each scene's estimate, refused with RESOURCE_EXHAUSTED naming the flag."""
from __future__ import annotations

import pytest

from culinarycut import Client
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

"""`bench run --workers auto` sizes the episodes at once to the servers' cores: one per core their Steps share,
within the sessions each has free, summed over servers, at most 16."""
from __future__ import annotations

import pytest

from culinarycut.bench.preflight import auto_workers
from culinarycut.cli_bench import _workers
from culinarycut.v1 import simulator_pb2


def info(step_cores: int, max_sessions: int = 16, active: int = 0) -> simulator_pb2.ServerInfo:
    return simulator_pb2.ServerInfo(limits=simulator_pb2.ServerLimits(step_cores=step_cores, max_sessions=max_sessions,
                                                                      active_sessions=active))


def test_one_worker_per_core_the_steps_share():
    assert auto_workers({"a": info(2)}) == 2
    assert auto_workers({"a": info(2), "b": info(8)}) == 10  # every server's cores
    assert auto_workers({"a": info(64)}) == 16  # capped
    assert auto_workers({"a": info(8, max_sessions=16, active=13)}) == 3  # the sessions it has free
    assert auto_workers({"a": info(8, max_sessions=4, active=4)}) == 1  # none free: one, and it waits its turn
    assert auto_workers({"a": info(0)}) == 2  # a server too old to say


def test_the_option_takes_a_count_or_auto(client):
    assert _workers("auto") is None and _workers("3") == 3
    with pytest.raises(Exception, match="not a number of workers or auto"):
        _workers("many")
    live = client.server_info()
    assert auto_workers({"live": live}) == min(16, live.limits.step_cores, live.limits.max_sessions -
                                               live.limits.active_sessions)

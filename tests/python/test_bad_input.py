"""Bad requests over the wire get the documented status code, and the server keeps serving."""
from __future__ import annotations

import math

import numpy as np
import pytest

from culinarycut import Client, errors
from conftest import start_server, stop_server

GOOD_JOINT_DELTA = [0.01, 0, 0, 0, 0, 0, 0]  # rad


def assert_still_serving(client: Client, session_id: str, frame_before: int) -> None:
    """A rejected request must not advance the session, and the next valid Step must succeed."""
    assert client.observe(session_id).stamp.frame_id == frame_before
    response = client.step(session_id, "pd_joint_delta_pos", GOOD_JOINT_DELTA)
    assert response.stamp.frame_id == frame_before + 1


def frame(client: Client, session_id: str) -> int:
    return client.observe(session_id).stamp.frame_id


@pytest.mark.parametrize("rpc", ["step", "reset", "observe", "save_snapshot", "close_session"])
def test_unknown_session_is_not_found(client, session, rpc):
    calls = {
        "step": lambda: client.step("no-such-session", "pd_joint_delta_pos", GOOD_JOINT_DELTA),
        "reset": lambda: client.reset("no-such-session", seed=0),
        "observe": lambda: client.observe("no-such-session"),
        "save_snapshot": lambda: client.save_snapshot("no-such-session"),
        "close_session": lambda: client.close_session("no-such-session"),
    }
    f0 = frame(client, session)
    with pytest.raises(errors.NotFound) as info:
        calls[rpc]()
    assert info.value.code.name == "NOT_FOUND"
    assert_still_serving(client, session, f0)


BAD_ACTIONS = {
    "too_short": ("pd_joint_delta_pos", [0.0] * 6, "action.values"),
    "too_long": ("pd_joint_delta_pos", [0.0] * 8, "action.values"),
    "empty": ("pd_joint_delta_pos", [], "action.values"),
    "ee_delta_7_values": ("pd_ee_delta_pose", [0.0] * 7, "action.values"),
    "nan": ("pd_joint_delta_pos", [0, 0, math.nan, 0, 0, 0, 0], "action.values"),
    "inf": ("pd_joint_delta_pos", [0, 0, 0, math.inf, 0, 0, 0], "action.values"),
    "minus_inf": ("pd_joint_pos", [0, 0, 0, -math.inf, 0, 0, 0], "action.values"),
    "nan_in_ee_pose": ("pd_ee_pose", [0.5, 0, math.nan, 0, 1, 0, 0], "action.values"),
    "unknown_control_mode": ("pd_teleport", [0.0] * 7, "control_mode"),
    "zero_quaternion": ("pd_ee_pose", [0.5, 0.0, 0.2, 0.0, 0.0, 0.0, 0.0], "action.values"),
}


@pytest.mark.parametrize("case", sorted(BAD_ACTIONS))
def test_bad_action_is_invalid_argument_naming_the_field(client, session, case):
    mode, values, field = BAD_ACTIONS[case]
    f0 = frame(client, session)
    with pytest.raises(errors.InvalidArgument) as info:
        client.step(session, mode, values)
    assert field in info.value.details, f"{case}: message does not name {field!r}: {info.value.details!r}"
    assert_still_serving(client, session, f0)


def test_bad_initial_qpos_is_invalid_argument(client, session):
    f0 = frame(client, session)
    with pytest.raises(errors.InvalidArgument) as info:
        client.reset(session, seed=0, initial_qpos=[0.0] * 5)
    assert "initial_qpos" in info.value.details
    assert_still_serving(client, session, f0)


def test_garbage_snapshot_is_invalid_argument(client, session):
    f0 = frame(client, session)
    with pytest.raises(errors.InvalidArgument) as info:
        client.restore_snapshot(session, b"\x00not a snapshot\xff" * 4)
    assert "snapshot" in info.value.details
    assert_still_serving(client, session, f0)


def test_step_and_observe_before_reset_are_failed_precondition(client, session):
    fresh = client.create_session(None).session_id
    try:
        with pytest.raises(errors.FailedPrecondition):
            client.step(fresh, "pd_joint_delta_pos", GOOD_JOINT_DELTA)
        with pytest.raises(errors.FailedPrecondition):
            client.observe(fresh)
        assert_still_serving(client, session, frame(client, session))
        assert client.reset(fresh, seed=0).stamp.frame_id == 0  # and the fresh session recovers
        assert client.step(fresh, "pd_joint_delta_pos", GOOD_JOINT_DELTA).stamp.frame_id == 1
    finally:
        client.close_session(fresh)


@pytest.fixture(scope="module")
def small_server():
    """A second server allowing only 2 sessions."""
    srv = start_server(max_sessions=2)
    yield srv
    stop_server(srv)


def test_too_many_sessions_is_resource_exhausted(small_server):
    with Client(small_server.address) as client:
        assert client.server_info().limits.max_sessions == 2
        first = client.create_session(None).session_id
        second = client.create_session(None).session_id
        with pytest.raises(errors.ResourceExhausted):
            client.create_session(None)
        assert client.server_info().limits.active_sessions == 2
        client.reset(first, seed=0)
        assert client.step(first, "pd_joint_delta_pos", GOOD_JOINT_DELTA).stamp.frame_id == 1
        client.close_session(second)  # freeing a slot makes room again
        third = client.create_session(None).session_id
        client.reset(third, seed=0)
        client.close_session(third)
        client.close_session(first)
        assert client.server_info().limits.active_sessions == 0

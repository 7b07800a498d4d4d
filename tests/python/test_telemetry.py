"""Telemetry: ZeroMQ PUB frames [topic "session/<id>", TelemetryFrame] for every Step."""
from __future__ import annotations

import time

import pytest
import zmq

from culinarycut.v1 import simulator_pb2

GOOD_JOINT_DELTA = [0.01, 0, 0, 0, 0, 0, 0]  # rad


@pytest.fixture
def subscriber():
    ctx = zmq.Context()
    sock = ctx.socket(zmq.SUB)
    sock.setsockopt(zmq.LINGER, 0)
    yield sock
    sock.close()
    ctx.term()


def receive_all(sock, quiet_s: float = 1.0) -> list[list[bytes]]:
    """All messages until none arrives for quiet_s seconds."""
    messages = []
    while sock.poll(int(quiet_s * 1000)):
        messages.append(sock.recv_multipart())
    return messages


def test_server_info_advertises_the_endpoint(client, telemetry_endpoint):
    info = client.server_info()
    assert "telemetry" in info.capabilities
    assert info.telemetry_endpoint == telemetry_endpoint


def test_step_frames_are_published_per_session(client, session, subscriber, telemetry_endpoint):
    other = client.create_session(None).session_id  # its frames must not reach our subscription
    client.reset(other, seed=0)
    topic = f"session/{session}".encode()
    subscriber.setsockopt(zmq.SUBSCRIBE, topic)
    subscriber.connect(telemetry_endpoint)
    time.sleep(0.5)  # ZeroMQ "slow joiner": the subscription needs a moment to reach the publisher

    sent = {}
    for _ in range(10):
        response = client.step(session, "pd_joint_delta_pos", GOOD_JOINT_DELTA)
        sent[response.stamp.frame_id] = response
        client.step(other, "pd_joint_delta_pos", GOOD_JOINT_DELTA)
    client.close_session(other)

    messages = receive_all(subscriber)
    assert len(messages) >= 5, f"expected frames for most of 10 steps, got {len(messages)}"
    frame_ids = []
    for parts in messages:
        assert len(parts) == 2, f"expected [topic, frame], got {len(parts)} parts"
        assert parts[0] == topic
        frame = simulator_pb2.TelemetryFrame.FromString(parts[1])
        assert frame.session_id == session
        assert len(frame.qpos) == 7 and len(frame.qvel) == 7 and len(frame.tcp_pose) == 7
        frame_ids.append(frame.stamp.frame_id)
        step = sent.get(frame.stamp.frame_id)
        if step is not None:  # the published state is the one the Step returned
            assert list(frame.qpos) == list(step.observation.agent.qpos)
            assert list(frame.tcp_pose) == list(step.observation.tcp_pose)
    assert all(b > a for a, b in zip(frame_ids, frame_ids[1:])), frame_ids
    assert frame_ids[-1] == max(sent)

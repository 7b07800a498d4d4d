"""Telemetry: ZeroMQ PUB frames [the session's telemetry topic, TelemetryFrame] for every Step; the topic is
random and unrelated to the session id, so a subscriber to everything learns no handle on any session."""
from __future__ import annotations

import subprocess
import time

import pytest
import zmq

from culinarycut import errors
from culinarycut.launch import ServerProcess, server_binary
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


def test_step_frames_are_published_per_session(client, subscriber, telemetry_endpoint):
    handshake = client.create_session(None)
    session = handshake.session_id
    client.reset(session, seed=0)
    other = client.create_session(None).session_id  # its frames must not reach our subscription
    client.reset(other, seed=0)
    topic = handshake.telemetry_topic.encode()
    assert topic.startswith(b"telemetry/") and session[2:].encode() not in topic
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
        assert frame.session_id == "" and session.encode() not in parts[1]
        assert len(frame.qpos) == 7 and len(frame.qvel) == 7 and len(frame.tcp_pose) == 7
        frame_ids.append(frame.stamp.frame_id)
        step = sent.get(frame.stamp.frame_id)
        if step is not None:  # the published state is the one the Step returned
            assert list(frame.qpos) == list(step.observation.agent.qpos)
            assert list(frame.tcp_pose) == list(step.observation.tcp_pose)
    assert all(b > a for a, b in zip(frame_ids, frame_ids[1:])), frame_ids
    assert frame_ids[-1] == max(sent)


def test_a_stranger_reading_every_topic_gets_no_session_handle(client, subscriber, telemetry_endpoint):
    session = client.create_session(None).session_id
    subscriber.setsockopt(zmq.SUBSCRIBE, b"")  # everything
    subscriber.connect(telemetry_endpoint)
    time.sleep(0.5)
    client.reset(session, seed=0)
    client.step(session, "pd_joint_delta_pos", GOOD_JOINT_DELTA)
    messages = receive_all(subscriber)
    assert messages and all(session.encode() not in b"".join(parts) for parts in messages)
    for topic in {parts[0].decode() for parts in messages}:
        for handle in (topic, topic.split("/", 1)[1], "s-" + topic.split("/", 1)[1]):
            with pytest.raises(errors.NotFound):
                client.step(handle, "pd_joint_delta_pos", GOOD_JOINT_DELTA)
    client.close_session(session)


@pytest.mark.parametrize("endpoint, message", [
    ("epgm://eth0;239.192.7.7:47003", "transport 'epgm' is not allowed"),
    ("udp://127.0.0.1:47003", "transport 'udp' is not allowed"),
    ("tcp://0.0.0.0:0", "not on loopback"),
])
def test_telemetry_endpoints_off_this_machine_are_refused_at_start(endpoint, message):
    refused = subprocess.run([str(server_binary()), "--listen", "127.0.0.1:0", "--telemetry", endpoint],
                             capture_output=True, text=True, timeout=30)
    assert refused.returncode != 0 and message in refused.stderr, refused.stderr


def test_telemetry_is_off_unless_asked_for(client):
    with ServerProcess(server_binary(), max_sessions=1) as server:  # the launcher asks for it
        assert server.telemetry
    started = subprocess.Popen([str(server_binary()), "--listen", "127.0.0.1:0"], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    try:
        printed = [started.stdout.readline() for _ in range(3)]  # model, listening, version: 3 lines at least
    finally:
        started.terminate()
        started.wait(timeout=10)
    assert any("listening on" in line for line in printed) and not any("telemetry on" in line for line in printed)

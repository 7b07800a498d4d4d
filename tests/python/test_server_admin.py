"""Server-level behaviour over the wire: health service, the resolved scene, bad flags."""
from __future__ import annotations

import subprocess

import grpc
import pytest

from culinarycut import Client
from culinarycut.launch import server_binary

SERVING = b"\x08\x01"  # grpc.health.v1.HealthCheckResponse{status: SERVING}


def health_check(address: str, service: str) -> bytes:
    """grpc.health.v1.Health/Check with a hand-encoded request (Debian ships no grpc_health package)."""
    request = b"\x0a" + bytes([len(service)]) + service.encode() if service else b""
    with grpc.insecure_channel(address) as channel:
        check = channel.unary_unary("/grpc.health.v1.Health/Check")
        return check(request, timeout=10)


@pytest.mark.parametrize("service", ["", "culinarycut.v1.Simulator"])
def test_health_service_reports_serving(address, service):
    assert health_check(address, service) == SERVING


def test_resolved_scene_echoes_every_setting(client):
    response = client.create_session({"quality": "fine", "seed": 7, "robot": {"controlFrequencyHz": 10}})
    try:
        resolved = response.resolved_scene
        assert (resolved.quality, resolved.seed, resolved.robot.control_frequency_hz) == ("fine", 7, 10)
        assert resolved.robot.physics_frequency_hz == 500 and len(resolved.robot.initial_qpos) == 7
        assert (response.stamp.frame_id, response.stamp.sim_time) == (0, 0.0)
    finally:
        client.close_session(response.session_id)


def test_a_scene_dict_with_unknown_fields_is_a_clear_client_error(address):
    with Client(address) as client, pytest.raises(ValueError, match="scene"):
        client.create_session({"robot": {"no_such_field": 1}})


@pytest.mark.parametrize("args, message", [
    (["--listen", "127.0.0.1:99999"], "0..65535"),
    (["--listen", "127.0.0.1"], "host:port"),
    (["--idle-timeout", "-1"], "idle-timeout"),
    (["--max-sessions", "0"], "max-sessions"),
])
def test_bad_flags_exit_non_zero_with_a_message(args, message):
    result = subprocess.run([str(server_binary()), *args], capture_output=True, text=True, timeout=30)
    assert result.returncode != 0
    assert message in result.stdout + result.stderr

"""A policy written in C++ plays a suite through the runner: the example oracle_policy_server (client/cpp/examples,
built on the C++ client library) served over the policy protocol, `culinarycut bench run smoke --policy grpc`
against a real culinarycut-server. The oracle plans on the simulator with the session the runner lends it."""
from __future__ import annotations

import os
import signal
import subprocess

import pytest

from bench_cli import bench
from stored_runs import rows

# The smoke suite's ratio cut, once: CI's share of the suite (docs/policy_protocol.md has the whole suite's run).
RATIO_TASK = ["--tasks", "cucumber/normal/ratio-*", "--trials", "1", "--workers", "1", "--no-progress"]


@pytest.fixture(scope="module")
def cpp_policy_server():
    """The C++ example serving on a free port; yields host:port."""
    binary = os.environ.get("CULINARYCUT_ORACLE_POLICY_SERVER")
    if not binary:
        pytest.fail("CULINARYCUT_ORACLE_POLICY_SERVER is not set: run this test through ctest, which builds the example")
    proc = subprocess.Popen([binary, "--listen", "127.0.0.1:0"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True)
    try:
        first = proc.stdout.readline()
        assert first.startswith("serving policy oracle-cpp 1 (pd_ee_pose_quat, needs the session) on "), \
            first + proc.stdout.read()
        yield first.split()[-1]
    finally:
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(30) == 0, proc.stdout.read()


def test_a_cpp_policy_server_plays_the_smoke_suite(cpp_policy_server, address, tmp_path):
    out = tmp_path / "run"
    bench("run", "smoke", "--policy", "grpc", "--policy-url", cpp_policy_server, "--server", address,
          "--out", str(out), *RATIO_TASK)
    (row,) = rows(out)
    assert row["task"] == "cucumber/normal/ratio-0.3-left"
    assert (row["outcome"], row["error"]) == ("success", ""), row
    assert (row["policy"], row["policy_name"], row["policy_version"]) == ("grpc", "oracle-cpp", "1")
    assert row["steps"] > 20  # one Act per control step


def test_act_for_an_episode_never_reset_is_refused_by_name(cpp_policy_server):
    import grpc

    from culinarycut.v1 import policy_pb2, policy_pb2_grpc

    with grpc.insecure_channel(cpp_policy_server) as channel:
        stub = policy_pb2_grpc.PolicyStub(channel)
        metadata = stub.GetPolicyMetadata(policy_pb2.PolicyMetadataRequest(), timeout=10)
        assert (metadata.action_dim, metadata.needs_session) == (7, True)
        with pytest.raises(grpc.RpcError) as refused:
            stub.Act(policy_pb2.PolicyActRequest(episode_id="nobody"), timeout=10)
        assert refused.value.code() == grpc.StatusCode.FAILED_PRECONDITION
        assert "no ResetPolicy started" in refused.value.details()
        with pytest.raises(grpc.RpcError) as refused:
            stub.ResetPolicy(policy_pb2.PolicyResetRequest(episode_id="e", instruction="cut"), timeout=10)
        assert refused.value.code() == grpc.StatusCode.INVALID_ARGUMENT and "session" in refused.value.details()

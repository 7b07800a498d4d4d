"""`culinarycut bench run --policy grpc --policy-url` through the real path: a culinarycut-server, the scripted
oracle served over the policy protocol by `culinarycut policy serve oracle` (it plans on the simulator with
the session the runner sends it), a policy server that is not listening (the pre-flight check's exit 1) and
a policy that answers the wrong shape (its episode stored as a policy_error that names the problem)."""
from __future__ import annotations

import socket
import subprocess
import sys

import numpy as np
import pytest

from bench_cli import bench
from culinarycut.policy_server import serve
from stored_runs import rows

ONE_EPISODE = ["--tasks", "cucumber/normal/ratio-*", "--trials", "1", "--workers", "1", "--no-progress"]


@pytest.fixture(scope="module")
def served_oracle():
    """`culinarycut policy serve oracle` on a free port; yields host:port."""
    proc = subprocess.Popen([sys.executable, "-m", "culinarycut", "policy", "serve", "oracle", "--listen",
                             "127.0.0.1:0"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        first = proc.stdout.readline()
        assert first.startswith("serving policy oracle 1 (pd_ee_pose_quat, needs the session) on "), \
            first + proc.stdout.read()
        yield first.split()[-1]
    finally:
        proc.terminate()
        assert proc.wait(30) == 0, proc.stdout.read()


def test_the_oracle_served_over_the_protocol_cuts(served_oracle, address, tmp_path):
    out = tmp_path / "run"
    bench("run", "smoke", "--policy", "grpc", "--policy-url", served_oracle, "--server", address, "--out", str(out),
          *ONE_EPISODE)
    (row,) = rows(out)
    assert (row["outcome"], row["end_reason"], row["error"]) == ("success", "success", ""), row["error"]
    assert (row["policy"], row["policy_name"], row["policy_version"]) == ("grpc", "oracle", "1")
    assert row["steps"] > 20  # one Act per step: the oracle answers one action at a time


def test_a_policy_server_that_is_not_listening_stops_the_run_before_any_episode(address, tmp_path):
    with socket.socket() as probe:  # a port nobody listens on
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    done = bench("run", "smoke", "--policy", "grpc", "--policy-url", f"127.0.0.1:{port}", "--policy-option",
                 "retries=0", "--server", address, "--out", str(tmp_path / "run"), *ONE_EPISODE, check=False)
    assert done.returncode == 1, done.stdout + done.stderr
    assert f"policy grpc is not ready, no episode was run: PolicyServerUnreachable: policy server 127.0.0.1:{port} " \
           "does not answer" in done.stderr and "Traceback" not in done.stderr
    assert rows(tmp_path / "run") == []


def test_a_wrong_shape_is_stored_as_a_policy_error_naming_it(address, tmp_path):
    server, port = serve(lambda observation, instruction: np.zeros(5), metadata={"name": "five-values"})
    try:
        done = bench("run", "smoke", "--policy", "grpc", "--policy-url", f"127.0.0.1:{port}", "--server", address,
                     "--out", str(tmp_path / "run"), *ONE_EPISODE, check=False)
    finally:
        server.stop(0)
    assert done.returncode == 3, done.stdout + done.stderr  # every episode ran, some are stored as errors
    (row,) = rows(tmp_path / "run")
    assert (row["outcome"], row["end_reason"], row["steps"], row["policy_name"]) == \
        ("error", "policy_error", 0, "five-values")
    assert row["error"] == (f"act at step 0: PolicyServerError: policy server 127.0.0.1:{port}: Act answered actions "
                            "of shape [5]; expected [6] or [1, 6] (pd_ee_delta_pose takes 6 values)")

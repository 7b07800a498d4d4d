"""Transient server failures during generation, injected by a gRPC proxy in front of the real server:
a failure the retries outlast is not a rejected episode; it leaves the job without a row, the CLI
exits non-zero, the card's filter rate leaves it out, and running the same command again runs it."""
from __future__ import annotations

import subprocess
import sys
import threading
from concurrent import futures

import grpc
from culinarycut.datasets.card import write_card
from culinarycut.datasets.generate import RetryPolicy, run_job
from culinarycut.datasets.jobs import DatasetConfig, make_jobs
from culinarycut.datasets.store import GenerationStore

MESSAGE_BYTES = 64 * 1024 * 1024
STEP = "/culinarycut.v1.Simulator/Step"
INSTRUCTIONS = "/culinarycut.v1.Tasks/GenerateInstructions"
QUICK_RETRY = RetryPolicy(attempts=2, backoff_s=0.01)


class FaultProxy(grpc.GenericRpcHandler):
    """Forwards every call to `upstream` as bytes, except that calls number `failing` (0-based, counted
    per method) of `method` are answered with `code` without reaching the server."""

    def __init__(self, upstream: str, method: str, code: grpc.StatusCode, failing):
        self.method, self.code, self.failing = method, code, failing
        self.calls = self.injected = 0
        self.lock = threading.Lock()
        options = [("grpc.max_receive_message_length", MESSAGE_BYTES),
                   ("grpc.max_send_message_length", MESSAGE_BYTES)]
        self.channel = grpc.insecure_channel(upstream, options=options)
        self.server = grpc.server(futures.ThreadPoolExecutor(max_workers=8), options=options)
        self.server.add_generic_rpc_handlers([self])
        self.address = f"127.0.0.1:{self.server.add_insecure_port('127.0.0.1:0')}"
        self.server.start()

    def service(self, details):
        forward = self.channel.unary_unary(details.method)
        method = details.method

        def handle(request: bytes, context):
            if method == self.method:
                with self.lock:
                    fail = self.calls in self.failing
                    self.calls += 1
                    self.injected += fail
                if fail:
                    context.abort(self.code, "injected fault")
            try:
                return forward(request, timeout=context.time_remaining())
            except grpc.RpcError as err:
                context.abort(err.code(), err.details())

        return grpc.unary_unary_rpc_method_handler(handle)

    def close(self):
        self.server.stop(None)
        self.channel.close()


def _config(jobs: int) -> DatasetConfig:
    """Episodes cut short (15 steps): each ends as a quick 'truncated' rejection."""
    spec = {"style": "normal", "state": "ratio", "ratio": 0.3, "reference": "left", "target_object": "cucumber"}
    return DatasetConfig(name="faults", seed=5, tasks=(spec,), episodes_per_task=jobs, image_size=32,
                         cameras=("front",), max_episode_steps=15)


def test_a_fault_mid_episode_is_retried_from_the_seed(address, tmp_path):
    proxy = FaultProxy(address, STEP, grpc.StatusCode.RESOURCE_EXHAUSTED, failing={5})
    try:
        row = run_job(make_jobs(_config(1))[0], _config(1), tmp_path, proxy.address, QUICK_RETRY)
    finally:
        proxy.close()
    assert proxy.injected == 1
    assert row["reason"].startswith("truncated") and row["steps"] == 15, row
    assert not (tmp_path / "errors").exists()


def _generate(address: str, out, attempts: int = 2, *extra: str) -> subprocess.CompletedProcess:
    command = [sys.executable, "-m", "culinarycut", "data", "generate", "--out", str(out), "--server", address,
               "--styles", "normal", "--states", "ratio-0.3", "--episodes-per-task", "2", "--image-size", "32",
               "--cameras", "front", "--max-steps", "15", "--attempts", str(attempts), "--retry-backoff", "0.01",
               "--no-progress", *extra]
    return subprocess.run(command, capture_output=True, text=True, timeout=300)


def test_a_persistent_fault_leaves_the_job_for_the_next_run(address, tmp_path):
    out, code = tmp_path / "data", grpc.StatusCode.INTERNAL
    # the first job's instructions pass, the second job's fail on both tries
    proxy = FaultProxy(address, INSTRUCTIONS, code, failing=range(1, 100))
    try:
        failed = _generate(proxy.address, out)
    finally:
        proxy.close()
    assert failed.returncode == 1, failed.stdout + failed.stderr
    assert "1 jobs failed with transient server errors" in failed.stderr and proxy.injected == 2
    with GenerationStore(out) as store:
        rows = store.rows()
    assert len(rows) == 1 and not any(r["reason"].startswith("server_error") for r in rows)
    errors = sorted((out / "errors").glob("*.json"))
    assert len(errors) == 1 and code.name in errors[0].read_text()
    card = write_card(out, tmp_path / "card").read_text()
    assert "0 kept trajectories of 1 generated" in card and "1 jobs failed with transient server errors" in card

    resumed = _generate(address, out)
    assert resumed.returncode == 0, resumed.stdout + resumed.stderr
    assert "this run: 1 in" in resumed.stdout
    with GenerationStore(out) as store:
        assert [r["reason"].split(":")[0] for r in store.rows()] == ["truncated", "truncated"]
    assert not any((out / "errors").glob("*.json"))
    assert "transient" not in write_card(out, tmp_path / "card").read_text()


def test_bad_retry_options_are_refused(address, tmp_path):
    result = _generate(address, tmp_path / "data", attempts=0)
    assert result.returncode == 2 and "--attempts" in result.stderr, result.stderr
    result = _generate(address, tmp_path / "data", 2, "--scenes", "table,moon")
    assert result.returncode == 2 and "--scenes: moon; choose from table, kitchen" in result.stderr, result.stderr
    assert not (tmp_path / "data").exists()  # refused before anything was written


def test_progress_moves_with_each_episode_not_each_shard(address, tmp_path, capfd, monkeypatch):
    """Three episodes in one shard: the bar shows 1/3 or 2/3 before the shard returns."""
    from culinarycut.datasets import generate as generate_module
    monkeypatch.setattr(generate_module, "PROGRESS_POLL_S", 0.05)  # an episode takes longer than this
    summary = generate_module.generate(_config(3), tmp_path / "data", [address], shard_size=3, progress=True)
    assert summary.ran == 3
    err = capfd.readouterr().err
    assert "1/3" in err or "2/3" in err, err
    assert "episodes/h" in err and "3/3" in err

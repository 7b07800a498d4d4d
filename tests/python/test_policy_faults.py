"""Model servers that fail mid-episode: killed (REST and websocket) or frozen, the episode ends as a
policy_error within the timeouts, never a hung run, and the next episode with a working server runs."""
from __future__ import annotations

import signal
import threading
import time

import pytest

import policy_support
from culinarycut.bench.episode import EpisodeOptions, run_episode
from culinarycut.bench.episode_scene import suite_episodes
from culinarycut.bench.suite import load_suite
from culinarycut_policies.standins.process import StandinProcess

STEPS = 40
KILL_AFTER = 3
# Generous against a loaded CI machine; the frozen server's test shortens the query timeout itself.
TIMEOUTS = {"connect_timeout_s": 2.0, "query_timeout_s": 5.0, "retries": 2, "backoff_s": 0.2}
ADAPTERS = {
    "openvla": ("culinarycut_policies.openvla:OpenVLAPolicy", "http"),
    "octo": ("culinarycut_policies.octo:OctoPolicy", "ws"),
}


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict:
    folder = tmp_path_factory.mktemp("policy-faults")
    return {"statistics": policy_support.write_statistics(folder), "suite": policy_support.write_suite(folder, STEPS)}


def episode(files, address, model: str, url: str, **timeouts) -> tuple[dict, float]:
    spec = suite_episodes(load_suite(str(files["suite"])))[0]
    options = {"url": url, "statistics": str(files["statistics"]), "unnorm_key": policy_support.DELTA_KEY,
               "camera_size": 64, **TIMEOUTS, **timeouts}
    started = time.monotonic()
    result = run_episode(spec, address, EpisodeOptions(policy=ADAPTERS[model][0], policy_options=options,
                                                       act_timeout_s=30.0))
    return result.row, time.monotonic() - started


def run_while(standin, files, address, model, fault, **timeouts) -> tuple[dict, float]:
    """The episode on a thread; `fault(standin)` once the stand-in has answered KILL_AFTER queries."""
    out = {}
    thread = threading.Thread(target=lambda: out.update(zip(("row", "wall"), episode(files, address, model,
                                                                                     standin.url, **timeouts))))
    thread.start()
    standin.wait_for_queries(KILL_AFTER)
    fault(standin)
    thread.join(60)
    assert not thread.is_alive(), "the episode hung after its model server failed"
    return out["row"], out["wall"]


def standin_args(model: str, files) -> list[str]:
    return ["--statistics", str(files["statistics"])] if model == "openvla" else []


@pytest.mark.parametrize("model", sorted(ADAPTERS))
def test_killed_model_server_is_a_policy_error_and_the_next_episode_runs(files, address, model):
    standin = StandinProcess(model, *standin_args(model, files))
    try:
        row, wall = run_while(standin, files, address, model, lambda s: s.signal(signal.SIGKILL))
    finally:
        standin.close()
    assert (row["outcome"], row["end_reason"]) == ("error", "policy_error"), row
    assert "act at step" in row["error"] and ("PolicyServerUnreachable" in row["error"]), row["error"]
    # The stand-in logs a query before answering it: the kill may come before or after that answer.
    assert KILL_AFTER - 1 <= row["steps"] < STEPS and wall < 30
    replacement = StandinProcess(model, *standin_args(model, files))
    try:
        row, _ = episode(files, address, model, replacement.url)
    finally:
        replacement.close()
    assert (row["end_reason"], row["steps"], row["error"]) == ("step_limit", STEPS, "")


def test_frozen_model_server_times_out(files, address):
    standin = StandinProcess("octo")
    try:
        row, wall = run_while(standin, files, address, "octo", lambda s: s.signal(signal.SIGSTOP),
                              query_timeout_s=2.0)
    finally:
        standin.close()
    assert row["end_reason"] == "policy_error" and "did not answer within 2 s" in row["error"], row["error"]
    assert wall < 20


def test_unreachable_model_server_fails_at_reset(files, address):
    row, wall = episode(files, address, "octo", "ws://127.0.0.1:9")
    assert row["end_reason"] == "policy_error" and row["error"].startswith("reset: PolicyServerUnreachable")
    assert "no connection after 3 attempts" in row["error"] and wall < 20

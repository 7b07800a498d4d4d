"""Every adapter drives a short draft episode on a real culinarycut-server while its stand-in model server
answers over a real loopback socket; and `culinarycut bench run --policy openvla --policy-url` as a user
runs it, with the adapters registered through the policies package's entry points."""
from __future__ import annotations

import json
import os
import shutil
import sqlite3
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import policy_support
from culinarycut import Client
from culinarycut.bench.episode import EpisodeOptions, run_episode
from culinarycut.bench.episode_scene import suite_episodes
from culinarycut.bench.suite import load_suite
from culinarycut_policies.standins.launch import make_standin

STEPS = 6
CAMERA = 64  # small cameras: the adapters resize to the model's size anyway


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict:
    folder = tmp_path_factory.mktemp("policy-episodes")
    return {"statistics": policy_support.write_statistics(folder), "suite": policy_support.write_suite(folder, STEPS),
            "folder": folder}


@pytest.fixture(scope="module")
def spec(files):
    return suite_episodes(load_suite(str(files["suite"])))[0]


def run(spec, address, files, model: str, policy: str, unnorm_key: str | None = None, **options):
    """(row, the fake model's last request, latency summary, result) of one episode with the stand-in of
    `model`; the episode must have run all its steps without error."""
    statistics = str(files["statistics"])
    server, fake = make_standin(model, statistics, unnorm_key)
    server.start()
    try:
        policy_options = {"url": server.url, "camera_size": CAMERA, **options}
        if unnorm_key is not None:
            policy_options.update(statistics=statistics, unnorm_key=unnorm_key)
        result = run_episode(spec, address, EpisodeOptions(policy=policy, policy_options=policy_options))
    finally:
        server.stop()
    row = result.row
    assert row["error"] == "" and row["end_reason"] == "step_limit", row["error"]
    assert row["steps"] == STEPS
    return row, fake.last_request, json.loads(row["policy_latency"]), result


def test_openvla_one_action_per_query(spec, address, files):
    row, request, latency, _ = run(spec, address, files, "openvla", "culinarycut_policies.openvla:OpenVLAPolicy",
                                   policy_support.DELTA_KEY, center_crop=True)
    assert latency["queries"] == STEPS
    assert request["image"].shape == (224, 224, 3) and request["image"].dtype == np.uint8
    assert request["unnorm_key"] == policy_support.DELTA_KEY and request["instruction"] == row["instruction"]


def test_openvla_oft_executes_its_chunk_open_loop(spec, address, files):
    row, request, latency, _ = run(spec, address, files, "openvla-oft", "culinarycut_policies.openvla_oft:OpenVLAOFTPolicy",
                                   policy_support.DELTA_KEY, execute_steps=4)
    assert latency["queries"] == 2  # steps 0-3 from the first chunk, 4-5 from the second
    assert request["full_image"].shape == request["wrist_image"].shape == (224, 224, 3)
    assert request["state"].shape == (8,) and request["state"][6:].tolist() == [0.0, 0.0]  # no gripper
    assert 0.05 < request["state"][2] < 1.0  # the knife's TCP height (m), unnormalised on the wire


@pytest.mark.parametrize("execution, queries", [("ensemble", STEPS), ("receding", 3)])
def test_octo_history_and_execution(spec, address, files, execution, queries):
    row, request, latency, _ = run(spec, address, files, "octo", "culinarycut_policies.octo:OctoPolicy",
                                   policy_support.DELTA_KEY, execution=execution, exec_horizon=2,
                                   wrist_camera="wrist")
    assert latency["queries"] == queries
    observation = request["observation"]
    assert observation["image_primary"].shape == (1, 2, 256, 256, 3)
    assert observation["image_wrist"].shape == (1, 2, 128, 128, 3)
    assert observation["timestep_pad_mask"].tolist() == [[True, True]] and request["prompt"] == row["instruction"]


@pytest.mark.parametrize("normalization", ["none", "bounds"])
def test_rdt_holds_the_pose_it_is_given_back(spec, address, files, normalization):
    # The stand-in predicts the state it was sent: (normalise ->) unified vector -> (un-normalise ->) 6-D
    # rotation -> quaternion must bring the knife back to where it is, so it stays put.
    key = policy_support.RDT_KEY if normalization == "bounds" else None
    row, request, latency, result = run(spec, address, files, "rdt", "culinarycut_policies.rdt:RDTPolicy", key,
                                        normalization=normalization)
    assert latency["queries"] == 1
    assert [None if i is None else i.shape for i in request["images"]] == \
        [None, None, None, (384, 384, 3), (384, 384, 3), None]
    assert request["ctrl_freq"] == pytest.approx(row["steps"] / row["sim_time_s"], rel=1e-3)
    assert request["state_elem_mask"][0, 10] == 0 and request["state_elem_mask"][0, 30] == 1
    z = np.asarray(result.trace["tcp_z_m"])
    assert np.ptp(z) < 0.002, z


def test_rdt_sends_precomputed_language_embeddings(spec, address, files):
    with Client(address) as client:
        instruction = client.tasks.generate_instructions(spec.task.cut_spec(), seed=spec.seed, count=1,
                                                         split=spec.language)[0]
    embeddings = files["folder"] / "embeddings.npz"
    np.savez(embeddings, **{instruction: np.full((5, 4096), 0.25, dtype=np.float32)})
    row, request, _, _ = run(spec, address, files, "rdt", "culinarycut_policies.rdt:RDTPolicy",
                             language_embeddings=str(embeddings))
    assert request["text_embeds"].shape == (1, 5, 4096) and "instruction" not in request
    other = files["folder"] / "other.npz"
    np.savez(other, **{"cut something else": np.zeros((5, 4096), dtype=np.float32)})
    server, _ = make_standin("rdt")
    server.start()
    try:
        result = run_episode(spec, address, EpisodeOptions(
            policy="culinarycut_policies.rdt:RDTPolicy",
            policy_options={"url": server.url, "language_embeddings": str(other)}))
    finally:
        server.stop()
    assert result.row["end_reason"] == "policy_error" and "no language embedding for" in result.row["error"]


def test_openpi_replans_every_five_steps(spec, address, files):
    row, request, latency, _ = run(spec, address, files, "openpi", "culinarycut_policies.openpi:OpenPIPolicy")
    assert latency["queries"] == 2
    assert request["observation/image"].shape == (224, 224, 3) and request["prompt"] == row["instruction"]
    assert request["observation/state"].shape == (8,)


@pytest.fixture(scope="module")
def installed_policies(tmp_path_factory) -> Path:
    """policies/ installed as a user installs it (its entry points are how --policy finds the adapters)."""
    target, source = tmp_path_factory.mktemp("site"), tmp_path_factory.mktemp("source") / "policies"
    # A copy: the build writes build/ and egg-info into the folder it builds.
    shutil.copytree(policy_support.POLICIES, source, ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    done = subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
                           "--no-deps", "--no-build-isolation", "--no-index", "--target", str(target), str(source)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return target


@pytest.mark.parametrize("model, unnorm_key", [("openvla", policy_support.DELTA_KEY),
                                               ("octo", policy_support.DELTA_KEY),
                                               ("rdt", None), ("openpi", None)])
def test_bench_run_with_policy_url(files, address, installed_policies, tmp_path, model, unnorm_key):
    server, _ = make_standin(model, str(files["statistics"]))
    server.start()
    out = tmp_path / "run"
    options = [f"camera_size={CAMERA}"]
    if unnorm_key:
        options += [f"statistics={files['statistics']}", f"unnorm_key={unnorm_key}"]
    try:
        env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(installed_policies), os.environ.get("PYTHONPATH", "")])}
        done = subprocess.run(
            [sys.executable, "-m", "culinarycut", "bench", "run", str(files["suite"]), "--policy", model,
             "--policy-url", server.url, *[a for o in options for a in ("--policy-option", o)],
             "--server", address, "--workers", "1", "--out", str(out), "--no-progress"],
            capture_output=True, text=True, timeout=300, env=env)
    finally:
        server.stop()
    assert done.returncode == 0, done.stdout + done.stderr
    db = sqlite3.connect(out / "results.sqlite")
    try:
        end_reason, steps, latency, options = db.execute(
            "SELECT end_reason, steps, policy_latency, policy_options FROM episodes").fetchone()
    finally:
        db.close()
    assert (end_reason, steps) == ("step_limit", STEPS)
    assert json.loads(latency)["queries"] >= 1 and json.loads(options)["url"] == server.url


def test_a_run_folder_from_before_policy_latency_resumes(tmp_path):
    from culinarycut.bench.store import EPISODE_COLUMNS, ResultStore
    old = ", ".join(f"{n} {k}" for n, k, _ in EPISODE_COLUMNS if n != "policy_latency")
    db = sqlite3.connect(tmp_path / "results.sqlite")
    db.execute(f"CREATE TABLE episodes ({old}, PRIMARY KEY (task, trial))")
    db.execute("INSERT INTO episodes (suite, task, trial, seed, outcome) VALUES ('s', 'a', 0, 1, 'success')")
    db.commit()
    db.close()
    with ResultStore(tmp_path) as store:
        assert store.record({"suite": "s", "task": "a", "trial": 1, "seed": 2, "outcome": "failure",
                             "policy_latency": '{"queries": 3}'})
        rows = store.episodes()
    assert [(r["trial"], r["policy_latency"]) for r in rows] == [(0, None), (1, '{"queries": 3}')]

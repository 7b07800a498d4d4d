"""The learned policy (learning/) end to end, the way a user runs it: two draft episodes generated
(`culinarycut data generate`, front and wrist cameras at 32 px; a strawberry, the smallest food and the
cheapest to simulate: seconds where a cucumber takes a minute) and exported (robomimic HDF5), a few
training steps (`python -m culinarycut_learning train`), the checkpoint served (`... serve`) behind
openpi's websocket protocol, and one short episode of a suite through the benchmark runner with the
openpi adapter's defaults (`--policy openpi --policy-url ws://...`), stored without a policy error.
Then reproducibility: the same seed gives the same weights (another seed does not), and a run killed
with SIGKILL between checkpoints and started again resumes to the weights of an uninterrupted run."""
from __future__ import annotations

import json
import os
import signal
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest
import torch

REPO_ROOT = Path(__file__).resolve().parents[2]
SIZE = 32   # pixels: the cameras and the model's images
TRAIN = ["--steps", "4", "--batch-size", "4", "--image-size", str(SIZE), "--threads", "1", "--save-every", "2",
         "--log-every", "1", "--warmup-steps", "1", "--no-progress"]
SUITE = """name = "learning-e2e"
description = "one short draft episode of the trained policy"
trials = 1
max_episode_steps = 15
quality = "draft"

[[tasks]]
food = "strawberry"
state = "middle"
"""


def environment() -> dict:
    """This interpreter's environment, with learning/ importable where it is not installed."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO_ROOT / "learning"), env.get("PYTHONPATH")]))
    return env


def run(*command, env: dict | None = None, timeout_s: float = 300) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, *map(str, command)], capture_output=True, text=True, timeout=timeout_s,
                          env=env or environment(), cwd=REPO_ROOT)


def ok(result: subprocess.CompletedProcess) -> subprocess.CompletedProcess:
    assert result.returncode == 0, f"{' '.join(result.args)} exited {result.returncode}:\n{result.stdout}\n{result.stderr}"
    return result


def train(export: Path, out: Path, *extra, env: dict | None = None) -> subprocess.CompletedProcess:
    return run("-m", "culinarycut_learning", "train", "--data", export, "--out", out, *TRAIN, *extra, env=env)


def weights(run_folder: Path) -> dict:
    return torch.load(run_folder / "checkpoint.pt", map_location="cpu")["model"]


def same(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(torch.equal(a[k], b[k]) for k in a)


@pytest.fixture(scope="module")
def export(address, tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("learning")
    ok(run("-m", "culinarycut", "data", "generate", "--out", root / "data", "--food", "strawberry", "--styles", "normal",
           "--states", "middle",
           "--episodes-per-task", "2", "--cameras", "front,wrist", "--image-size", SIZE, "--scenes", "table",
           "--server", address, "--no-progress"))
    ok(run("-m", "culinarycut", "data", "export", root / "data", "--out", root / "export", "--format", "robomimic"))
    return root / "export"


@pytest.fixture(scope="module")
def trained(export) -> Path:
    out = export.parent / "run-a"
    result = ok(train(export, out))
    assert "4 steps (from 0)" in result.stdout, result.stdout
    return out


def test_the_trained_policy_runs_a_suite_episode_through_the_openpi_adapter(trained, address, tmp_path):
    server = subprocess.Popen([sys.executable, "-m", "culinarycut_learning", "serve", "--checkpoint", trained,
                               "--port", "0"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              env=environment(), cwd=REPO_ROOT)
    try:
        first = server.stdout.readline()
        assert first.startswith("listening on ws://"), first + server.stdout.read()
        url = first.split()[2]
        suite = tmp_path / "learning-e2e.toml"
        suite.write_text(SUITE)
        result = run("-m", "culinarycut", "bench", "run", suite, "--policy", "openpi", "--policy-url", url,
                     "--policy-option", f"camera_size={SIZE}", "--server", address, "--workers", "1",
                     "--out", tmp_path / "bench", "--no-progress")
    finally:
        server.send_signal(signal.SIGTERM)
        served_output = server.communicate(timeout=30)[0]
    assert server.returncode == 0, served_output
    ok(result)
    with sqlite3.connect(tmp_path / "bench" / "results.sqlite") as db:
        db.row_factory = sqlite3.Row
        rows = [dict(r) for r in db.execute("SELECT * FROM episodes")]
    assert len(rows) == 1, rows
    row = rows[0]
    assert row["outcome"] in ("success", "failure") and row["end_reason"] != "policy_error", row
    assert row["error"] in (None, ""), row["error"]
    assert row["policy_name"] == "openpi" and row["steps"] > 0
    assert '"queries": ' in row["policy_latency"] and '"queries": 0' not in row["policy_latency"], row["policy_latency"]


def test_the_same_seed_gives_the_same_weights(trained, export):
    again = export.parent / "run-b"
    ok(train(export, again))
    assert same(weights(trained), weights(again))
    other = export.parent / "run-seed-1"
    ok(train(export, other, "--seed", "1"))
    assert not same(weights(trained), weights(other))


def test_a_killed_run_resumes_to_the_weights_of_an_uninterrupted_one(trained, export):
    out = export.parent / "run-killed"
    killed = train(export, out, env={**environment(), "CULINARYCUT_LEARNING_KILL_AT_STEP": "3"})
    assert killed.returncode == -signal.SIGKILL, killed.stderr
    assert torch.load(out / "checkpoint.pt", map_location="cpu")["step"] == 2   # step 3's work was lost
    resumed = ok(train(export, out))
    assert "resuming" in resumed.stderr and "4 steps (from 2)" in resumed.stdout, resumed.stdout + resumed.stderr
    assert same(weights(trained), weights(out))
    # The log keeps one line per step, the killed run's step 3 replaced by the resumed one's.
    steps = [int(line.split('"step": ')[1].split(",")[0]) for line in (out / "log.jsonl").read_text().splitlines()]
    assert steps == [1, 2, 3, 4]
    # Another setting for the same folder is refused, naming it.
    refused = train(export, out, "--lr", "0.001")
    assert refused.returncode == 1 and "lr: 0.0003 -> 0.001" in refused.stderr, refused.stderr


def test_training_can_keep_to_some_cut_styles(trained, export):
    # The export holds normal cuts only: --styles normal trains on all of them, saw on none (refused, naming the
    # style), and a name that is no style is refused before any data is read.
    out = export.parent / "run-normal"
    ok(train(export, out, "--styles", "normal"))
    saved = json.loads((out / "config.json").read_text())
    assert saved["styles"] == ["normal"] and same(weights(trained), weights(out))
    none = train(export, export.parent / "run-saw", "--styles", "saw")
    assert none.returncode == 1 and "no episodes to train on in the styles saw" in none.stderr, none.stderr
    bad = train(export, export.parent / "run-bad", "--styles", "sawing")
    assert bad.returncode == 2 and "sawing is not a cut style" in bad.stderr, bad.stderr

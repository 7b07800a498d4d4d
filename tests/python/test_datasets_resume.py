"""`culinarycut data generate` killed with SIGKILL in the middle of a shard, then run again with the same
command: every job ends with exactly one row and one episode file, the episode finished before the
kill is not run again, and verify finds the dataset whole."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

from culinarycut.datasets.store import GenerationStore
from culinarycut.datasets.verify import verify

JOBS = 4


def _command(address: str, out) -> list[str]:
    return [sys.executable, "-m", "culinarycut", "data", "generate", "--out", str(out), "--server", address,
            "--styles", "normal", "--states", "ratio-0.3", "--episodes-per-task", str(JOBS),
            "--shard-size", str(JOBS), "--image-size", "32", "--no-progress"]


def test_kill_mid_shard_then_resume(address, tmp_path):
    out = tmp_path / "data"
    process = subprocess.Popen(_command(address, out), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    deadline = time.monotonic() + 240
    rows = out / "rows"
    while not (rows.is_dir() and any(rows.glob("*.json"))):
        assert process.poll() is None, f"generate ended before the kill:\n{process.stdout.read()}"
        assert time.monotonic() < deadline, "no episode finished in 240 s"
        time.sleep(0.1)
    os.kill(process.pid, signal.SIGKILL)
    process.wait()
    before = {p.name: p.read_text() for p in rows.glob("*.json")}
    assert 1 <= len(before) < JOBS, "the kill was not in the middle of the shard"
    with GenerationStore(out) as store:
        assert store.rows() == []  # the shard had not returned: only the row files hold its episodes

    resumed = subprocess.run(_command(address, out), capture_output=True, text=True, timeout=300)
    assert resumed.returncode == 0, resumed.stdout + resumed.stderr
    assert f"this run: {JOBS - len(before)} in" in resumed.stdout, resumed.stdout

    with GenerationStore(out) as store:
        stored = store.rows()
    assert len(stored) == len({r["key"] for r in stored}) == JOBS
    for name, text in before.items():  # not run again: its row is the one written before the kill
        assert (rows / name).read_text() == text
        assert json.loads(text)["key"] in {r["key"] for r in stored}
    files = sorted(p.name for p in (out / "episodes").iterdir())
    assert files == sorted(r["file"].split("/")[-1] for r in stored if r["kept"])
    report = verify(out, None, replay_count=0)
    assert report.ok, report.problems

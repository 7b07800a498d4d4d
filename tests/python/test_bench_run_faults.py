"""`culinarycut bench run` fails loudly, through real servers on loopback: a model server that does not
answer stops the run before its first episode; policy errors in a row stop it; the exit code says whether
every episode ran cleanly; a read-only folder, a full disk and a corrupt database give one line naming the
file and the command that resumes, with every stored row kept."""
from __future__ import annotations

import errno
import os
import re
import shutil
import socket
import sqlite3
import stat
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

import policy_support
from bench_cli import bench
from culinarycut import cli
from culinarycut.bench.store import ResultStore
from stored_runs import rows

TINY_SUITE = """name = "tiny"
description = "short draft episodes for the runner's fault tests"
trials = {trials}
max_episode_steps = 5
quality = "draft"

[[tasks]]
food = "cucumber"
state = "middle"
"""
NOBODY = 65534


def tiny_suite(folder: Path, trials: int) -> Path:
    path = folder / "tiny.toml"
    path.write_text(TINY_SUITE.format(trials=trials))
    return path


def free_port() -> int:
    """A loopback port nothing listens on (bound, then released)."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def error_lines(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if line.strip()]


@pytest.mark.parametrize("policy,scheme", [("openvla", "http"), ("octo", "ws")])
def test_a_model_server_that_does_not_answer_stops_the_run_before_its_first_episode(
        policy, scheme, address, tmp_path):
    url = f"{scheme}://127.0.0.1:{free_port()}"
    statistics = policy_support.write_statistics(tmp_path)
    out = tmp_path / "run"
    options = [f"statistics={statistics}", f"unnorm_key={policy_support.DELTA_KEY}", "retries=1", "backoff_s=0.1"]
    done = bench("run", str(tiny_suite(tmp_path, 3)), "--policy", policy, "--policy-url", url,
                 *[arg for option in options for arg in ("--policy-option", option)], "--server", address,
                 "--out", str(out), "--no-progress", check=False)
    assert done.returncode == 1, done.stderr
    (line,) = error_lines(done.stderr)  # one line, no traceback
    assert line.startswith(f"error: policy {policy} is not ready, no episode was run: PolicyServerUnreachable")
    assert url in line and "--policy-url" in line
    assert rows(out) == []


def test_a_quality_the_server_does_not_publish_stops_the_run_before_its_first_episode(address, tmp_path):
    suite = tiny_suite(tmp_path, 1)
    suite.write_text(suite.read_text().replace('quality = "draft"', 'quality = "ultra"'))
    out = tmp_path / "run"
    done = bench("run", str(suite), "--server", address, "--out", str(out), "--no-progress", check=False)
    assert done.returncode == 1, done.stderr
    (line,) = error_lines(done.stderr)  # one line, no traceback; the names come from the server
    assert line == (f"error: suite tiny, task cucumber/normal/middle: quality 'ultra' is not a preset of server "
                    f"{address} (it has draft, standard, fine)")
    assert rows(out) == []


def test_policy_errors_in_a_row_stop_the_run_and_say_how_to_rerun_them(address, tmp_path):
    out = tmp_path / "run"
    done = bench("run", str(tiny_suite(tmp_path, 4)), "--policy", "bench_policies:RaisingPolicy",
                 "--max-consecutive-policy-errors", "2", "--workers", "1", "--server", address, "--out", str(out),
                 "--no-progress", check=False)
    assert done.returncode == 1, done.stderr
    assert re.search(r"^error: stopped after 2 policy errors in a row \(--max-consecutive-policy-errors\), the last "
                     r"in cucumber/normal/middle trial \d: act at step 2: RuntimeError: the model ran out of ideas\. "
                     r"2 of 4 episodes are stored", done.stderr, re.M), done.stderr
    assert done.stderr.rstrip().endswith("--max-consecutive-policy-errors 2 --workers 1 --server "
                                         f"{address} --out {out} --no-progress --retry-errors")
    assert [r["end_reason"] for r in rows(out)] == ["policy_error"] * 2
    assert cli.build_parser().parse_args(["bench", "run", "smoke"]).max_consecutive_policy_errors == 5
    assert bench("run", "smoke", "--max-consecutive-policy-errors", "-1", check=False).returncode == 2


def test_a_run_that_ends_with_error_rows_exits_3_and_names_them(address, tmp_path):
    out = tmp_path / "run"
    argv = ["run", str(tiny_suite(tmp_path, 2)), "--policy", "bench_policies:RaisingPolicy",
            "--max-consecutive-policy-errors", "0", "--server", address, "--out", str(out), "--no-progress"]
    done = bench(*argv, check=False)
    assert done.returncode == 3, done.stderr
    assert "error: not every episode ran cleanly: 2 policy_error stored" in done.stderr
    assert done.stderr.rstrip().endswith("--no-progress --retry-errors")
    assert bench(*argv, check=False).returncode == 3  # a resume with nothing to run still says so


def test_a_corrupt_results_database_is_named_and_left_as_it_is(address, tmp_path):
    out = tmp_path / "run"
    out.mkdir()
    garbage = b"these bytes are no SQLite database " * 200
    (out / "results.sqlite").write_bytes(garbage)
    done = bench("run", str(tiny_suite(tmp_path, 1)), "--policy", "noop", "--server", address, "--out", str(out),
                 "--no-progress", check=False)
    assert done.returncode == 4, done.stderr
    (line,) = error_lines(done.stderr)
    assert line.startswith(f"error: {out / 'results.sqlite'} is not a readable SQLite database "
                           "(file is not a database); it was left as it is.")
    assert "resume with: culinarycut bench run" in line
    assert (out / "results.sqlite").read_bytes() == garbage


def test_a_report_of_a_corrupt_database_names_it_in_one_line(tmp_path):
    (tmp_path / "results.sqlite").write_bytes(b"these bytes are no SQLite database " * 200)
    done = bench("report", str(tmp_path), check=False)
    assert done.returncode == 4, done.stderr
    assert error_lines(done.stderr) == [f"error: {tmp_path / 'results.sqlite'} is not a readable SQLite database "
                                        "(file is not a database); it was left as it is. Recover its rows (sqlite3 "
                                        f"{tmp_path / 'results.sqlite'} .recover | sqlite3 recovered.sqlite) or move "
                                        "it aside, then run the report again"]


@pytest.fixture
def shared_folder():
    """A folder an unprivileged user can reach (pytest's tmp_path is private to the user running it)."""
    folder = Path(tempfile.mkdtemp(prefix="culinarycut-readonly-"))
    folder.chmod(0o755)
    yield folder
    for path in [folder, *folder.rglob("*")]:
        path.chmod(0o755 if path.is_dir() else 0o644)
    shutil.rmtree(folder)


def as_unprivileged_user():
    """Root writes through any permission bit: its run of the CLI drops to nobody to meet a read-only folder."""
    if os.geteuid() == 0:
        os.setgroups([])
        os.setgid(NOBODY)
        os.setuid(NOBODY)


def test_a_read_only_run_folder_is_named_and_every_stored_row_is_kept(address, shared_folder):
    if os.geteuid() == 0 and subprocess.run([sys.executable, "-c", "import culinarycut.cli"], capture_output=True,
                                            preexec_fn=as_unprivileged_user).returncode != 0:
        pytest.skip("as root a read-only folder takes an unprivileged user, who cannot read this Python's packages")
    suite, out = tiny_suite(shared_folder, 2), shared_folder / "run"
    argv = [sys.executable, "-m", "culinarycut", "bench", "run", str(suite), "--policy", "noop", "--server", address,
            "--out", str(out), "--no-progress"]
    first = subprocess.run([*argv, "--trials", "1"], capture_output=True, text=True, timeout=120)
    assert first.returncode == 0, first.stderr
    stored = rows(out)
    for path in out.rglob("*"):
        path.chmod(stat.S_IRUSR | stat.S_IRGRP | stat.S_IROTH)
    out.chmod(0o555)
    refused = subprocess.run(argv, capture_output=True, text=True, timeout=120, preexec_fn=as_unprivileged_user,
                             env={**os.environ, "HOME": str(shared_folder)})
    assert refused.returncode == 4, refused.stderr
    (line,) = error_lines(refused.stderr)
    assert line.startswith(f"error: cannot write {out / 'results.sqlite'}: ")
    assert f"Make {out} writable and resume with: culinarycut bench run {suite}" in line
    out.chmod(0o755)
    for path in out.rglob("*"):
        path.chmod(0o644)
    assert rows(out) == stored
    resumed = subprocess.run(argv, capture_output=True, text=True, timeout=120)
    assert resumed.returncode == 0 and "(1 were already stored)" in resumed.stdout, resumed.stderr
    assert rows(out)[0] == stored[0] and len(rows(out)) == 2


def disk_full_database_error() -> sqlite3.OperationalError:
    err = sqlite3.OperationalError("database or disk is full")
    err.sqlite_errorcode = sqlite3.SQLITE_FULL
    return err


@pytest.mark.parametrize("failing", ["video", "database"])
def test_a_full_disk_stops_the_run_with_the_file_and_the_resume_command(failing, address, tmp_path, monkeypatch,
                                                                          capsys):
    """The second episode's write fails with ENOSPC (its failure video, or its row in the database): the first
    stays stored, and the resumed run stores the second once."""
    out = tmp_path / "run"
    argv = ["bench", "run", str(tiny_suite(tmp_path, 2)), "--policy", "noop", "--record-failures", "--workers", "1",
            "--server", address, "--out", str(out), "--no-progress"]
    writes = {"video": 0, "database": 0}
    write_bytes, record = Path.write_bytes, ResultStore.record

    def video_write(path, data):
        writes["video"] += path.parent.name == "videos"
        if failing == "video" and writes["video"] == 2:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        return write_bytes(path, data)

    def database_write(store, *args, **kwargs):
        writes["database"] += 1
        if failing == "database" and writes["database"] == 2:
            raise disk_full_database_error()
        return record(store, *args, **kwargs)

    monkeypatch.setattr(Path, "write_bytes", video_write)
    monkeypatch.setattr(ResultStore, "record", database_write)
    assert cli.main(argv) == 4
    (line,) = error_lines(capsys.readouterr().err)
    file = out / "videos" / "cucumber_normal_middle_trial1.gif" if failing == "video" else out / "results.sqlite"
    assert line.startswith(f"error: cannot write {file}: the disk is full (")
    assert line.endswith("what is stored is kept. Free some space and resume with: culinarycut " + " ".join(argv))
    (first,) = rows(out)
    monkeypatch.undo()
    assert cli.main(argv) == 0
    assert [r["trial"] for r in rows(out)] == [0, 1] and rows(out)[0] == first

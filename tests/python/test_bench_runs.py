"""The benchmark runner through real servers on loopback, as a user runs it (`culinarycut bench ...` in a
subprocess): the smoke suite end to end, kill -9 and resume, two servers through Dask with one of
them killed mid-run, policy faults, version mixing, and the report against the database."""
from __future__ import annotations

import json
import os
import re
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import start_server, stop_server

HERE = Path(__file__).resolve().parent
# What must not differ between two runs of the same episodes (the same build, seeds and thread count).
OUTCOME_COLUMNS = ("task", "trial", "seed", "instruction", "outcome", "end_reason", "steps", "pieces", "cuts",
                   "cuts_within_tolerance", "peak_force_n")


def bench(*argv, timeout=600, check=True):
    env = {**os.environ, "PYTHONPATH": str(HERE)}
    done = subprocess.run([sys.executable, "-m", "culinarycut", "bench", *argv], capture_output=True, text=True,
                          timeout=timeout, env=env)
    if check:
        assert done.returncode == 0, f"exit {done.returncode}\n{done.stdout}\n{done.stderr}"
    return done


def rows(folder: Path) -> list[dict]:
    db = sqlite3.connect(folder / "results.sqlite")
    db.row_factory = sqlite3.Row
    try:
        return [dict(r) for r in db.execute("SELECT * FROM episodes ORDER BY task, trial")]
    finally:
        db.close()


def rows_so_far(folder: Path) -> list[dict]:
    """Rows of a run in progress: the runner may have created the file but not yet its tables."""
    try:
        return rows(folder)
    except sqlite3.OperationalError as error:
        if "no such table" in str(error):
            return []
        raise


def outcomes(folder: Path) -> list[tuple]:
    return [tuple(r[c] for c in OUTCOME_COLUMNS) for r in rows(folder)]


def wait_for_rows(folder: Path, count: int, proc: subprocess.Popen, timeout_s: float = 300) -> None:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if (folder / "results.sqlite").exists() and len(rows_so_far(folder)) >= count:
            return
        assert proc.poll() is None, "the runner ended before it was stopped"
        time.sleep(0.2)
    pytest.fail(f"fewer than {count} rows after {timeout_s} s")


@pytest.fixture(scope="module")
def second_server():
    server = start_server(max_sessions=8)
    yield server
    if server.proc.poll() is None:
        stop_server(server)


@pytest.fixture(scope="module")
def smoke_run(tmp_path_factory, address) -> Path:
    """The smoke suite with the oracle on one server, as the README runs it."""
    out = tmp_path_factory.mktemp("smoke") / "run"
    done = bench("run", "smoke", "--server", address, "--workers", "2", "--out", str(out), "--no-progress")
    assert re.search(r"^all\s+8/8\s+100 %", done.stdout, re.M), done.stdout  # the oracle cuts every task
    return out


def test_the_smoke_suite_runs_end_to_end_and_stores_a_full_row_per_episode(smoke_run):
    stored = rows(smoke_run)
    assert len(stored) == 8 and {r["outcome"] for r in stored} == {"success"}
    for row in stored:
        assert row["policy"] == "oracle" and row["server_version"] and row["build_id"]
        assert json.loads(row["resolved_scene"])["task"]["instruction"] == row["instruction"]
        cuts = json.loads(row["cuts"])
        assert len(cuts) == row["cuts_required"] >= 1
        assert all(c["position_error_fraction"] < 0.1 for c in cuts)
        assert row["peak_force_n"] > 1.0 and 0.01 < row["peak_speed_m_s"] < 1.0
        assert row["steps"] > 50 and row["wall_s"] >= row["env_wall_s"] > 0
        assert set(json.loads(row["stage_wall_s"])) >= {"mpm", "physics"}
    split = next(r for r in stored if r["state"] == "split")
    assert split["pieces"] == 3 and split["cuts_within_tolerance"] == 2


def test_two_servers_through_dask_give_the_same_outcomes_even_when_one_dies(smoke_run, address, tmp_path):
    """Same seeds, same build: identical rows; the episodes of the killed server are run on the other, once."""
    doomed = start_server(max_sessions=8)
    out = tmp_path / "two"
    proc = subprocess.Popen([sys.executable, "-m", "culinarycut", "bench", "run", "smoke", "--server", address,
                             "--server", doomed.address, "--workers", "2", "--out", str(out), "--no-progress"],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        wait_for_rows(out, 2, proc)
        doomed.kill()
        output, _ = proc.communicate(timeout=600)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, output
    assert outcomes(out) == outcomes(smoke_run)
    assert any(r["attempts"] >= 2 for r in rows(out)), "no episode moved to the surviving server"


def test_kill_9_of_the_runner_then_resume_runs_every_episode_exactly_once(address, tmp_path):
    out = tmp_path / "resumed"
    argv = [sys.executable, "-m", "culinarycut", "bench", "run", "smoke", "--trials", "1", "--server", address,
            "--workers", "1", "--out", str(out), "--no-progress"]
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wait_for_rows(out, 1, proc)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    before = {(r["task"], r["trial"]): r["finished_at"] for r in rows(out)}
    assert 1 <= len(before) < 4
    done = bench("run", "smoke", "--trials", "1", "--server", address, "--workers", "1", "--out", str(out),
                 "--no-progress")
    assert f"({len(before)} were already stored)" in done.stdout
    after = rows(out)
    assert len(after) == 4 and len({(r["task"], r["trial"]) for r in after}) == 4
    assert all(before[(r["task"], r["trial"])] == r["finished_at"] for r in after if (r["task"], r["trial"]) in before)
    again = bench("run", "smoke", "--trials", "1", "--server", address, "--out", str(out), "--no-progress")
    assert "this run: 0 episodes" in again.stdout


def test_a_policy_that_raises_or_hangs_is_recorded_as_policy_error_and_the_suite_goes_on(address, tmp_path):
    suite = tmp_path / "faults.toml"
    suite.write_text('name = "faults"\ndescription = "policy faults"\ntrials = 2\nmax_episode_steps = 20\n'
                     '[[tasks]]\nfood = "cucumber"\nstate = "middle"\n')
    raised = bench("run", str(suite), "--policy", "bench_policies:RaisingPolicy", "--server", address,
                   "--out", str(tmp_path / "raising"), "--no-progress")
    assert "faults with bench_policies:RaisingPolicy" in raised.stdout
    stored = rows(tmp_path / "raising")
    assert len(stored) == 2 and {r["end_reason"] for r in stored} == {"policy_error"}
    assert all("the model ran out of ideas" in r["error"] and r["steps"] == 2 for r in stored)  # it raises at step 2
    slow = bench("run", str(suite), "--policy", "bench_policies:SlowPolicy", "--act-timeout", "0.5", "--server",
                 address, "--out", str(tmp_path / "slow"), "--no-progress")
    assert slow.returncode == 0
    assert {r["error"] for r in rows(tmp_path / "slow")} == {"act took longer than 0.5 s at step 0"}


def test_a_run_refuses_to_mix_server_versions_unless_told(address, tmp_path):
    out = tmp_path / "mixed"
    one_task = ["--tasks", "cucumber/normal/ratio-*", "--trials", "2", "--server", address, "--out", str(out),
                "--no-progress"]
    bench("run", "smoke", *one_task)
    db = sqlite3.connect(out / "results.sqlite")
    with db:
        db.execute("UPDATE episodes SET server_version = '0.0.1', build_id = 'elsewhere' WHERE trial = 0")
        db.execute("DELETE FROM episodes WHERE trial = 1")
    db.close()
    refused = bench("run", "smoke", *one_task, check=False)
    assert refused.returncode == 1 and "servers of different versions" in refused.stderr
    assert "0.0.1 (build elsewhere)" in refused.stderr and "--allow-mixed-versions" in refused.stderr
    other_suite = bench("run", "split-partial", "--trials", "1", "--server", address, "--out", str(out),
                        "--no-progress", check=False)
    assert other_suite.returncode == 1 and "holds a run with suite = smoke" in other_suite.stderr
    bench("run", "smoke", *one_task, "--allow-mixed-versions")
    assert len(rows(out)) == 2


def test_the_report_tables_match_the_database_and_the_page_is_self_contained(smoke_run, tmp_path):
    bench("report", str(smoke_run), str(smoke_run), "--out", str(tmp_path))
    markdown = (tmp_path / "report.md").read_text()
    per_task = markdown.split("## Success per task")[1].split("##")[0]
    db = sqlite3.connect(smoke_run / "results.sqlite")
    expected = db.execute("SELECT task, SUM(outcome = 'success'), COUNT(*) FROM episodes GROUP BY task").fetchall()
    for task, successes, total in expected:
        line = next(line for line in per_task.splitlines() if line.startswith(f"| {task} |"))
        assert line.count(f"| {successes}/{total} |") == 2  # both runs, side by side
    assert "## Split cuts: partial success" in markdown
    for image in re.findall(r"\]\((report_files/[^)]+)\)", markdown):
        assert (tmp_path / image).stat().st_size > 1000
    page = (tmp_path / "report.html").read_text()
    assert page.count("data:image/png;base64,") >= 2
    assert not re.search(r"(src|href)=\"(?!data:)", page)  # nothing outside the file


def test_the_html_report_renders_in_a_headless_browser(smoke_run, tmp_path):
    """Every chart decodes and every table is there, as Chromium shows the page."""
    from selenium import webdriver
    bench("report", str(smoke_run), "--out", str(tmp_path))
    options = webdriver.ChromeOptions()
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"):
        options.add_argument(flag)
    browser = webdriver.Chrome(options=options)
    try:
        browser.get((tmp_path / "report.html").as_uri())
        images = browser.execute_script(
            "return Array.from(document.images).map(i => [i.complete, i.naturalWidth, i.alt]);")
        tables = browser.execute_script("return document.querySelectorAll('table').length;")
        first_heading = browser.find_element("tag name", "h1").text
    finally:
        browser.quit()
    assert len(images) >= 2 and all(done and width > 100 for done, width, _ in images), images
    assert {alt for _, _, alt in images} >= {"Success per food", "Force at the wrist, every trial"}
    assert tables >= 7 and first_heading == "Benchmark report: smoke"


def test_episodes_go_to_an_existing_dask_cluster_whose_worker_is_bound_to_a_server(address, second_server, tmp_path):
    """--scheduler: a user's own cluster; the worker's CULINARYCUT_SERVER decides where its episodes run."""
    dask = Path(sys.executable).parent / "dask"
    scheduler = subprocess.Popen([str(dask), "scheduler", "--host", "127.0.0.1", "--port", "0",
                                  "--no-dashboard"], stderr=subprocess.PIPE, text=True)
    worker = None
    try:
        scheduler_address = None
        for line in scheduler.stderr:
            found = re.search(r"Scheduler at:\s+(tcp://\S+)", line)
            if found:
                scheduler_address = found.group(1)
                break
        assert scheduler_address, "the Dask scheduler did not start"
        worker = subprocess.Popen([str(dask), "worker", scheduler_address, "--nthreads", "1", "--no-dashboard"],
                                  env={**os.environ, "CULINARYCUT_SERVER": second_server.address},
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        out = tmp_path / "remote"
        bench("run", "smoke", "--tasks", "cucumber/normal/ratio-*", "--trials", "1", "--server", address,
              "--scheduler", scheduler_address, "--out", str(out), "--no-progress")
        (row,) = rows(out)
        assert row["outcome"] == "success" and row["server"] == second_server.address
    finally:
        for process in (worker, scheduler):
            if process is not None:
                process.terminate()
                process.wait(timeout=30)


def test_ctrl_c_stops_the_run_and_says_how_to_resume(address, tmp_path):
    out = tmp_path / "interrupted"
    proc = subprocess.Popen([sys.executable, "-m", "culinarycut", "bench", "run", "smoke", "--trials", "1",
                             "--server", address, "--workers", "1", "--out", str(out), "--no-progress"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_for_rows(out, 1, proc)
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130, stderr
    assert re.search(r"stopped: \d of 4 episodes are stored in .*; resume with:\n  culinarycut bench run smoke", stderr)

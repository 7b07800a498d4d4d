"""The benchmark runner through real servers on loopback, as a user runs it (`culinarycut bench ...` in a
subprocess): the smoke suite end to end, kill -9 and resume, two servers through Dask with one of
them killed mid-run, policy faults, version mixing, retrying stored errors, failure videos, the
floor policies, and the report against the database."""
from __future__ import annotations

import contextlib
import io
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

from bench_cli import bench, with_tests_on_path
from conftest import start_server, stop_server
from stored_runs import rows, rows_so_far

# What must not differ between two runs of the same episodes (the same build, seeds and thread count).
OUTCOME_COLUMNS = ("task", "trial", "seed", "instruction", "outcome", "end_reason", "steps", "pieces", "cuts",
                   "cuts_within_tolerance", "peak_force_n")
# A small suite for the report sections and the floor policies: three ratios from each side (a radar
# per side), a middle cut with topology on and off; 8 short draft episodes, about a second each.
SECTIONS_SUITE = """name = "sections"
description = "ratio radar by side and topology on/off, briefly"
trials = 1
max_episode_steps = 30
quality = "draft"

[[tasks]]
food = "cucumber"
state = "ratio"
ratio = [0.3, 0.5, 0.7]
side = ["left", "right"]

[[tasks]]
food = "cucumber"
state = "middle"
topology = [true, false]
"""


def outcomes(folder: Path) -> list[tuple]:
    return [tuple(r[c] for c in OUTCOME_COLUMNS) for r in rows(folder)]


def traces(folder: Path) -> list[tuple]:
    db = sqlite3.connect(folder / "results.sqlite")
    try:
        return db.execute("SELECT task, trial, trace FROM traces ORDER BY task, trial").fetchall()
    finally:
        db.close()


def edit(folder: Path, statement: str, params=()) -> None:
    db = sqlite3.connect(folder / "results.sqlite")
    with db:
        db.execute(statement, params)
    db.close()


@contextlib.contextmanager
def dask_cluster(worker_env: dict, preload: str | None = None, scheduler_env: dict | None = None):
    """A Dask scheduler and one single-thread worker, as a user starts them; yields the scheduler address."""
    dask = Path(sys.executable).parent / "dask"
    scheduler = subprocess.Popen([str(dask), "scheduler", "--host", "127.0.0.1", "--port", "0",
                                  "--no-dashboard"], stderr=subprocess.PIPE, text=True,
                                 env={**os.environ, **(scheduler_env or {})})
    worker = None
    try:
        scheduler_address = None
        for line in scheduler.stderr:
            found = re.search(r"Scheduler at:\s+(tcp://\S+)", line)
            if found:
                scheduler_address = found.group(1)
                break
        assert scheduler_address, "the Dask scheduler did not start"
        env = with_tests_on_path({**os.environ, **worker_env})
        worker = subprocess.Popen([str(dask), "worker", scheduler_address, "--nthreads", "1", "--no-dashboard"] +
                                  (["--preload", preload] if preload else []),
                                  env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        yield scheduler_address
    finally:
        for process in (worker, scheduler):
            if process is not None:
                process.terminate()
                process.wait(timeout=30)


def wait_for_rows(folder: Path, count: int, proc: subprocess.Popen, timeout_s: float = 300) -> None:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if len(rows_so_far(folder)) >= count:
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


def test_the_smoke_suite_runs_end_to_end_and_stores_a_full_row_per_episode(smoke_run, client):
    stored = rows(smoke_run)
    simd = client.server_info().simd
    assert len(stored) == 8 and {r["outcome"] for r in stored} == {"success"}
    for row in stored:
        assert row["policy"] == "oracle" and row["server_version"] and row["build_id"]
        assert row["simd"] == simd  # the instruction set its MPM kernels ran
        assert json.loads(row["resolved_scene"])["task"]["instruction"] == row["instruction"]
        cuts = json.loads(row["cuts"])
        assert len(cuts) == row["cuts_required"] >= 1
        assert all(c["position_error_fraction"] < 0.1 for c in cuts)
        assert all(c["angle_error_deg"] is not None and c["angle_error_deg"] < 9.0 for c in cuts)  # the cut surface
        assert (row["pivot_deg"] > 20.0) == (row["style"] == "guillotine") and row["saw_strokes"] == 0
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
                   "--out", str(tmp_path / "raising"), "--no-progress", check=False)
    assert raised.returncode == 3 and "faults with bench_policies:RaisingPolicy" in raised.stdout
    stored = rows(tmp_path / "raising")
    assert len(stored) == 2 and {r["end_reason"] for r in stored} == {"policy_error"}
    assert all("the model ran out of ideas" in r["error"] and r["steps"] == 2 for r in stored)  # it raises at step 2
    slow = bench("run", str(suite), "--policy", "bench_policies:SlowPolicy", "--act-timeout", "0.5", "--server",
                 address, "--out", str(tmp_path / "slow"), "--no-progress", check=False)
    assert slow.returncode == 3  # every episode ran, but as an error
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
    assert "0.0.1 (build elsewhere, " in refused.stderr and "--allow-mixed-versions" in refused.stderr
    other_suite = bench("run", "split-partial", "--trials", "1", "--server", address, "--out", str(out),
                        "--no-progress", check=False)
    assert other_suite.returncode == 1 and "holds a run with suite = smoke" in other_suite.stderr
    bench("run", "smoke", *one_task, "--allow-mixed-versions")
    assert len(rows(out)) == 2
    # Finished, the run may be resumed from another build (a study going on to its next suite): nothing to store.
    db = sqlite3.connect(out / "results.sqlite")
    with db:
        db.execute("UPDATE episodes SET server_version = '0.0.1', build_id = 'elsewhere'")
    db.close()
    finished = bench("run", "smoke", *one_task)
    assert "this run: 0 episodes" in finished.stdout and len(rows(out)) == 2


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
    orientation = markdown.split("## Cut placement and orientation")[1].split("##")[0]
    assert "![Angle between the cut surface and the target plane](report_files/cut_orientation.png)" in orientation
    assert "![Angle between the blade in the food and the target plane](report_files/blade_orientation.png)" in orientation
    assert orientation.count("| guillotine |") == 2  # a row per run
    for image in re.findall(r"\]\((report_files/[^)]+)\)", markdown):
        assert (tmp_path / image).stat().st_size > 1000
    page = (tmp_path / "report.html").read_text()
    assert page.count("data:image/png;base64,") >= 2
    assert not re.search(r"(src|href)=\"(?!data:)", page)  # no failure videos here: nothing outside the file


def test_the_report_names_runs_as_asked_and_charts_success_per_suite(smoke_run, tmp_path):
    """A study names its runs (a learned policy is served over openpi; "openpi @ server" would not say which), and
    draws success per suite in the order it ran them."""
    from culinarycut.bench.report import load_run, write_report
    from culinarycut.bench.report_charts import success_per
    write_report([smoke_run, smoke_run], tmp_path, labels=["learned (openpi)", "oracle"],
                 folder_names=["STUDY/bench/learned", "STUDY/bench/oracle"])
    summary = (tmp_path / "report.md").read_text().split("## Success per task")[0]
    assert "| A | learned (openpi) | STUDY/bench/learned |" in summary and "| B | oracle | STUDY/bench/oracle |" in summary
    assert str(smoke_run) not in summary  # the study's own names, not the machine's paths
    rows = load_run(smoke_run).rows
    other = [{**row, "suite": "another"} for row in rows]
    chart = success_per([("learned", other + rows)], "suite", "Success per suite", sort_values=False)
    assert chart.startswith(b"\x89PNG") and len(chart) > 1000


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
    with dask_cluster({"CULINARYCUT_SERVER": second_server.address}) as scheduler_address:
        out = tmp_path / "remote"
        bench("run", "smoke", "--tasks", "cucumber/normal/ratio-*", "--trials", "1", "--server", address,
              "--scheduler", scheduler_address, "--out", str(out), "--no-progress")
        (row,) = rows(out)
        assert row["outcome"] == "success" and row["server"] == second_server.address


def test_a_worker_bound_to_a_server_of_another_build_stops_the_run_before_its_row_is_stored(
        sections_suite, address, second_server, tmp_path):
    """The pre-flight check asks only the --server addresses; the row a worker brings back is checked too."""
    from other_build_worker import OTHER_BUILD, OTHER_VERSION
    with dask_cluster({"CULINARYCUT_SERVER": second_server.address}, preload="other_build_worker") as scheduler:
        out = tmp_path / "mixed-worker"
        argv = ["run", str(sections_suite), "--policy", "noop", "--tasks", "cucumber/normal/middle", "--server",
                address, "--scheduler", scheduler, "--out", str(out), "--no-progress"]
        refused = bench(*argv, check=False)
        assert refused.returncode == 1, refused.stderr
        assert f"ran on {second_server.address}, {OTHER_VERSION} (build {OTHER_BUILD}, " in refused.stderr
        assert "Traceback" not in refused.stderr and "--allow-mixed-versions" in refused.stderr
        assert re.search(r"resume with:\n  culinarycut bench run .*sections\.toml", refused.stderr)
        assert rows(out) == []
        bench(*argv, "--allow-mixed-versions")
        (row,) = rows(out)
        assert (row["server_version"], row["build_id"]) == (OTHER_VERSION, OTHER_BUILD)


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


def test_a_task_that_fails_on_its_worker_stops_the_run_with_the_resume_hint_not_as_bad_input(address, tmp_path):
    """A ValueError from inside an episode is no usage error (exit 2): the run stops (exit 1), says which
    episode and how to resume, and prints no traceback."""
    suite = tmp_path / "bug.toml"
    suite.write_text('name = "bug"\ndescription = "a policy bug"\ntrials = 1\nmax_episode_steps = 5\n'
                     '[[tasks]]\nfood = "cucumber"\nstate = "middle"\n')
    done = bench("run", str(suite), "--policy", "bench_policies:CamerasBugPolicy", "--server", address,
                 "--workers", "1", "--out", str(tmp_path / "bug"), "--no-progress", check=False)
    assert done.returncode == 1, done.stderr
    assert ("error: episode cucumber/normal/middle trial 0 failed on its worker: "
            "ValueError: camera 'wrist' has no resolution") in done.stderr
    assert re.search(r"0 of 1 episodes are stored; resume with:\n  culinarycut bench run .*bug\.toml", done.stderr)
    assert "Traceback" not in done.stderr


def test_a_worker_killed_mid_episode_stops_the_run_with_the_resume_hint(second_server, tmp_path):
    """KilledWorker (here at the first death: allowed-failures 0) is reported as such, not as a traceback.
    On the second server: the killed worker's session stays open there until its idle timeout."""
    suite = tmp_path / "killed.toml"
    suite.write_text('name = "killed"\ndescription = "a worker killed"\ntrials = 1\nmax_episode_steps = 5\n'
                     '[[tasks]]\nfood = "cucumber"\nstate = "middle"\n')
    with dask_cluster({}, scheduler_env={"DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "0"}) as scheduler:
        done = bench("run", str(suite), "--policy", "bench_policies:WorkerKillingPolicy", "--server",
                     second_server.address, "--scheduler", scheduler, "--out", str(tmp_path / "killed"),
                     "--no-progress", check=False)
    assert done.returncode == 1, done.stderr
    assert "error: episode cucumber/normal/middle trial 0: the Dask workers running it died" in done.stderr
    assert re.search(r"0 of 1 episodes are stored; resume with:\n  culinarycut bench run .*killed\.toml", done.stderr)
    assert "Traceback" not in done.stderr


@pytest.fixture(scope="module")
def sections_suite(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("suites") / "sections.toml"
    path.write_text(SECTIONS_SUITE)
    return path


@pytest.fixture(scope="module")
def noop_run(sections_suite, address, tmp_path_factory) -> Path:
    """The sections suite with the noop policy, failure videos on: every episode fails and is filmed."""
    out = tmp_path_factory.mktemp("noop") / "run"
    bench("run", str(sections_suite), "--policy", "noop", "--record-failures", "--server", address,
          "--workers", "2", "--out", str(out), "--no-progress")
    return out


def test_record_failures_keeps_a_gif_of_each_failed_episode_and_the_report_shows_it(noop_run, tmp_path):
    from PIL import Image, ImageSequence
    stored = rows(noop_run)
    assert len(stored) == 8 and {r["outcome"] for r in stored} == {"failure"}
    for row in stored:
        gif = Image.open(noop_run / row["video"])
        assert gif.format == "GIF" and gif.size == (160, 120)
        # 30 steps, every second one at 100 ms (identical frames, the knife held still, merge into one)
        assert sum(frame.info["duration"] for frame in ImageSequence.Iterator(gif)) == 15 * 100
    bench("report", str(noop_run), "--out", str(tmp_path))
    markdown = (tmp_path / "report.md").read_text()
    failures = markdown.split("## First failure of each task")[1]
    for row in stored:  # one failure per task, each with its video beside the report
        name = Path(row["video"]).name
        assert f"![{row['task']}, trial 0](report_files/{name})" in failures
        assert (tmp_path / "report_files" / name).read_bytes() == (noop_run / row["video"]).read_bytes()
    page = (tmp_path / "report.html").read_text()
    assert "data:image/gif" not in page  # a thumbnail (the last frame) links each video file beside the page
    links = re.findall(r'<a href="(report_files/[^"]+)"><img src="data:image/jpeg;base64,', page)
    assert sorted(links) == sorted(f"report_files/{Path(row['video']).name}" for row in stored)


def test_the_report_has_a_radar_per_side_and_topology_on_and_off_from_a_stored_run(noop_run, tmp_path):
    from PIL import Image
    bench("report", str(noop_run), "--out", str(tmp_path))
    markdown = (tmp_path / "report.md").read_text()
    assert "![Ratio cuts on cucumber](report_files/ratio_radar_cucumber.png)" in markdown
    radar = Image.open(tmp_path / "report_files" / "ratio_radar_cucumber.png")
    assert radar.width > 1.6 * radar.height  # two polar panels side by side: from the left, from the right
    topology = markdown.split("## Topology updates on and off")[1].split("##")[0]
    expected: dict[str, list[str]] = {}  # task without /topology-off: success with it on, with it off
    for row in rows(noop_run):  # one trial per task
        cells = expected.setdefault(row["task"].replace("/topology-off", ""), ["-", "-"])
        cells[0 if row["topology"] else 1] = f"{int(row['outcome'] == 'success')}/1"
    assert expected["cucumber/normal/middle"] == ["0/1", "0/1"]
    for task, (on, off) in expected.items():
        line = next(line for line in topology.splitlines() if line.startswith(f"| {task} |"))
        assert line.split(" | ")[1::2] == [on, off], line  # task | on: success | on: rate | off: success | ...


def test_the_random_policy_gives_the_same_episodes_in_two_runs_of_the_same_suite(sections_suite, address, tmp_path):
    for name in ("first", "second"):
        bench("run", str(sections_suite), "--policy", "random", "--server", address, "--workers", "2",
              "--out", str(tmp_path / name), "--no-progress")
    first, second = rows(tmp_path / "first"), rows(tmp_path / "second")
    assert len(first) == 8
    assert outcomes(tmp_path / "first") == outcomes(tmp_path / "second")
    assert [r["peak_speed_m_s"] for r in first] == [r["peak_speed_m_s"] for r in second]
    assert traces(tmp_path / "first") == traces(tmp_path / "second")  # knife speed and height, step by step
    assert len({r["peak_speed_m_s"] for r in first}) == 8  # each episode drew its own actions, and moved
    assert min(r["peak_speed_m_s"] for r in first) > 0.1


def test_retry_errors_reruns_the_episodes_stored_as_server_errors_and_replaces_their_rows(
        sections_suite, address, tmp_path):
    out = tmp_path / "retried"
    argv = ["run", str(sections_suite), "--policy", "noop", "--tasks", "cucumber/normal/middle*", "--server",
            address, "--out", str(out), "--no-progress"]
    bench(*argv)
    kept, errored = rows(out)
    # As a deadline on the episode's first call leaves it: the row names no server version.
    edit(out, "UPDATE episodes SET outcome = 'error', end_reason = 'server_error', server_version = '', "
              "build_id = '', error = 'DEADLINE_EXCEEDED: Deadline Exceeded' WHERE task = ?", (errored["task"],))
    resumed = bench(*argv, check=False)  # an error row names no version: no "mixed versions" refusal
    assert resumed.returncode == 3 and "this run: 0 episodes" in resumed.stdout
    assert rows(out)[1]["end_reason"] == "server_error"
    bench("report", str(out), "--out", str(tmp_path / "report"))
    summary = (tmp_path / "report" / "report.md").read_text().split("## ")[0]
    assert f"| noop @ {kept['server_version']} ({kept['build_id']}, {kept['simd']}) |" in summary  # the error row names no build
    retried = bench(*argv, "--retry-errors")
    assert "this run: 1 episodes" in retried.stdout and "1 stored errors run again" in retried.stdout
    now_kept, now_retried = rows(out)
    assert now_kept == kept  # untouched, finished_at included
    assert now_retried["outcome"] == "failure" and now_retried["end_reason"] == errored["end_reason"]
    assert (now_retried["server_version"], now_retried["build_id"]) == (errored["server_version"],
                                                                        errored["build_id"])
    assert now_retried["error"] == "" and now_retried["finished_at"] > errored["finished_at"]
    again = bench(*argv, "--retry-errors")
    assert "this run: 0 episodes" in again.stdout  # nothing left to retry

"""The safety ablation through the benchmark: suites declare the limiter (and bad settings are refused naming
the field), the aggressive oracle's options, a limiter-on and -off pair of episodes on a real server storing
the limiter's state, interventions and the knife's peaks, and the report's safety section matching the rows."""
from __future__ import annotations

import json
import os
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from culinarycut.bench.episode_scene import episode_spec
from culinarycut.bench.suite import SuiteError, load_suite
from culinarycut.policies.registry import make_policy
from stored_runs import rows

# The scale-1 apple's predicted force (about 32 N) is above 15 N, so with every guard the speed guard's
# v_safe is 0 and the knife is held at the food; with the limiter off the same scene is cut.
PAIR_SUITE = """name = "pair"
description = "one apple, limiter off and on at a low F_max"
trials = 1
max_episode_steps = 120
randomize = { position_m = 0.0, yaw_deg = 0.0, scale = [1.0, 1.0] }

[policy]
name = "oracle-aggressive"

[[tasks]]
food = "apple"
state = "middle"
safety_limiter = false

[[tasks]]
food = "apple"
state = "middle"
safety_limiter = true
safety = { max_force_n = 15, margin = 0.1 }
"""


def write_suite(tmp_path: Path, body: str, name: str = "mine") -> Path:
    path = tmp_path / f"{name}.toml"
    path.write_text(f'name = "{name}"\ndescription = "a test suite"\n' + body)
    return path


def bench(*argv, timeout=300, check=True) -> subprocess.CompletedProcess:
    done = subprocess.run([sys.executable, "-m", "culinarycut", "bench", *argv], capture_output=True, text=True,
                          timeout=timeout, env=dict(os.environ))
    if check:
        assert done.returncode == 0, f"exit {done.returncode}\n{done.stdout}\n{done.stderr}"
    return done


def test_the_shipped_ablation_suite_pairs_off_and_on_and_passes_the_settings_into_the_scene():
    suite = load_suite("safety-ablation")
    assert suite.policy["name"] == "oracle-aggressive"
    assert {t.food for t in suite.tasks} == {"cucumber", "apple", "banana"}
    assert all(t.trials == 20 for t in suite.tasks)
    settings = {(t.safety_limiter, t.safety.get("max_force_n")) for t in suite.tasks}
    assert settings == {(False, None), (True, 100), (True, 15)}
    off = suite.task("apple/normal/middle/limiter-off")
    on = suite.task("apple/normal/middle/limiter-100N")
    scene_off, scene_on = episode_spec(suite, off, 3).scene, episode_spec(suite, on, 3).scene
    assert "safety_limiter" not in scene_off["effects"] and "safety" not in scene_off
    assert scene_on["effects"]["safety_limiter"] is True and scene_on["safety"] == {"max_force_n": 100}
    # The settings of one trial see the same scene: only the limiter differs.
    assert scene_off["objects"] == scene_on["objects"] and scene_off["seed"] == scene_on["seed"]


def test_suite_wide_settings_apply_to_every_task_and_a_task_overrides_them(tmp_path):
    suite = load_suite(str(write_suite(tmp_path, """safety_limiter = true
safety = { max_force_n = 40, margin = 0.2, max_entry_angle_deg = 10 }
[[tasks]]
food = "cucumber"
state = "middle"
[[tasks]]
food = "banana"
state = "middle"
safety = { max_force_n = 25, guards = ["force"] }
[[tasks]]
food = "apple"
state = "middle"
safety_limiter = false
""")))
    cucumber, banana, apple = suite.tasks
    assert cucumber.name == "cucumber/normal/middle/limiter-40N"
    assert cucumber.safety == {"max_force_n": 40, "margin": 0.2, "max_entry_angle_deg": 10}
    assert banana.name == "banana/normal/middle/limiter-25N-force"
    assert banana.safety == {"max_force_n": 25, "margin": 0.2, "max_entry_angle_deg": 10, "guards": ["force"]}
    assert apple.name == "apple/normal/middle/limiter-off" and not apple.safety_limiter
    assert "safety" not in episode_spec(suite, apple, 0).scene


def test_a_suite_without_the_limiter_keeps_its_task_names_and_seeds():
    smoke = load_suite("smoke")
    assert not any(t.safety_limiter or "limiter" in t.name for t in smoke.tasks)
    assert all("safety_limiter" not in episode_spec(smoke, t, 0).scene["effects"] for t in smoke.tasks)


@pytest.mark.parametrize("body, message", [
    ('[[tasks]]\nfood = "apple"\nstate = "middle"\nsafety_limiter = "yes"\n',
     r"^suite.tasks\[0\].safety_limiter: 'yes' is not of type 'boolean'"),
    ('[[tasks]]\nfood = "apple"\nstate = "middle"\nsafety_limiter = true\nsafety = { margin = 1.5 }\n',
     r"^suite.tasks\[0\].safety.margin: 1.5 is greater than the maximum of 0.9"),
    ('[[tasks]]\nfood = "apple"\nstate = "middle"\nsafety_limiter = true\nsafety = { guards = ["speed", "brake"] }\n',
     r"^suite.tasks\[0\].safety.guards\[1\]: 'brake' is not one of \['speed', 'force', 'entry_angle'\]"),
    ('safety_limiter = true\nsafety = { max_force_n = 0 }\n[[tasks]]\nfood = "apple"\nstate = "middle"\n',
     r"^suite.safety.max_force_n: 0 is less than or equal to the minimum of 0"),
    ('safety_limiter = true\nsafety = { max_entry_angle_deg = 120 }\n[[tasks]]\nfood = "apple"\nstate = "middle"\n',
     r"^suite.safety.max_entry_angle_deg: 120 is greater than the maximum of 90"),
    ('safety_limiter = true\nsafety = { f_max = 50 }\n[[tasks]]\nfood = "apple"\nstate = "middle"\n',
     r"^suite.safety: .*'f_max' was unexpected\); valid fields: max_force_n, margin, guards, max_entry_angle_deg$"),
    ('safety = { max_force_n = 50 }\n[[tasks]]\nfood = "apple"\nstate = "middle"\n',
     r"^suite.safety: settings for a safety limiter that no task turns on"),
    ('[[tasks]]\nfood = "apple"\nstate = "middle"\nsafety = { max_force_n = 50 }\n',
     r"^suite.tasks\[0\].safety: settings for a safety limiter that is off; set safety_limiter = true"),
    ('[[tasks]]\nfood = "apple"\nstate = "middle"\nsafety_limiter = true\nsafety = { margin = 0.2 }\n'
     '[[tasks]]\nfood = "apple"\nstate = "middle"\nsafety_limiter = true\n', "task names repeat"),
])
def test_bad_safety_settings_are_refused_naming_the_field(tmp_path, body, message):
    path = write_suite(tmp_path, body)
    with pytest.raises(SuiteError, match=message):
        load_suite(str(path))
    shown = bench("show", str(path), check=False)
    assert shown.returncode == 2 and "suite" in shown.stderr


def test_the_aggressive_oracle_refuses_bad_options_naming_them(tmp_path):
    policy = make_policy("oracle-aggressive", {"cut_speed_m_s": 3.0})
    assert policy.cut_speed_m_s == 3.0 and policy.planned_speed_m_s == 2.0  # the planner's bound
    assert policy.planner_options()["cut_speed_m_s"] == {"min": 2.0, "max": 2.0}
    with pytest.raises(ValueError, match="option cut_speed_m_s must be a number in"):
        make_policy("oracle-aggressive", {"cut_speed_m_s": -1})
    with pytest.raises(ValueError, match="option hold_s"):
        make_policy("oracle-aggressive", {"hold_s": "long"})
    done = bench("run", str(write_suite(tmp_path, '[[tasks]]\nfood = "apple"\nstate = "middle"\n')),
                 "--policy", "oracle-aggressive", "--policy-option", "cut_speed_m_s=0", "--server", "127.0.0.1:1",
                 "--out", str(tmp_path / "run"), check=False)
    assert done.returncode == 2 and "cut_speed_m_s" in done.stderr


@pytest.fixture(scope="module")
def pair_run(tmp_path_factory, address) -> Path:
    folder = tmp_path_factory.mktemp("pair")
    suite = folder / "pair.toml"
    suite.write_text(PAIR_SUITE)
    bench("run", str(suite), "--server", address, "--out", str(folder / "run"), "--workers", "2", "--no-progress")
    return folder / "run"


def test_a_limiter_on_and_off_pair_stores_the_limiter_its_interventions_and_the_peaks(pair_run):
    off, on = sorted(rows(pair_run), key=lambda r: r["safety_limiter"])
    assert off["task"] == "apple/normal/middle/limiter-off" and on["task"] == "apple/normal/middle/limiter-15N"
    assert off["seed"] == on["seed"]
    assert (off["safety_limiter"], on["safety_limiter"]) == (0, 1)
    assert off["safety_settings"] is None and json.loads(on["safety_settings"]) == {"margin": 0.1, "max_force_n": 15}
    assert on["safety_max_force_n"] == 15.0 and off["safety_max_force_n"] is None
    # Off: the aggressive knife cuts the apple; nothing counts interventions.
    assert off["outcome"] == "success", off["score_summary"]
    assert off["peak_knife_force_n"] > 5.0 and off["peak_cutting_speed_m_s"] > 0.2
    assert off["interventions_speed"] == off["interventions_force"] == off["safety_acted_steps"] == 0
    assert off["peak_commanded_speed_m_s"] is None
    # On at 15 N: the speed guard holds the knife at the apple, so it never cuts and pushes nothing.
    assert on["interventions_speed"] > 0 and on["safety_acted_steps"] >= on["interventions_speed"]
    assert on["outcome"] == "failure" and on["peak_knife_force_n"] < 1.0
    assert on["peak_commanded_speed_m_s"] > 1.0  # what the aggressive policy asked for before the limit
    trace = json.loads(sqlite3.connect(pair_run / "results.sqlite").execute(
        "SELECT trace FROM traces WHERE task = ?", (on["task"],)).fetchone()[0])
    assert len(trace["tcp_along_cut_m"]) == len(trace["safety_acted"]) == on["steps"]
    assert sum(trace["safety_acted"]) == on["safety_acted_steps"]


def test_the_report_has_the_safety_section_and_its_table_matches_the_database(pair_run, tmp_path):
    bench("report", str(pair_run), "--out", str(tmp_path))
    markdown = (tmp_path / "report.md").read_text()
    section = markdown.split("## Safety limiter: on against off")[1].split("\n## ")[0]
    db = sqlite3.connect(pair_run / "results.sqlite")
    stored = db.execute("SELECT safety_limiter, AVG(peak_cutting_speed_m_s), AVG(peak_knife_force_n), "
                        "SUM(outcome = 'success'), COUNT(*) FROM episodes GROUP BY safety_limiter").fetchall()
    labels = {0: "limiter off", 1: "limiter on, F_max 15 N"}
    paper = {0: "| 3.63 |", 1: None}  # the paper ran F_max 100 N only: no paper cells beside 15 N
    for limiter, speed, force, successes, total in stored:
        line = next(line for line in section.splitlines() if line.startswith(f"| {labels[limiter]} |"))
        cells = [c.strip() for c in line.strip("|").split("|")]
        assert cells[1] == str(total)
        assert cells[2] == f"{speed:.2f}" and cells[4] == f"{force:.2f}"
        assert cells[6].startswith(f"{successes}/{total} ")
        assert (paper[limiter] in line) if paper[limiter] else cells[3] == cells[5] == "-"
    image = next(name for name in (tmp_path / "report_files").iterdir() if name.name == "safety_ablation.png")
    assert image.stat().st_size > 10_000
    assert "safety_ablation.png" in markdown and "Safety limiter: on against off" in (tmp_path / "report.html").read_text()


def test_a_run_without_the_limiter_has_no_safety_section(tmp_path, address):
    suite = write_suite(tmp_path, 'trials = 1\nmax_episode_steps = 3\n[[tasks]]\nfood = "banana"\nstate = "middle"\n')
    bench("run", str(suite), "--policy", "noop", "--server", address, "--out", str(tmp_path / "run"), "--no-progress")
    bench("report", str(tmp_path / "run"))
    assert "Safety limiter" not in (tmp_path / "run" / "report.md").read_text()


def test_the_success_chart_draws_a_food_that_always_succeeds():
    """At n/n successes the Wilson bound can round a hair under 100 %; the bar's error must not go negative."""
    from culinarycut.bench.report_charts import success_per_food
    rows = [{"food": "banana", "outcome": "success"}] * 60
    assert success_per_food([("run", rows)]).startswith(b"\x89PNG")

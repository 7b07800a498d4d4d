"""Benchmark suites as data: every shipped suite validates, errors name the field, seeds come from
(suite, task, trial) alone, and episode scenes are drawn from the seed."""
from __future__ import annotations

import re
import subprocess
import sys

import pytest

from culinarycut.bench.episode_scene import DISTRACTOR_SLOTS_M, episode_spec, suite_episodes
from culinarycut.bench.knife_reach import distractors_in_reach
from culinarycut.bench.suite import SuiteError, available_suites, episode_seed, load_suite

SHIPPED = ["smoke", "unseen-seeds", "multi-object", "unseen-language", "cross-object", "continuous-ratio",
           "split-partial", "topology-ablation", "safety-ablation", "coverage"]


def write_suite(tmp_path, body: str, name: str = "mine"):
    path = tmp_path / f"{name}.toml"
    path.write_text(f'name = "{name}"\ndescription = "a test suite"\n' + body)
    return str(path)


def test_every_shipped_suite_loads_and_the_paper_settings_are_there():
    assert set(SHIPPED) <= set(available_suites())
    suites = {name: load_suite(name) for name in SHIPPED}
    seeds = suites["unseen-seeds"]
    assert {t.style for t in seeds.tasks} == {"normal", "bias", "guillotine", "saw"}
    assert len({t.food for t in seeds.tasks}) == 7
    # 13 cut states per style and food: middle, nine ratios, three splits (the paper's "Data Statistics").
    assert len([t for t in seeds.tasks if t.food == "apple" and t.style == "saw"]) == 13
    assert all(t.trials == 20 for t in seeds.tasks)
    assert {t.distractors for t in suites["multi-object"].tasks} == {2, 3, 4}
    coverage = suites["coverage"]
    assert {(t.food, t.style) for t in coverage.tasks} == {(t.food, t.style) for t in seeds.tasks}  # every pair
    assert len(coverage.tasks) == 28 and {t.state for t in coverage.tasks} == {"middle"}
    assert {t.language for t in suites["unseen-language"].tasks} == {"held_out"}
    assert {t.group for t in suites["cross-object"].tasks} == {"train-objects", "unseen-objects"}
    ratio = suites["continuous-ratio"].tasks
    assert {t.ratio for t in ratio} == {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9}
    assert {t.side for t in ratio} == {"left", "right"} and {t.food for t in ratio} == {"banana", "cucumber"}
    assert {t.pieces for t in suites["split-partial"].tasks} == {3, 4, 5}
    assert {t.topology for t in suites["topology-ablation"].tasks} == {True, False}


@pytest.mark.parametrize("body, message", [
    ('[[tasks]]\nfood = "durian"\nstate = "middle"\n', r"suite.tasks\[0\].food: 'durian' is not one of"),
    ('[[tasks]]\nfood = ["apple", "kiwi"]\nstate = "middle"\n', r"suite.tasks\[0\].food\[1\]: 'kiwi'"),
    ('[[tasks]]\nfood = "apple"\nstate = "middle"\ncolour = "red"\n', r"suite.tasks\[0\].*'colour' was unexpected"),
    # an unknown field: the message lists the fields that may stand there
    ('[[tasks]]\nfood = "apple"\nstate = "middle"\ncolour = "red"\n',
     r"'colour' was unexpected\); valid fields: name, group, food, style, state, ratio, side, pieces, distractors, "
     r"topology, scene, language, quality, mpm, trials, max_episode_steps, material_overrides, safety_limiter, "
     r"safety$"),
    ('mpm = { cfl = 1.5 }\n[[tasks]]\nfood = "apple"\nstate = "middle"\n', r"^suite.mpm.cfl: 1.5 is greater than"),
    ('mpm = { activity_radius = 2 }\n[[tasks]]\nfood = "apple"\nstate = "middle"\n',
     r"^suite.mpm.activity_radius: 2 is greater than"),
    ('randomize = { yaw = 5 }\n[[tasks]]\nfood = "apple"\nstate = "middle"\n',
     r"^suite.randomize: .*'yaw' was unexpected\); valid fields: position_m, yaw_deg, scale$"),
    ('[report]\nratio_radar = true\n[[tasks]]\nfood = "apple"\nstate = "middle"\n',
     r"^suite: .*'report' was unexpected\); valid fields: name, description, trials, .*, tasks$"),
    ('trials = 0\n[[tasks]]\nfood = "apple"\nstate = "middle"\n', r"suite.trials: 0 is less than the minimum"),
    ('[[tasks]]\nfood = "apple"\nstate = "ratio"\nratio = 1.5\n', r"suite.tasks\[0\].ratio"),
    ('[[tasks]]\nfood = "apple"\n', r"suite.tasks\[0\]: 'state' is a required property"),
    ('[[tasks]]\nfood = "apple"\nstate = "middle"\n[[tasks]]\nfood = "apple"\nstate = "middle"\n', "repeat"),
    ('tasks = [', "not valid TOML"),
])
def test_bad_suites_are_refused_naming_the_field(tmp_path, body, message):
    with pytest.raises(SuiteError, match=message):
        load_suite(write_suite(tmp_path, body))


def test_list_fields_expand_into_named_tasks(tmp_path):
    suite = load_suite(write_suite(tmp_path, 'trials = 3\n[[tasks]]\nfood = ["apple", "banana"]\nstate = "ratio"\n'
                                             'ratio = [0.2, 0.7]\nside = "right"\ntopology = [true, false]\n'))
    names = [t.name for t in suite.tasks]
    assert len(names) == 8 and "apple/normal/ratio-0.2-right" in names
    assert "banana/normal/ratio-0.7-right/topology-off" in names
    assert suite.episode_count == 24


def test_mpm_overrides_reach_the_episode_scene_task_over_suite(tmp_path):
    suite = load_suite(write_suite(tmp_path, 'mpm = { cfl = 0.3 }\n[[tasks]]\nfood = "apple"\nstate = "middle"\n'
                                             '[[tasks]]\nfood = "banana"\nstate = "middle"\n'
                                             'mpm = { cfl = 0.5, particles_per_cell = 6, activity_radius = 0.04 }\n'))
    apple, banana = (episode_spec(suite, task, 0).scene for task in suite.tasks)
    assert apple["mpm"] == {"cfl": 0.3}
    assert banana["mpm"] == {"cfl": 0.5, "particles_per_cell": 6, "activity_radius": 0.04}
    assert "mpm" not in episode_spec(load_suite("smoke"), load_suite("smoke").tasks[0], 0).scene


def test_seeds_come_from_suite_task_and_trial_only():
    assert episode_seed("smoke", "apple/normal/middle", 3) == episode_seed("smoke", "apple/normal/middle", 3)
    seeds = {episode_seed(s, t, i) for s in ("a", "b") for t in ("x", "y") for i in range(50)}
    assert len(seeds) == 200 and all(0 <= s < 2**63 for s in seeds)
    suite = load_suite("multi-object")
    first, again = suite_episodes(suite)[:5], suite_episodes(load_suite("multi-object"))[:5]
    assert [e.scene for e in first] == [e.scene for e in again]  # same inputs, same scenes


def test_distractors_are_other_foods_in_distinct_slots_around_the_target():
    suite = load_suite("multi-object")
    task = next(t for t in suite.tasks if t.distractors == 4)
    for trial in range(10):
        objects = episode_spec(suite, task, trial).scene["objects"]
        assert len(objects) == 5 and objects[0]["food"] == task.food
        assert len({o["food"] for o in objects}) == 5  # the target is the only one of its kind
        target = objects[0]["pose"]["position"]
        offsets = {(round(o["pose"]["position"][0] - target[0], 1), round(o["pose"]["position"][1] - target[1], 1))
                   for o in objects[1:]}
        assert len(offsets) == 4
        for dx, dy in offsets:  # each distractor sits in one of the slots, give or take the jitter
            assert min(abs(dx - sx) + abs(dy - sy) for sx, sy in DISTRACTOR_SLOTS_M) < 0.1


def test_no_distractor_lies_where_the_knife_reaches_while_it_cuts_the_target():
    """Every multi-object episode's distractors clear the knife's sweep (blade, handle, saw strokes) for cuts
    anywhere from 0.1 to 0.9 of the target's length; the sweep is checked on a scene the oracle failed in."""
    for episode in suite_episodes(load_suite("multi-object")):
        assert distractors_in_reach(episode.scene["objects"]) == [], episode.key
    # A banana saw cut the oracle failed when a 22 cm slot behind the target held an apple: its handle
    # pressed on the apple at 113 N (2026-12-07), and the sweep says so.
    banana = {"food": "banana", "scale": 0.945, "pose": {"position": [0.516, 0.011, 0.037],
                                                         "quaternion": [0.673, 0.0, 0.0, 0.740]}}
    apple = {"food": "apple", "scale": 1.069, "pose": {"position": [0.313, 0.010, 0.058],
                                                       "quaternion": [0.731, 0.0, 0.0, 0.683]}}
    assert distractors_in_reach([banana, apple]) == [1]
    assert distractors_in_reach([banana, {**apple, "pose": {**apple["pose"], "position": [0.80, 0.010, 0.058]}}]) == []


@pytest.mark.parametrize("argv, message", [
    (["bench", "run", "no-such-suite"], "unknown suite 'no-such-suite'; choose one of: .*smoke"),
    (["bench", "run", "smoke", "--policy", "telepathy"], "unknown policy 'telepathy'; choose one of: grpc, noop, "),
    (["bench", "run", "smoke", "--workers", "0"], "--workers must be at least 1"),
    (["bench", "run", "smoke", "--policy", "random", "--policy-option", "scale=7"], "scale must be in"),
    (["bench", "run", "smoke", "--policy", "random", "--policy-option", "scale"], "'scale': use key=value"),
    (["bench", "show", "no-such-suite"], "unknown suite"),
])
def test_the_cli_refuses_bad_input_with_exit_code_2(argv, message):
    done = subprocess.run([sys.executable, "-m", "culinarycut", *argv], capture_output=True, text=True, timeout=60)
    assert done.returncode == 2, done.stderr
    assert re.search(message, done.stderr), done.stderr


def test_a_server_that_is_down_is_named_before_any_episode(tmp_path):
    done = subprocess.run([sys.executable, "-m", "culinarycut", "bench", "run", "smoke", "--server", "127.0.0.1:1",
                           "--out", str(tmp_path / "run"), "--no-progress"], capture_output=True, text=True, timeout=60)
    assert done.returncode == 1
    assert "server 127.0.0.1:1 is not reachable" in done.stderr
    assert not (tmp_path / "run").exists()  # nothing was started


@pytest.mark.parametrize("successes, trials, low, high", [
    (5, 10, 0.2366, 0.7634),   # Wilson's interval as tabulated (Newcombe 1998, method 3)
    (0, 20, 0.0, 0.1611),
    (20, 20, 0.8389, 1.0),
    (81, 263, 0.2553, 0.3662),
])
def test_wilson_intervals_match_published_values(successes, trials, low, high):
    from culinarycut.bench.stats import wilson_interval
    assert wilson_interval(successes, trials) == pytest.approx((low, high), abs=1e-4)

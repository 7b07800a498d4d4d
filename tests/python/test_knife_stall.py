"""A food too hard for the Panda says so: the step reports the knife stalled (in the food with a joint at its
effort limit), and the benchmark row of a failed episode ends with knife_stalled, not a silent failure."""
from __future__ import annotations

import sqlite3
import subprocess
import sys

from culinarycut import CulinaryCutEnv
from culinarycut.policies import ScriptedOracle
from culinarycut.scenes import CUTTING_EFFECTS

# 10 kJ/m^2 is 80 times a cucumber's toughness: its edge alone would need about 300 N, several times what
# the Panda's wrist gives.
UNCUTTABLE = {"fracture_toughness_j_m2": 1e4}


def scene(material_overrides: dict, max_steps: int) -> dict:
    return {"quality": "draft", "effects": CUTTING_EFFECTS, "max_episode_steps": max_steps,
            "objects": [{"food": "cucumber", "material_overrides": material_overrides}],
            "task": {"instruction": "cut the cucumber in the middle"}}


def stalled_steps(address: str, material_overrides: dict, max_steps: int) -> tuple[int, bool]:
    with CulinaryCutEnv(address, scene=scene(material_overrides, max_steps)) as env:
        env.reset(seed=0)
        oracle = ScriptedOracle(env.client, env.session_id)
        oracle.reset()
        stalled, info, done = 0, {}, False
        while not (oracle.finished or done):
            _, values = oracle.act()
            _, _, terminated, truncated, info = env.step(values)
            stalled += int(info["knife_stalled"])
            done = terminated or truncated
        return stalled, bool(info.get("success"))


def test_a_food_too_tough_to_cut_stalls_the_knife_and_a_real_cucumber_does_not(address):
    stalled, success = stalled_steps(address, UNCUTTABLE, max_steps=120)
    assert stalled > 0 and not success
    stalled, success = stalled_steps(address, {}, max_steps=0)
    assert stalled == 0 and success


def test_a_stalled_episode_is_recorded_as_knife_stalled(tmp_path, address):
    suite = tmp_path / "uncuttable.toml"
    suite.write_text('''name = "uncuttable"
description = "A cucumber far tougher than the Panda can cut."
trials = 1
max_episode_steps = 120
quality = "draft"
material_overrides = { fracture_toughness_j_m2 = 1e4 }

[[tasks]]
food = "cucumber"
state = "middle"
''')
    out = tmp_path / "run"
    done = subprocess.run([sys.executable, "-m", "culinarycut", "bench", "run", str(suite), "--policy", "oracle",
                           "--server", address, "--out", str(out)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    db = sqlite3.connect(out / "results.sqlite")
    try:
        outcome, end_reason, stalled = db.execute("SELECT outcome, end_reason, stalled_steps FROM episodes").fetchone()
    finally:
        db.close()
    assert (outcome, end_reason) == ("failure", "knife_stalled") and stalled > 0

"""Success needs the cut's orientation as well as its position (paper, "Success Criteria"): through the real
server, a vertical cut at the right place fails a bias task, and its measured cut surface and the blade's
pose in the food say why."""
from __future__ import annotations

import math

from culinarycut.env import CulinaryCutEnv
from culinarycut.policies import ScriptedOracle

CUTTING_EFFECTS = {"mpm": True, "damage": True, "friction": True, "topology": True, "force_sensing": True}
TOLERANCE_DEG = 9.0  # the success rule's angle tolerance (sim/task/success_metrics.h)


def test_a_vertical_cut_fails_a_bias_task(client):
    scene = {"quality": "draft", "effects": CUTTING_EFFECTS, "objects": [{"food": "cucumber"}],
             "task": {"instruction": "bias cut the cucumber at the middle"}}
    with CulinaryCutEnv(client=client, scene=scene) as env:
        env.reset(seed=1)
        oracle = ScriptedOracle(client, env.session_id)
        oracle.reset(instruction="normal cut the cucumber at the middle")  # vertical, not the task's bias
        info = {}
        for _ in range(2000):
            if oracle.finished:
                break
            _, values = oracle.act()
            _, _, _, _, info = env.step(values)
    score = info["task"]
    assert len(info["food"]["pieces"]) == 2, score
    cut = score["required"][0]
    assert cut["placed"] and cut["position_ok"], score  # in the right place ...
    assert cut["angle_measured"] and not cut["angle_ok"], score  # ... but upright
    # A vertical plane misses the bias range (20-35 deg from vertical) by at least 20 deg, less the fit's few.
    assert math.degrees(cut["angle_error_rad"]) > 15.0, score
    # The blade's pose in the food says the same, exactly: the oracle held it upright, 0.35 rad (20 deg) short.
    assert cut["blade_angle_measured"], score
    assert abs(math.degrees(cut["blade_angle_error_rad"]) - 20.05) < 0.5, score
    assert not info["success"] and "blade off by" in score["summary"], score

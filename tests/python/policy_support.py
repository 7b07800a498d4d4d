"""Shared by the policy adapter tests: this tree's policies/ on sys.path, a statistics file in the
dataset_statistics.json layout, a one-task suite of short draft episodes."""
from __future__ import annotations

import json
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
POLICIES = REPO / "policies"
if str(POLICIES) not in sys.path:
    sys.path.insert(0, str(POLICIES))  # this tree's adapters, ahead of any installed copy

DELTA_KEY = "culinarycut_delta"  # 7-D delta end-effector actions (OpenVLA, OpenVLA-OFT, Octo)
RDT_KEY = "culinarycut_rdt"      # 16-D absolute states (RDT): 7 joints, TCP xyz, 6-D rotation


def _entry(low, high, mask=None) -> dict:
    low, high = list(map(float, low)), list(map(float, high))
    entry = {"mean": [(a + b) / 2 for a, b in zip(low, high)], "std": [(b - a) / 4 for a, b in zip(low, high)],
             "min": [a * 1.5 for a in low], "max": [b * 1.5 for b in high], "q01": low, "q99": high}
    if mask is not None:
        entry["mask"] = list(mask)
    return entry


def statistics_document() -> dict:
    """Two datasets: small asymmetric delta bounds (gripper unmasked), and RDT's state bounds."""
    delta_low = [-0.004, -0.005, -0.006, -0.02, -0.02, -0.03, 0.0]
    delta_high = [0.006, 0.005, 0.004, 0.02, 0.03, 0.02, 1.0]
    proprio_low = [-0.9, -0.9, -0.1, -3.2, -3.2, -3.2, 0.0, 0.0]
    proprio_high = [0.9, 0.9, 1.2, 3.2, 3.2, 3.2, 0.0, 0.0]
    rdt_low = [-2.9, -1.8, -2.9, -3.1, -2.9, -0.1, -2.9, -0.9, -0.9, -0.1] + [-1.0] * 6
    rdt_high = [2.9, 1.8, 2.9, -0.1, 2.9, 3.8, 2.9, 0.9, 0.9, 1.2] + [1.0] * 6
    return {
        DELTA_KEY: {"action": _entry(delta_low, delta_high, [True] * 6 + [False]),
                    "proprio": _entry(proprio_low, proprio_high, [True] * 6 + [False] * 2),
                    "num_transitions": 1000, "num_trajectories": 10},
        RDT_KEY: {"action": _entry(rdt_low, rdt_high), "proprio": _entry(rdt_low, rdt_high),
                  "num_transitions": 1000, "num_trajectories": 10},
    }


def write_statistics(folder: Path) -> Path:
    path = folder / "dataset_statistics.json"
    path.write_text(json.dumps(statistics_document(), indent=1))
    return path


def write_suite(folder: Path, steps: int, trials: int = 1) -> Path:
    """A one-task suite (a softened cucumber, cut in the middle, draft) of `steps`-step episodes."""
    path = folder / "policy-adapters.toml"
    path.write_text(f'''name = "policy-adapters"
description = "Short draft episodes for the policy adapter tests."
trials = {trials}
max_episode_steps = {steps}
quality = "draft"
material_overrides = {{ youngs_modulus_pa = 2e5 }}

[[tasks]]
food = "cucumber"
state = "middle"
''')
    return path


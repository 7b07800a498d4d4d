"""Example normalisation statistics in the dataset_statistics.json layout, for the stand-ins' users (tests,
the overhead benchmark, trying an adapter without a dataset): two datasets, 7-D delta end-effector
actions in metres and radians and RDT's 16-D absolute states, each saying its layout and units as
CulinaryCut's export does. Not the statistics of any real data."""
from __future__ import annotations

import json
from pathlib import Path

from culinarycut.datasets.adapter_layouts import DELTA_EE_ACTION, DELTA_EE_PROPRIO, RDT_STATE, RDT_UNITS

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
                    "num_transitions": 1000, "num_trajectories": 10, "action_layout": DELTA_EE_ACTION,
                    "proprio_layout": DELTA_EE_PROPRIO, "action_units": "metres_radians"},
        RDT_KEY: {"action": _entry(rdt_low, rdt_high), "proprio": _entry(rdt_low, rdt_high),
                  "num_transitions": 1000, "num_trajectories": 10, "action_layout": RDT_STATE,
                  "proprio_layout": RDT_STATE, "action_units": RDT_UNITS},
    }


def write_statistics(folder: Path) -> Path:
    """folder/dataset_statistics.json with statistics_document()."""
    path = folder / "dataset_statistics.json"
    path.write_text(json.dumps(statistics_document(), indent=1))
    return path

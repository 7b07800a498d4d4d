"""dataset_statistics.json in OpenVLA / Octo's layout: per dataset name, action and proprio
mean/std/min/max/q01/q99/mask, num_transitions and num_trajectories (what their un-normalisation
reads; mask False marks dimensions left un-normalised, none here since there is no gripper)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np


def _summary(values: np.ndarray) -> dict:
    values = values.astype(np.float64)
    return {"mean": values.mean(0).tolist(), "std": values.std(0).tolist(), "min": values.min(0).tolist(),
            "max": values.max(0).tolist(), "q01": np.quantile(values, 0.01, axis=0).tolist(),
            "q99": np.quantile(values, 0.99, axis=0).tolist(), "mask": [True] * values.shape[1]}


def dataset_statistics(name: str, actions: list[np.ndarray], proprio: list[np.ndarray]) -> dict:
    if not actions:
        raise ValueError("no kept episodes: nothing to take statistics of")
    all_actions, all_proprio = np.concatenate(actions), np.concatenate(proprio)
    return {name: {"action": _summary(all_actions), "proprio": _summary(all_proprio),
                   "num_transitions": int(len(all_actions)), "num_trajectories": len(actions)}}


def write_statistics(path: Path, statistics: dict) -> None:
    path.write_text(json.dumps(statistics, indent=2))

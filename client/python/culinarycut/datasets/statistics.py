"""dataset_statistics.json in OpenVLA / Octo's layout: per key, action and proprio
mean/std/min/max/q01/q99/mask, num_transitions and num_trajectories (what their un-normalisation reads;
mask False marks dimensions left un-normalised).

Three keys per dataset `name` (adapter_layouts.py computes the layouts):
- `name`: the recorded actions (the control mode's values) and proprio (joints, TCP pose): generic, for
  training code of one's own; no adapter accepts it.
- `name_delta_ee`: what the OpenVLA, OpenVLA-OFT and Octo adapters read: delta end-effector actions in
  metres and radians (7, gripper masked) and LIBERO's eef proprio (8, gripper slots masked).
- `name_rdt`: what the RDT adapter reads with normalization=bounds: its 16 unified-vector state and action
  slots.
Each entry names its layout and units (`action_layout`, `proprio_layout`, `action_units`, and the
dimension names), so an adapter can refuse statistics that are not in the layout it executes.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from culinarycut.datasets.adapter_layouts import (DELTA_EE_ACTION, DELTA_EE_ACTION_NAMES, DELTA_EE_PROPRIO,
                                                  DELTA_EE_PROPRIO_NAMES, RDT_STATE, RDT_STATE_NAMES, RDT_UNITS)

DELTA_EE_SUFFIX = "_delta_ee"
RDT_SUFFIX = "_rdt"
FLAT = 1e-9  # a range below this is a constant


def _summary(values: np.ndarray, mask: list[bool] | None = None) -> dict:
    values = values.astype(np.float64)
    return {"mean": values.mean(0).tolist(), "std": values.std(0).tolist(), "min": values.min(0).tolist(),
            "max": values.max(0).tolist(), "q01": np.quantile(values, 0.01, axis=0).tolist(),
            "q99": np.quantile(values, 0.99, axis=0).tolist(),
            "mask": list(mask) if mask is not None else [True] * values.shape[1]}


def _entry(actions: list[np.ndarray], proprio: list[np.ndarray], action_mask=None, proprio_mask=None) -> dict:
    all_actions, all_proprio = np.concatenate(actions), np.concatenate(proprio)
    return {"action": _summary(all_actions, action_mask), "proprio": _summary(all_proprio, proprio_mask),
            "num_transitions": int(len(all_actions)), "num_trajectories": len(actions)}


def dataset_statistics(name: str, actions: list[np.ndarray], proprio: list[np.ndarray], *,
                       control_mode: str, action_names: list[str], proprio_names: list[str]) -> dict:
    """The generic key: the recorded actions and proprio as they are."""
    if not actions:
        raise ValueError("no kept episodes: nothing to take statistics of")
    entry = _entry(actions, proprio)
    entry.update(action_layout=control_mode, proprio_layout="joints_tcp_pose_quat", action_units=control_mode,
                 action_names=action_names, proprio_names=proprio_names)
    return {name: entry}


def delta_ee_statistics(name: str, actions: list[np.ndarray], proprio: list[np.ndarray]) -> dict:
    """The OpenVLA / OpenVLA-OFT / Octo key: the gripper dimensions are not normalised (mask False)."""
    entry = _entry(actions, proprio, [True] * 6 + [False], [True] * 6 + [False] * 2)
    entry.update(action_layout=DELTA_EE_ACTION, proprio_layout=DELTA_EE_PROPRIO, action_units="metres_radians",
                 action_names=DELTA_EE_ACTION_NAMES, proprio_names=DELTA_EE_PROPRIO_NAMES)
    return {name + DELTA_EE_SUFFIX: entry}


def rdt_statistics(name: str, actions: list[np.ndarray], states: list[np.ndarray]) -> dict:
    """The RDT key: a slot that never changes (max = min) is masked, min/max cannot scale it."""
    varies = [bool(v) for v in np.ptp(np.concatenate(states + actions), axis=0) > FLAT]
    entry = _entry(actions, states, varies, varies)
    entry.update(action_layout=RDT_STATE, proprio_layout=RDT_STATE, action_units=RDT_UNITS,
                 action_names=RDT_STATE_NAMES, proprio_names=RDT_STATE_NAMES)
    return {name + RDT_SUFFIX: entry}


def write_statistics(path: Path, statistics: dict) -> None:
    path.write_text(json.dumps(statistics, indent=2))

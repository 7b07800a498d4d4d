"""`culinarycut data export`: the kept episodes in the formats training code reads, plus the
dataset_statistics.json the policy adapters read (statistics.py: a generic key and one per adapter layout)."""
from __future__ import annotations

import logging
from pathlib import Path

from culinarycut.datasets.adapter_layouts import (DELTA_MODES, delta_ee_actions, delta_ee_proprio, rdt_actions,
                                                  rdt_states)
from culinarycut.datasets.episodes import action_names, iter_episodes, proprio, proprio_names
from culinarycut.datasets.export_lerobot import export_lerobot
from culinarycut.datasets.export_libero import export_libero
from culinarycut.datasets.export_rdt import export_rdt
from culinarycut.datasets.export_robomimic import export_robomimic
from culinarycut.datasets.statistics import dataset_statistics, delta_ee_statistics, rdt_statistics, write_statistics

FORMATS = ("robomimic", "libero", "lerobot", "rdt")
DEFAULT_FORMATS = ("robomimic", "lerobot", "rdt")  # libero needs end-effector data (export_libero.py)
STATISTICS_NAME = "dataset_statistics.json"
log = logging.getLogger(__name__)


def export(root: Path, out: Path, formats: tuple[str, ...] = DEFAULT_FORMATS,
           name: str = "culinarycut") -> dict[str, Path]:
    unknown = set(formats) - set(FORMATS)
    if unknown:
        raise ValueError(f"unknown formats {sorted(unknown)}; choose from {', '.join(FORMATS)}")
    out.mkdir(parents=True, exist_ok=True)
    written = {}
    if "robomimic" in formats:
        written["robomimic"] = export_robomimic(root, out / "robomimic" / f"{name}.hdf5")
    if "libero" in formats:
        written["libero"] = export_libero(root, out / "libero")
    if "lerobot" in formats:
        written["lerobot"] = export_lerobot(root, out / "lerobot")
    if "rdt" in formats:
        written["rdt"] = export_rdt(root, out / "rdt")
    written["statistics"] = out / STATISTICS_NAME
    write_statistics(written["statistics"], all_statistics(root, name))
    return written


def all_statistics(root: Path, name: str) -> dict:
    """The generic key, the RDT key, and (for end-effector control modes) the delta end-effector key."""
    actions, states, delta, delta_proprio, rdt_action, rdt_state = [], [], [], [], [], []
    modes = set()
    first = None
    for _, meta, steps in iter_episodes(root):
        modes.add(meta["control_mode"])
        first = first or (meta["control_mode"], steps)
        actions.append(steps["actions"])
        states.append(proprio(steps))
        rdt_action.append(rdt_actions(steps))
        rdt_state.append(rdt_states(steps))
        if meta["control_mode"] in DELTA_MODES:
            delta.append(delta_ee_actions(steps, meta["control_mode"]))
            delta_proprio.append(delta_ee_proprio(steps))
    if not actions:
        raise ValueError(f"{root}: no kept episodes: nothing to take statistics of")
    if len(modes) != 1:
        raise ValueError(f"{root}: episodes of several control modes ({', '.join(sorted(modes))}) cannot share "
                         "one action statistic")
    mode, steps = first
    statistics = dataset_statistics(name, actions, states, control_mode=mode,
                                    action_names=action_names(mode, steps["actions"].shape[1]),
                                    proprio_names=proprio_names(steps))
    if delta:
        statistics.update(delta_ee_statistics(name, delta, delta_proprio))
    else:
        log.warning("no delta end-effector statistics (OpenVLA, OpenVLA-OFT, Octo): control mode %s has no "
                    "end-effector target; they need %s data", mode, " or ".join(DELTA_MODES))
    statistics.update(rdt_statistics(name, rdt_action, rdt_state))
    return statistics

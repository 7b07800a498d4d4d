"""The kept episodes of a generated dataset in a fixed order (by job key), and the per-step quantities
every export carries, named once here."""
from __future__ import annotations

from pathlib import Path
from typing import Iterator

import numpy as np

from culinarycut.datasets.episode_file import read_episode
from culinarycut.datasets.store import GenerationStore, require_dataset

# Contact phases as integers (the name list is stored beside the codes in every export).
PHASES = ("approach", "descend", "cut", "retreat", "transfer", "follow")


def kept_files(root: Path) -> list[Path]:
    require_dataset(root)
    with GenerationStore(root) as store:
        return [root / row["file"] for row in store.rows(kept_only=True)]


def iter_episodes(root: Path) -> Iterator[tuple[int, dict, dict[str, np.ndarray]]]:
    """(episode index, meta, steps) for each kept episode."""
    for index, path in enumerate(kept_files(root)):
        meta, steps = read_episode(path)
        yield index, meta, steps


def scene_conditions(meta: dict) -> dict:
    """Where an episode was recorded: its scene (table or kitchen) and whether topology was on, as every
    export carries them (episodes recorded before scenes were drawn were on the table)."""
    effects = meta.get("resolved_scene", {}).get("effects", {})
    return {"scene": meta.get("variation", {}).get("scene", "table"), "topology": bool(effects.get("topology", True))}


def camera_names(steps: dict) -> list[str]:
    return sorted(name[len("obs/"):-len("_rgb")] for name in steps if name.startswith("obs/") and name.endswith("_rgb"))


def proprio(steps: dict) -> np.ndarray:
    """The proprioceptive state: joint positions (rad) then the TCP pose (m x3, quaternion wxyz)."""
    return np.concatenate([steps["obs/qpos"], steps["obs/tcp_pose"]], axis=1).astype(np.float32)


def proprio_names(steps: dict) -> list[str]:
    joints = [f"joint_{i}_rad" for i in range(steps["obs/qpos"].shape[1])]
    return joints + ["tcp_x_m", "tcp_y_m", "tcp_z_m", "tcp_qw", "tcp_qx", "tcp_qy", "tcp_qz"]


def action_names(control_mode: str, size: int) -> list[str]:
    if control_mode == "pd_ee_pose_quat" and size == 7:
        return ["x_m", "y_m", "z_m", "qw", "qx", "qy", "qz"]
    if control_mode == "pd_ee_delta_pose" and size == 6:
        return ["dx", "dy", "dz", "droll", "dpitch", "dyaw"]
    return [f"{control_mode}_{i}" for i in range(size)]


def phase_codes(steps: dict) -> np.ndarray:
    return np.array([PHASES.index(p) if p in PHASES else -1 for p in steps["phase"]], dtype=np.int8)

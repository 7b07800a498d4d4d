"""LIBERO's HDF5 layout (scripts/create_dataset.py of Lifelong-Robot-Learning/LIBERO), one file per task as
LIBERO keeps them (`<instruction>_demo.hdf5`), read by its robomimic-based loader
(libero/lifelong/datasets.py get_dataset: SequenceDataset over obs keys such as agentview_rgb,
eye_in_hand_rgb, gripper_states, joint_states).

data attrs: env_name, env_args (robomimic's env metadata), problem_info (language_instruction),
macros_image_convention, num_demos, total. demo_i: obs/agentview_rgb (front camera), obs/eye_in_hand_rgb
(wrist camera, when recorded), obs/gripper_states (2 finger joints: 0, the knife has none),
obs/joint_states, obs/ee_states = [ee_pos, ee_ori], ee_ori the TCP rotation as robosuite's quat2axisangle
(rotation_vector.py), actions in robosuite's OSC_POSE units (delta position / 0.05 m, delta rotation as
an axis-angle / 0.5 rad, clipped to [-1, 1] as the controller clips; gripper -1, open), states,
robot_states (get_robot_state_vector: gripper qpos, eef pos, eef quaternion xyzw), rewards, dones; attrs
num_samples, model_file (the resolved scene), init_state (the seed), the episode's instructions.
Images are upright (image convention "opencv"), where LIBERO's own are stored upside down ("opengl").
"""
from __future__ import annotations

import json
import re
from pathlib import Path

import h5py
import numpy as np

from culinarycut.datasets.adapter_layouts import (DELTA_MODES, ROBOSUITE_OSC_UNIT_M, ROBOSUITE_OSC_UNIT_RAD,
                                                  delta_ee_actions)
from culinarycut.datasets.episodes import iter_episodes, scene_conditions
from culinarycut.datasets.export_robomimic import GYM_ENV_NAME, robomimic_env_args
from culinarycut.datasets.rotation_vector import tcp_rotation_vector
from culinarycut.geometry import quat_from_axis_angle, quat_mul, quat_to_axis_angle

GRIPPER_OPEN = -1.0  # robosuite's gripper action: -1 open, 1 closed
CAMERA_KEYS = {"front": "agentview_rgb", "wrist": "eye_in_hand_rgb"}


def libero_actions(steps: dict, control_mode: str) -> np.ndarray:
    """(T, 7) OSC_POSE actions: the delta end-effector action (adapter_layouts.py, rotation as XYZ Euler
    angles of R_target R_tcp^T) with its rotation as an axis-angle, in OSC units, and an open gripper."""
    delta = delta_ee_actions(steps, control_mode)
    rotvec = np.array([euler_xyz_to_axis_angle(angles) for angles in delta[:, 3:6]]).reshape(-1, 3)
    osc = np.concatenate([delta[:, :3] / ROBOSUITE_OSC_UNIT_M, rotvec / ROBOSUITE_OSC_UNIT_RAD], axis=1)
    return np.concatenate([np.clip(osc, -1.0, 1.0), np.full((len(osc), 1), GRIPPER_OPEN)], axis=1)


def euler_xyz_to_axis_angle(angles) -> np.ndarray:
    """The rotation R = Rx(a) Ry(b) Rz(c) as an axis-angle (the shorter way round)."""
    x, y, z = (quat_from_axis_angle(np.eye(3)[i] * angle) for i, angle in enumerate(angles))
    return quat_to_axis_angle(quat_mul(quat_mul(x, y), z))


def libero_obs(steps: dict) -> dict[str, np.ndarray]:
    poses = np.asarray(steps["obs/tcp_pose"], dtype=np.float64)
    ee_ori = np.array([tcp_rotation_vector(q) for q in poses[:, 3:7]]).reshape(-1, 3)
    obs = {key: steps[f"obs/{camera}_rgb"] for camera, key in CAMERA_KEYS.items() if f"obs/{camera}_rgb" in steps}
    obs.update(gripper_states=np.zeros((len(poses), 2)), joint_states=steps["obs/qpos"],
               ee_states=np.concatenate([poses[:, :3], ee_ori], axis=1), ee_pos=poses[:, :3], ee_ori=ee_ori)
    return obs


def robot_states(steps: dict) -> np.ndarray:
    """LIBERO's get_robot_state_vector: gripper qpos (2), eef pos (3), eef quaternion (x, y, z, w)."""
    poses = np.asarray(steps["obs/tcp_pose"], dtype=np.float64)
    return np.concatenate([np.zeros((len(poses), 2)), poses[:, :3], poses[:, 4:7], poses[:, 3:4]], axis=1)


def task_file_name(instruction: str) -> str:
    return re.sub(r"[^a-z0-9.]+", "_", instruction.lower()).strip("_") + "_demo.hdf5"


def export_libero(root: Path, out: Path) -> Path:
    """One LIBERO file per task (cut spec) in the folder `out`; ValueError for data without a TCP target."""
    tasks: dict[str, list] = {}
    for _, meta, steps in iter_episodes(root):
        if meta["control_mode"] not in DELTA_MODES:
            raise ValueError(f"{root}: LIBERO's actions are end-effector deltas; control mode {meta['control_mode']!r} "
                             f"has no end-effector target (export LIBERO from {' or '.join(DELTA_MODES)} data)")
        tasks.setdefault(json.dumps(meta["cut_spec"], sort_keys=True), []).append((meta, steps))
    if not tasks:
        raise ValueError(f"{root}: no kept episodes to export")
    out.mkdir(parents=True, exist_ok=True)
    for index, episodes in enumerate(tasks.values()):
        instruction = episodes[0][0]["instructions"][0]
        name = task_file_name(instruction)
        path = out / name if not (out / name).exists() else out / f"task_{index}_{name}"
        write_task(path, instruction, episodes)
    return out


def write_task(path: Path, instruction: str, episodes: list) -> None:
    with h5py.File(path, "w") as file:
        data = file.create_group("data")
        total = 0
        for i, (meta, steps) in enumerate(episodes):
            demo = data.create_group(f"demo_{i}")
            for key, values in libero_obs(steps).items():
                demo.create_dataset(f"obs/{key}", data=values)
            count = len(steps["actions"])
            demo.create_dataset("actions", data=libero_actions(steps, meta["control_mode"]))
            demo.create_dataset("states", data=np.concatenate([steps["obs/qpos"], steps["obs/qvel"]], axis=1))
            demo.create_dataset("robot_states", data=robot_states(steps))
            demo.create_dataset("rewards", data=steps["rewards"].astype(np.uint8))
            demo.create_dataset("dones", data=steps["dones"].astype(np.uint8))
            demo.attrs["num_samples"] = count
            demo.attrs["model_file"] = json.dumps(meta["resolved_scene"], sort_keys=True)
            demo.attrs["init_state"] = json.dumps({"seed": meta["seed"]})
            demo.attrs["instructions"] = json.dumps(meta["instructions"])
            demo.attrs.update(scene_conditions(meta))
            total += count
        data.attrs["env_name"] = GYM_ENV_NAME
        data.attrs["env_args"] = json.dumps(robomimic_env_args(episodes[0][0]["control_mode"]))
        data.attrs["problem_info"] = json.dumps({"problem_name": "culinarycut", "domain_name": "cutting",
                                                 "language_instruction": instruction})
        data.attrs["macros_image_convention"] = "opencv"
        data.attrs["num_demos"] = len(episodes)
        data.attrs["total"] = total

"""From a model's action to a CulinaryCut control mode, and the robot state the models read; the one
place that says what happens to the gripper dimension.

The knife has no gripper (ManiSkill's `panda_stick` modes have no gripper dimension), so:
- OpenVLA, OpenVLA-OFT, Octo: the 7th action dimension (gripper, 1 = open) is read and dropped; the
  state OpenVLA-OFT sends fills its gripper slots, beyond the 6 pose values, with 0.
- RDT-1B: the right-gripper slot (10) of the unified vector is left out of the state mask, so the
  model is told it is absent, and its predicted value is ignored.
- openpi: `observation/state` carries no gripper; any action dimensions beyond the 6 pose deltas are dropped.
"""
from __future__ import annotations

import numpy as np

from culinarycut_policies.rotation import matrix_to_quat_wxyz, quat_wxyz_to_axis_angle

# pd_ee_delta_pose: 1 unit = 0.1 m of translation and 0.1 rad of rotation (docs/robot.md).
EE_DELTA_UNIT_M = 0.1
EE_DELTA_UNIT_RAD = 0.1
POSE_DIMS = 6          # x, y, z, roll, pitch, yaw deltas; a 7th (gripper) is dropped


def delta_to_ee_delta_pose(action: np.ndarray) -> tuple[str, np.ndarray]:
    """A model's delta end-effector action [dx, dy, dz (m), droll, dpitch, dyaw (rad), gripper...] in the
    root frame (the Bridge/OpenVLA convention of the statistics' units) as pd_ee_delta_pose values.
    The server clips each translation to +-0.1 m and the rotation vector to 0.1 rad per step."""
    action = np.asarray(action, dtype=np.float64).reshape(-1)
    if action.size < POSE_DIMS:
        raise ValueError(f"a delta end-effector action needs at least {POSE_DIMS} values, got {action.size}")
    values = np.concatenate([action[:3] / EE_DELTA_UNIT_M, action[3:POSE_DIMS] / EE_DELTA_UNIT_RAD])
    return "pd_ee_delta_pose", values


def pose_to_ee_pose_quat(position: np.ndarray, rotation: np.ndarray) -> tuple[str, np.ndarray]:
    """An absolute TCP pose (m, rotation matrix, world frame) as pd_ee_pose_quat [x, y, z, qw, qx, qy, qz]."""
    return "pd_ee_pose_quat", np.concatenate([np.asarray(position, dtype=np.float64), matrix_to_quat_wxyz(rotation)])


def tcp_pose(observation: dict) -> tuple[np.ndarray, np.ndarray]:
    """The knife TCP's position (m) and wxyz quaternion, world frame."""
    pose = np.asarray(observation["extra"]["tcp_pose"], dtype=np.float64)
    return pose[:3], pose[3:7]


def tcp_position_axis_angle(observation: dict) -> np.ndarray:
    """[x, y, z, rx, ry, rz]: LIBERO's eef state (position and rotation vector), the knife's TCP."""
    position, quaternion = tcp_pose(observation)
    return np.concatenate([position, quat_wxyz_to_axis_angle(quaternion)])


def pad_state(state: np.ndarray, dim: int) -> np.ndarray:
    """`state` followed by zeros (the gripper slots a knife does not have) up to `dim` values."""
    if dim < state.size:
        raise ValueError(f"the model's state has {dim} dimensions, fewer than the {state.size} pose values")
    return np.concatenate([state, np.zeros(dim - state.size)])

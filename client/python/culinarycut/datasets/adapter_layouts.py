"""The action and proprio layouts the policy adapters (culinarycut_policies) read, computed from a recorded
episode: the statistics contract between `culinarycut data export` and the adapters.

- delta end-effector (OpenVLA, OpenVLA-OFT, Octo): action `[dx, dy, dz (m), rx, ry, rz (rad), gripper]`,
  the recorded target relative to the measured TCP pose in the root frame (the rotation as XYZ Euler
  angles of `R_target R_tcp^T`, R = Rx Ry Rz: what pd_ee_delta_pose reads, in metres and radians instead
  of its 0.1 m / 0.1 rad units); gripper a constant 1 ("open", the Bridge/OpenVLA convention: nothing is
  grasped); proprio LIBERO's eef state `[x, y, z (m), rotation vector (rad), 0, 0]` (two gripper slots;
  the rotation vector as rotation_vector.py takes it, continuous through the knife's edge-down pose).
- RDT-1B: state and action in the 16 unified-vector slots the adapter fills (7 joints (rad), TCP xyz (m),
  6-D rotation: the first two columns of R); the action is the state after the step (RDT predicts states).
"""
from __future__ import annotations

import numpy as np

from culinarycut.datasets.object_frame import quat_to_matrix
from culinarycut.datasets.rotation_vector import tcp_rotation_vector

# What the statistics entries say about themselves (fields beside "action" and "proprio").
DELTA_EE_ACTION = "delta_ee_xyz_euler_xyz_gripper"
DELTA_EE_PROPRIO = "tcp_xyz_rotvec_edge_down_gripper2"  # rotation_vector.py: continuous at edge down
RDT_STATE = "rdt_unified_16"
ACTION_UNITS = ("metres_radians", "maniskill_normalised", "robosuite_osc")
RDT_UNITS = "si"  # absolute states: rad, m, and the unitless 6-D rotation

DELTA_EE_ACTION_NAMES = ["dx_m", "dy_m", "dz_m", "rx_rad", "ry_rad", "rz_rad", "gripper_open"]
DELTA_EE_PROPRIO_NAMES = ["tcp_x_m", "tcp_y_m", "tcp_z_m", "tcp_rotvec_x_rad", "tcp_rotvec_y_rad",
                          "tcp_rotvec_z_rad", "gripper_0", "gripper_1"]
# Their indices in RDT's 128-D unified vector (configs/state_vec.py): right_arm_joint_0..6_pos (0-6),
# right_eef_pos_x..z (30-32), right_eef_angle_0..5 (33-38). Slot 10 (right gripper) is not used: no gripper.
RDT_UNIFIED_SLOTS = list(range(7)) + [30, 31, 32] + list(range(33, 39))
RDT_STATE_NAMES = [f"right_arm_joint_{i}_pos_rad" for i in range(7)] + \
    ["right_eef_pos_x_m", "right_eef_pos_y_m", "right_eef_pos_z_m"] + [f"right_eef_angle_{i}" for i in range(6)]

ROBOSUITE_OSC_UNIT_M = 0.05   # robosuite's OSC_POSE (LIBERO): output_max 0.05 m and 0.5 rad, input in [-1, 1]
ROBOSUITE_OSC_UNIT_RAD = 0.5
EE_DELTA_UNIT_M = 0.1    # pd_ee_delta_pose: 1 = 0.1 m (docs/robot.md)
EE_DELTA_UNIT_RAD = 0.1  # and 0.1 rad
GRIPPER_OPEN = 1.0
DELTA_MODES = ("pd_ee_pose_quat", "pd_ee_delta_pose")  # the control modes with a TCP target to take a delta of


def matrix_to_euler_xyz(matrix: np.ndarray) -> np.ndarray:
    """Angles (rad) with R = Rx(a) Ry(b) Rz(c), the order pd_ee_pose and pd_ee_delta_pose read."""
    m = np.asarray(matrix, dtype=np.float64)
    b = np.arctan2(m[0, 2], np.hypot(m[0, 0], m[0, 1]))
    return np.array([np.arctan2(-m[1, 2], m[2, 2]), b, np.arctan2(-m[0, 1], m[0, 0])])


def delta_ee_actions(steps: dict, control_mode: str) -> np.ndarray:
    """(T, 7) delta end-effector actions in metres and radians; ValueError for modes with no TCP target."""
    actions = np.asarray(steps["actions"], dtype=np.float64)
    poses = np.asarray(steps["obs/tcp_pose"], dtype=np.float64)
    if control_mode == "pd_ee_pose_quat":
        rows = []
        for target, current in zip(actions, poses):
            rotation = quat_to_matrix(target[3:7]) @ quat_to_matrix(current[3:7]).T
            rows.append(np.concatenate([target[:3] - current[:3], matrix_to_euler_xyz(rotation)]))
        pose = np.asarray(rows).reshape(-1, 6)
    elif control_mode == "pd_ee_delta_pose":
        # the server clips normalised values to [-1, 1] first (its rotation by the vector's norm)
        rotation = actions[:, 3:6] / np.maximum(1.0, np.linalg.norm(actions[:, 3:6], axis=1, keepdims=True))
        pose = np.concatenate([np.clip(actions[:, :3], -1.0, 1.0) * EE_DELTA_UNIT_M, rotation * EE_DELTA_UNIT_RAD],
                              axis=1)
    else:
        raise ValueError(f"control mode {control_mode!r} has no end-effector target: delta end-effector "
                         "statistics need pd_ee_pose_quat or pd_ee_delta_pose data")
    return np.concatenate([pose, np.full((len(pose), 1), GRIPPER_OPEN)], axis=1)


def delta_ee_proprio(steps: dict) -> np.ndarray:
    """(T, 8): TCP position (m), rotation vector (rad, rotation_vector.py), two gripper slots at 0 (the knife
    has none)."""
    poses = np.asarray(steps["obs/tcp_pose"], dtype=np.float64)
    rotvecs = np.array([tcp_rotation_vector(q) for q in poses[:, 3:7]]).reshape(-1, 3)
    return np.concatenate([poses[:, :3], rotvecs, np.zeros((len(poses), 2))], axis=1)


def rdt_states(steps: dict) -> np.ndarray:
    """(T, 16): the state before each step in the adapter's unified-vector slots."""
    poses = np.asarray(steps["obs/tcp_pose"], dtype=np.float64)
    joints = np.asarray(steps["obs/qpos"], dtype=np.float64)[:, :7]
    ortho6d = np.array([np.concatenate([r[:, 0], r[:, 1]]) for r in map(quat_to_matrix, poses[:, 3:7])])
    return np.concatenate([joints, poses[:, :3], ortho6d.reshape(-1, 6)], axis=1)


def rdt_actions(steps: dict) -> np.ndarray:
    """(T, 16): the state after each step (the next observation's; the last step repeats the last state,
    the episode file holds no observation after it)."""
    states = rdt_states(steps)
    return np.concatenate([states[1:], states[-1:]], axis=0)

"""From a model's action to a CulinaryCut control mode, and the robot state the models read; the one
place that says what happens to the gripper dimension.

The knife has no gripper (ManiSkill's `panda_stick` modes have no gripper dimension), so:
- OpenVLA, OpenVLA-OFT, Octo: the 7th action dimension (gripper, 1 = open) is read and dropped; the
  state OpenVLA-OFT sends fills its gripper slots, beyond the 6 pose values, with 0.
- RDT-1B: the right-gripper slot (10) of the unified vector is left out of the state mask, so the
  model is told it is absent, and its predicted value is ignored.
- openpi's LIBERO layout: `observation/state` carries no gripper; any action dimensions beyond the 6 pose
  deltas are dropped. Its DROID and ALOHA layouts: openpi_layouts.py (the gripper reads closed on the
  knife, its action is ignored).
"""
from __future__ import annotations

import numpy as np
from culinarycut.datasets.adapter_layouts import (ACTION_UNITS, DELTA_EE_ACTION, DELTA_EE_PROPRIO, EE_DELTA_UNIT_M,
                                                  EE_DELTA_UNIT_RAD, ROBOSUITE_OSC_UNIT_M, ROBOSUITE_OSC_UNIT_RAD,
                                                  matrix_to_euler_xyz)
from culinarycut.datasets.object_frame import quat_to_matrix
from culinarycut.datasets.rotation_vector import tcp_rotation_vector
from culinarycut.geometry import quat_from_axis_angle

from culinarycut_policies.rotation import matrix_to_quat_wxyz
from culinarycut_policies.statistics import DatasetStatistics, StatisticsError, load_statistics, require_layout

POSE_DIMS = 6          # x, y, z, roll, pitch, yaw deltas; a 7th (gripper) is dropped
# What one unit of a delta action is, (m, rad): ours and Bridge/OpenVLA's metres and radians;
# ManiSkill's pd_ee_delta_pose (docs/robot.md); robosuite's OSC_POSE controller (LIBERO: output_max
# 0.05 m and 0.5 rad, its input clipped to [-1, 1] first).
UNIT_SCALES = {"metres_radians": (1.0, 1.0), "maniskill_normalised": (EE_DELTA_UNIT_M, EE_DELTA_UNIT_RAD),
               "robosuite_osc": (ROBOSUITE_OSC_UNIT_M, ROBOSUITE_OSC_UNIT_RAD)}
CLIPPED_UNITS = ("robosuite_osc",)
# How a delta's rotation is written: XYZ Euler angles (what pd_ee_delta_pose reads; CulinaryCut's export,
# Bridge/OpenVLA) or an axis-angle (robosuite's OSC_POSE turns its delta into a rotation with
# axisangle2quat: LIBERO-trained models). The default follows the units; option rotation_delta overrides.
ROTATION_DELTAS = ("euler_xyz", "axis_angle")
DEFAULT_ROTATION_DELTA = {"metres_radians": "euler_xyz", "maniskill_normalised": "euler_xyz",
                          "robosuite_osc": "axis_angle"}
assert set(UNIT_SCALES) == set(ACTION_UNITS)


def resolve_action_units(stats: DatasetStatistics | None, option: str | None, policy: str) -> str:
    """The units of the model's delta actions: the statistics' `action_units`, or option action_units for
    a file that does not say (a model trained elsewhere); the two must agree when both are given."""
    if option is not None and option not in UNIT_SCALES:
        raise ValueError(f"policy {policy!r}: option action_units={option!r}; choose one of {', '.join(UNIT_SCALES)}")
    declared = stats.action_units if stats is not None else None
    if declared is not None and declared not in UNIT_SCALES:
        raise StatisticsError(f"policy {policy!r}: {stats.where} has action_units {declared!r}, not delta "
                              f"end-effector units ({', '.join(UNIT_SCALES)})")
    if declared is not None and option is not None and declared != option:
        raise StatisticsError(f"policy {policy!r}: option action_units={option!r} contradicts {stats.where}'s "
                              f"action_units {declared!r}")
    units = option or declared
    if units is None:
        raise StatisticsError(f"policy {policy!r}: " + (f"{stats.where} does not say its action_units; "
                              if stats is not None else "") + "set option action_units= to one of "
                              f"{', '.join(UNIT_SCALES)} (what one unit of the model's delta action is)")
    return units


def load_delta_ee_statistics(path: str | None, key: str | None, units_option: str | None, *, policy: str,
                             proprio: bool) -> tuple[DatasetStatistics, str]:
    """(statistics, units) for OpenVLA, OpenVLA-OFT and Octo: a key in the delta end-effector layout (the
    `NAME_delta_ee` key of CulinaryCut's export), its proprio in LIBERO's eef layout when `proprio`."""
    stats = load_statistics(path, key, policy=policy, action_layout=DELTA_EE_ACTION)
    require_layout(stats, policy=policy, action_layout=DELTA_EE_ACTION,
                   proprio_layout=DELTA_EE_PROPRIO if proprio else None,
                   hint=" (`culinarycut data export` writes it under the key NAME_delta_ee: option unnorm_key)")
    return stats, resolve_action_units(stats, units_option, policy)


def resolve_rotation_delta(option: str | None, units: str, policy: str) -> str:
    if option is not None and option not in ROTATION_DELTAS:
        raise ValueError(f"policy {policy!r}: option rotation_delta={option!r}; choose one of "
                         f"{', '.join(ROTATION_DELTAS)}")
    return option or DEFAULT_ROTATION_DELTA[units]


def delta_to_ee_delta_pose(action: np.ndarray, units: str, rotation: str = "euler_xyz") -> tuple[str, np.ndarray]:
    """A model's delta end-effector action [dx, dy, dz, rotation (3), gripper...] in the root frame, in
    `units` (UNIT_SCALES), its rotation as XYZ Euler angles or an axis-angle (`rotation`), as
    pd_ee_delta_pose values (1 = 0.1 m, 0.1 rad, XYZ Euler). The server clips each translation to
    +-0.1 m and the rotation vector to 0.1 rad per step."""
    action = np.asarray(action, dtype=np.float64).reshape(-1)
    if action.size < POSE_DIMS:
        raise ValueError(f"a delta end-effector action needs at least {POSE_DIMS} values, got {action.size}")
    pose = np.clip(action[:POSE_DIMS], -1.0, 1.0) if units in CLIPPED_UNITS else action[:POSE_DIMS]
    metres, radians = UNIT_SCALES[units]
    turn = pose[3:] * radians
    if rotation == "axis_angle":
        turn = matrix_to_euler_xyz(quat_to_matrix(quat_from_axis_angle(turn)))
    values = np.concatenate([pose[:3] * (metres / EE_DELTA_UNIT_M), turn / EE_DELTA_UNIT_RAD])
    return "pd_ee_delta_pose", values


def pose_to_ee_pose_quat(position: np.ndarray, rotation: np.ndarray) -> tuple[str, np.ndarray]:
    """An absolute TCP pose (m, rotation matrix, world frame) as pd_ee_pose_quat [x, y, z, qw, qx, qy, qz]."""
    return "pd_ee_pose_quat", np.concatenate([np.asarray(position, dtype=np.float64), matrix_to_quat_wxyz(rotation)])


def tcp_pose(observation: dict) -> tuple[np.ndarray, np.ndarray]:
    """The knife TCP's position (m) and wxyz quaternion, world frame."""
    pose = np.asarray(observation["extra"]["tcp_pose"], dtype=np.float64)
    return pose[:3], pose[3:7]


def tcp_position_axis_angle(observation: dict) -> np.ndarray:
    """[x, y, z, rx, ry, rz]: LIBERO's eef state (position and rotation vector), the knife's TCP; the same
    rotation vector as the export's proprio (continuous through edge down: rotation_vector.py)."""
    position, quaternion = tcp_pose(observation)
    return np.concatenate([position, tcp_rotation_vector(quaternion)])


def pad_state(state: np.ndarray, dim: int) -> np.ndarray:
    """`state` followed by zeros (the gripper slots a knife does not have) up to `dim` values."""
    if dim < state.size:
        raise ValueError(f"the model's state has {dim} dimensions, fewer than the {state.size} pose values")
    return np.concatenate([state, np.zeros(dim - state.size)])

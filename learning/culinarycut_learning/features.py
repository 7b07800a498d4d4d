"""What the model sees, computed the same way from a recorded episode (training) and from an openpi
request in the LIBERO layout (serving), and the actions it answers in the units the openpi adapter
executes by default. One place, so training and serving cannot drift apart.

- images: the adapter's `resize_with_pad` to 224 x 224 (openpi-client's, culinarycut_policies.images),
  then a bilinear resize to the model's `image_size`; uint8 HxWx3, upright.
- state: LIBERO's eef state as the adapter sends it (`observation/state`, 8): the knife TCP's position
  (m) and rotation vector (rad, culinarycut.datasets.rotation_vector: continuous through edge down); the
  two gripper slots (always 0) are left out: 6 values.
- wrist force: the food -> knife wrench at the flange, flange frame [N x3, N m x3] (the server's
  `extra/wrist_wrench`; the adapter sends it as `observation/wrist_wrench` when the server's metadata
  asks), compressed as sign(w) log(1 + |w|): contact forces span 0 to tens of newtons.
- actions: LIBERO's OSC_POSE deltas (culinarycut.datasets.export_libero.libero_actions: the recorded
  target relative to the measured TCP, position / 0.05 m, rotation as an axis-angle / 0.5 rad, clipped
  to [-1, 1]), the 6 pose values; served with LIBERO's gripper column (-1, open) as (H, 7). The openpi
  adapter's defaults read exactly these: action_units robosuite_osc, rotation_delta axis_angle, one
  action per 20 Hz control step (model_rate_hz: the simulator's)."""
from __future__ import annotations

import numpy as np
from PIL import Image

from culinarycut.datasets.export_libero import GRIPPER_OPEN, libero_actions
from culinarycut.datasets.rotation_vector import tcp_rotation_vector
from culinarycut_policies.images import resize_with_pad

ADAPTER_IMAGE_SIZE = 224   # culinarycut_policies.openpi.IMAGE_SIZE: what the LIBERO layout sends
STATE_DIMS = 6
WRENCH_DIMS = 6
ACTION_DIMS = 6
SERVED_ACTION_DIMS = 7     # LIBERO's (H, 7): six pose deltas and the gripper


def model_image(image: np.ndarray, size: int) -> np.ndarray:
    """An RGB frame as the model sees it: the adapter's 224 x 224 resize with pad, then `size` x `size`."""
    padded = resize_with_pad(np.asarray(image, dtype=np.uint8), ADAPTER_IMAGE_SIZE, ADAPTER_IMAGE_SIZE)
    if size == ADAPTER_IMAGE_SIZE:
        return padded
    return np.asarray(Image.fromarray(padded).resize((size, size), resample=Image.BILINEAR))


def state_from_tcp_poses(poses: np.ndarray) -> np.ndarray:
    """(T, 6) float32: TCP position and rotation vector from (T, 7) [m x3, quaternion wxyz]."""
    poses = np.asarray(poses, dtype=np.float64).reshape(-1, 7)
    rotvecs = np.array([tcp_rotation_vector(q) for q in poses[:, 3:7]]).reshape(-1, 3)
    return np.concatenate([poses[:, :3], rotvecs], axis=1).astype(np.float32)


def state_from_request(state: np.ndarray) -> np.ndarray:
    """(6,) float32 from the LIBERO layout's `observation/state` (8: position, rotation vector, 2 gripper slots)."""
    state = np.asarray(state, dtype=np.float64).reshape(-1)
    if state.size < STATE_DIMS:
        raise ValueError(f"observation/state: expected at least {STATE_DIMS} values (TCP position and rotation "
                         f"vector), got {state.size}")
    return state[:STATE_DIMS].astype(np.float32)


def compress_wrench(wrench: np.ndarray) -> np.ndarray:
    """sign(w) log(1 + |w|), float32."""
    wrench = np.asarray(wrench, dtype=np.float64)
    return (np.sign(wrench) * np.log1p(np.abs(wrench))).astype(np.float32)


def osc_actions(recorded_actions: np.ndarray, tcp_poses: np.ndarray, control_mode: str) -> np.ndarray:
    """(T, 6) float32 OSC_POSE pose deltas of a recorded episode (its control mode's actions and TCP poses)."""
    steps = {"actions": np.asarray(recorded_actions), "obs/tcp_pose": np.asarray(tcp_poses)}
    return libero_actions(steps, control_mode)[:, :ACTION_DIMS].astype(np.float32)


def served_actions(pose_deltas: np.ndarray) -> np.ndarray:
    """(H, 7) float64 as a LIBERO checkpoint answers: the pose deltas clipped to [-1, 1] (what robosuite's
    controller, and the adapter, clip to) and the gripper column open."""
    deltas = np.clip(np.asarray(pose_deltas, dtype=np.float64), -1.0, 1.0)
    return np.concatenate([deltas, np.full((len(deltas), 1), GRIPPER_OPEN)], axis=1)

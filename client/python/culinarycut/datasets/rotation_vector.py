"""The TCP's rotation vector in the models' proprio (LIBERO's eef state; openpi's and OpenVLA-OFT's
`state`), continuous through the knife's normal pose.

The server answers quaternions with w >= 0, and the knife's normal pose, edge down (a pi turn about x,
any yaw), has w = 0: a small tilt either way flips the quaternion's sign, and a rotation vector of angle
<= pi jumps between (+pi, ...) and (-pi, ...). LIBERO's eef state is robosuite's `quat2axisangle`
(robosuite/utils/transform_utils.py) of MuJoCo's body quaternion, whose sign is continuous along the
arm: angle 2 acos(w) in [0, 2 pi], around (+pi, 0, 0) for a gripper pointing down. Here the sign is
taken from the quaternion's hemisphere about edge down, then robosuite's formula applies: near the
normal pose the vector is continuous and matches LIBERO's values; the jump moves to edge up, which the
knife never takes."""
from __future__ import annotations

import numpy as np

EDGE_DOWN_WXYZ = np.array([0.0, 1.0, 0.0, 0.0])  # the knife's normal pose: a pi turn about x


def quat_xyzw_to_axis_angle(quaternion) -> np.ndarray:
    """robosuite's quat2axisangle: (x, y, z) 2 acos(w) / sqrt(1 - w^2), zero for a zero angle; no sign
    flip, so the angle lies in [0, 2 pi]."""
    q = np.asarray(quaternion, dtype=np.float64)
    q = q / np.linalg.norm(q)
    w = float(np.clip(q[3], -1.0, 1.0))
    sin_half = np.sqrt(1.0 - w * w)
    if np.isclose(sin_half, 0.0):
        return np.zeros(3)
    return q[:3] * 2.0 * np.arccos(w) / sin_half


def tcp_rotation_vector(quaternion_wxyz) -> np.ndarray:
    """The rotation vector (rad) of a wxyz TCP quaternion, its sign chosen in the hemisphere of edge down."""
    q = np.asarray(quaternion_wxyz, dtype=np.float64)
    if float(np.dot(q, EDGE_DOWN_WXYZ)) < 0.0:
        q = -q
    return quat_xyzw_to_axis_angle(np.r_[q[1:], q[0]])

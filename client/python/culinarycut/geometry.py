"""Quaternion helpers in the wire convention: (w, x, y, z), unit norm, rotations in radians."""
from __future__ import annotations

import numpy as np


def quat_normalize(q) -> np.ndarray:
    q = np.asarray(q, dtype=np.float64)
    return q / np.linalg.norm(q)


def quat_mul(a, b) -> np.ndarray:
    """Hamilton product a*b: apply b first, then a."""
    aw, ax, ay, az = np.asarray(a, dtype=np.float64)
    bw, bx, by, bz = np.asarray(b, dtype=np.float64)
    return np.array([
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ])


def quat_conj(q) -> np.ndarray:
    w, x, y, z = np.asarray(q, dtype=np.float64)
    return np.array([w, -x, -y, -z])


def quat_from_axis_angle(rotvec) -> np.ndarray:
    """Rotation vector (axis * angle, rad) to a unit quaternion."""
    rotvec = np.asarray(rotvec, dtype=np.float64)
    angle = float(np.linalg.norm(rotvec))
    if angle < 1e-12:
        return np.array([1.0, 0.0, 0.0, 0.0])
    axis = rotvec / angle
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])


def quat_to_axis_angle(q) -> np.ndarray:
    """Unit quaternion to rotation vector (rad), taking the shorter of the two equivalent rotations."""
    q = quat_normalize(q)
    if q[0] < 0:  # q and -q are the same rotation; pick w >= 0 for an angle in [0, pi]
        q = -q
    s = float(np.linalg.norm(q[1:]))
    if s < 1e-12:
        return np.zeros(3)
    angle = 2.0 * np.arctan2(s, q[0])
    return q[1:] / s * angle


def quat_angle(q1, q2) -> float:
    """Angle (rad) of the rotation taking q1 to q2, in [0, pi]."""
    d = abs(float(np.dot(quat_normalize(q1), quat_normalize(q2))))
    return 2.0 * float(np.arccos(min(1.0, d)))


def quat_rotate(q, v) -> np.ndarray:
    """Rotate vector v by quaternion q."""
    qv = np.concatenate([[0.0], np.asarray(v, dtype=np.float64)])
    return quat_mul(quat_mul(q, qv), quat_conj(q))[1:]

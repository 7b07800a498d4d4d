"""Poses relative to a food object: positions in the object's frame in units of its half extents
(so a path recorded on one object fits another of a different position, rotation, scale or type)."""
from __future__ import annotations

import numpy as np

from culinarycut.geometry import quat_conj, quat_mul, quat_normalize


def quat_to_matrix(q) -> np.ndarray:
    w, x, y, z = quat_normalize(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def half_extents_in_object_frame(object_quat, bounds_min_m, bounds_max_m) -> np.ndarray:
    """The object's half extents (m) along its own axes from its world AABB: for a box rotated by R the
    AABB's half extents are |R| h, solved here by least squares (exact away from 45 deg yaws)."""
    world_half = 0.5 * (np.asarray(bounds_max_m, float) - np.asarray(bounds_min_m, float))
    h, *_ = np.linalg.lstsq(np.abs(quat_to_matrix(object_quat)), world_half, rcond=None)
    return np.maximum(h, 1e-3)


def to_object_frame(tcp_pose, object_pose, half_extents_m) -> np.ndarray:
    """World TCP pose [m x3, wxyz] -> [position / half extents (dimensionless) x3, wxyz in object frame]."""
    tcp_pose, object_pose = np.asarray(tcp_pose, float), np.asarray(object_pose, float)
    rotation = quat_to_matrix(object_pose[3:])
    local = rotation.T @ (tcp_pose[:3] - object_pose[:3]) / half_extents_m
    return np.concatenate([local, quat_normalize(quat_mul(quat_conj(object_pose[3:]), tcp_pose[3:]))])


def to_world_frame(relative_pose, object_pose, half_extents_m) -> np.ndarray:
    relative_pose, object_pose = np.asarray(relative_pose, float), np.asarray(object_pose, float)
    rotation = quat_to_matrix(object_pose[3:])
    position = object_pose[:3] + rotation @ (relative_pose[:3] * half_extents_m)
    return np.concatenate([position, quat_normalize(quat_mul(object_pose[3:], relative_pose[3:]))])

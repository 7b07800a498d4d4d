"""Rotations between CulinaryCut's wxyz quaternions and what the models use: rotation matrices and RDT's 6-D
representation (the first two columns of R). The state's rotation vector is in culinarycut.datasets.rotation_vector,
shared with the export."""
from __future__ import annotations

import numpy as np


def quat_wxyz_to_matrix(quaternion) -> np.ndarray:
    w, x, y, z = np.asarray(quaternion, dtype=np.float64) / np.linalg.norm(quaternion)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def matrix_to_quat_wxyz(matrix) -> np.ndarray:
    """Shepperd's method; w >= 0."""
    m = np.asarray(matrix, dtype=np.float64)
    trace = np.trace(m)
    if trace > 0:
        s = 2.0 * np.sqrt(trace + 1.0)
        q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
        q = [0.0, 0.0, 0.0, 0.0]
        q[0] = (m[k, j] - m[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (m[j, i] + m[i, j]) / s
        q[1 + k] = (m[k, i] + m[i, k]) / s
    q = np.asarray(q)
    q /= np.linalg.norm(q)
    return -q if q[0] < 0 else q


# RDT's rotation_matrix_to_ortho6d (data/utils.py): [R[:, 0], R[:, 1]].
def matrix_to_ortho6d(matrix) -> np.ndarray:
    m = np.asarray(matrix, dtype=np.float64)
    return np.concatenate([m[:, 0], m[:, 1]])


# RDT's ortho6d_to_rotation_matrix (data/utils.py): Gram-Schmidt, x = a1, z = x cross a2, y = z cross x.
def ortho6d_to_matrix(ortho6d) -> np.ndarray:
    v = np.asarray(ortho6d, dtype=np.float64)
    x = v[:3] / max(np.linalg.norm(v[:3]), 1e-8)
    z = np.cross(x, v[3:6])
    z = z / max(np.linalg.norm(z), 1e-8)
    y = np.cross(z, x)
    return np.stack([x, y, z], axis=-1)


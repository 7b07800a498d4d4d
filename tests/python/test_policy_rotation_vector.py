"""The rotation vector in the models' state (openpi's `observation/state`, OpenVLA-OFT's `state`, the
export's proprio) is robosuite's quat2axisangle and stays continuous while the knife sweeps through its
edge-down pose, where the server's quaternion (w >= 0) flips sign."""
from __future__ import annotations

import numpy as np

from culinarycut import CulinaryCutEnv
from culinarycut.datasets.adapter_layouts import delta_ee_proprio
from culinarycut.datasets.rotation_vector import quat_xyzw_to_axis_angle, tcp_rotation_vector
from culinarycut_policies.actions import tcp_position_axis_angle


def as_server_answers(q_wxyz):
    """The server's convention: w >= 0."""
    q = np.asarray(q_wxyz, dtype=np.float64)
    return -q if q[0] < 0 else q


def edge_down_tilted(tilt, yaw=0.2):
    """Rx(pi + tilt) Rz(yaw) as a wxyz quaternion: edge down, yawed, tilted about x by `tilt`."""
    c, s = np.cos((np.pi + tilt) / 2), np.sin((np.pi + tilt) / 2)
    cy, sy = np.cos(yaw / 2), np.sin(yaw / 2)
    return np.array([c * cy, s * cy, -s * sy, c * sy])


def test_quat2axisangle_golden_values():
    # robosuite/utils/transform_utils.py quat2axisangle (xyzw): angle 2 acos(w) in [0, 2 pi], no sign flip.
    np.testing.assert_allclose(quat_xyzw_to_axis_angle([1, 0, 0, 1e-4]), [3.14139265359, 0, 0], atol=1e-10)
    np.testing.assert_allclose(quat_xyzw_to_axis_angle([1, 0, 0, -1e-4]), [3.141792653589, 0, 0], atol=1e-10)
    np.testing.assert_allclose(quat_xyzw_to_axis_angle([0.6, 0, 0, -0.8]), [4.996183089593, 0, 0], atol=1e-10)
    np.testing.assert_allclose(quat_xyzw_to_axis_angle([0.5, 0.5, 0.5, -0.5]), [2.418399152312] * 3, atol=1e-10)
    np.testing.assert_allclose(quat_xyzw_to_axis_angle([0, 0, np.sqrt(0.5), np.sqrt(0.5)]), [0, 0, np.pi / 2])
    np.testing.assert_array_equal(quat_xyzw_to_axis_angle([0, 0, 0, 1]), np.zeros(3))


def test_the_two_quaternion_signs_near_edge_down_give_one_rotation_vector():
    # (1e-4, 1, 0, 0) and (-1e-4, 1, 0, 0) as the server answers it: both near (+pi, 0, 0), 2e-4 apart.
    plus = tcp_rotation_vector([1e-4, 1, 0, 0])
    minus = tcp_rotation_vector(as_server_answers([-1e-4, 1, 0, 0]))
    np.testing.assert_allclose(plus, [3.14139265359, 0, 0], atol=1e-10)
    np.testing.assert_allclose(minus, [3.141792653589, 0, 0], atol=1e-10)


def test_sweep_through_edge_down_is_continuous_for_adapter_and_export():
    tilts = np.linspace(-0.2, 0.2, 81)
    quats = np.array([as_server_answers(edge_down_tilted(t)) for t in tilts])
    assert (quats[:, 1] > 0).any() and (quats[:, 1] < 0).any()  # the server's sign flips within the sweep
    poses = np.concatenate([np.tile([0.5, 0.0, 0.2], (len(quats), 1)), quats], axis=1)
    adapter = np.array([tcp_position_axis_angle({"extra": {"tcp_pose": p}})[3:] for p in poses])
    export = delta_ee_proprio({"obs/tcp_pose": poses})[:, 3:6]
    np.testing.assert_allclose(adapter, export, atol=1e-12)
    assert np.abs(np.diff(adapter, axis=0)).max() < 0.01  # each step turns 0.005 rad
    angles = np.linalg.norm(adapter, axis=1)  # rises through pi, where the knife is exactly edge down
    assert (np.diff(angles) > 0).all() and abs(angles[40] - np.pi) < 1e-12


def test_knife_swept_through_its_normal_pose_on_the_server_gives_a_continuous_state(address):
    with CulinaryCutEnv(address, control_mode="pd_ee_pose") as env:
        env.reset(seed=0)
        states, signs = [], []
        for roll in np.linspace(np.pi - 0.15, np.pi + 0.15, 13):  # XYZ Euler roll through edge down
            for _ in range(12):
                obs, *_ = env.step(np.array([0.5, 0.0, 0.25, roll, 0.0, 0.2], dtype=np.float32))
            states.append(tcp_position_axis_angle(obs)[3:])
            signs.append(np.sign(obs["extra"]["tcp_pose"][4]))
    states = np.asarray(states)
    assert 1.0 in signs and -1.0 in signs, signs  # the server's quaternion flipped sign on the way
    assert np.abs(np.diff(states, axis=0)).max() < 0.1, states
    angles = np.linalg.norm(states, axis=1)
    assert angles[0] < np.pi - 0.05 and angles[-1] > np.pi + 0.05, angles

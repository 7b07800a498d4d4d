"""A ManiSkill-trained policy's actions mean the same here: normalised deltas in [-1, 1] scaled by
0.1 m / 0.1 rad in the robot's root frame, and pd_ee_pose as position + XYZ Euler angles."""
from __future__ import annotations

import numpy as np

from culinarycut import CulinaryCutEnv


def test_a_normalised_delta_of_one_targets_a_tenth_of_a_metre_in_the_root_frame(client, session):
    start = np.array(client.observe(session).observation.tcp_pose)
    for mode, values, expected in [("pd_ee_delta_pos", [0.0, 1.0, -0.5], [0.0, 0.1, -0.05]),
                                   ("pd_ee_delta_pose", [0.5, 0.0, 0.0, 0.0, 0.0, 0.0], [0.05, 0.0, 0.0])]:
        before = np.array(client.observe(session).observation.tcp_pose)
        response = client.step(session, mode, values)
        assert not response.info.action_clipped and response.info.ik_converged
        # Hold the joint targets that one action set: the TCP settles where that action aimed.
        target = list(response.observation.agent.qpos_target)
        for _ in range(40):
            response = client.step(session, "pd_joint_pos", target)
        moved = np.array(response.observation.tcp_pose[:3]) - before[:3]
        np.testing.assert_allclose(moved, expected, atol=1e-3)
    assert np.linalg.norm(np.array(client.observe(session).observation.tcp_pose[:3]) - start[:3]) > 0.1


def test_pd_ee_pose_takes_xyz_euler_angles_in_the_root_frame(address):
    with CulinaryCutEnv(address, control_mode="pd_ee_pose") as env:
        env.reset(seed=0)
        # Knife edge down (a pi turn about x), yawed 20 degrees about z: Rx(pi) Ry(0) Rz(-20 deg).
        action = np.array([0.5, 0.05, 0.2, np.pi, 0.0, np.deg2rad(-20.0)], dtype=np.float32)
        for _ in range(60):
            obs, *_ = env.step(action)
        tcp = obs["extra"]["tcp_pose"].astype(np.float64)
        np.testing.assert_allclose(tcp[:3], action[:3], atol=1e-3)
        w, x, y, z = tcp[3:]
        # Rx(pi) Rz(c) as a quaternion is (0, cos(c/2), -sin(c/2), 0) up to sign.
        c = np.deg2rad(-20.0)
        expected = np.array([0.0, np.cos(c / 2), -np.sin(c / 2), 0.0])
        assert min(np.linalg.norm(tcp[3:] - expected), np.linalg.norm(tcp[3:] + expected)) < 0.02, tcp[3:]

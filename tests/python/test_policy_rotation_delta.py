"""A LIBERO-trained model's rotation deltas are axis-angles (robosuite's OSC_POSE: set_goal_orientation in
robosuite/controllers/control_utils.py turns the delta into a rotation with axisangle2quat and applies it
in the world frame); the server's pd_ee_delta_pose reads XYZ Euler angles, so the adapter converts."""
from __future__ import annotations

import numpy as np
import pytest

from culinarycut.datasets.export_libero import euler_xyz_to_axis_angle

from culinarycut_policies.actions import delta_to_ee_delta_pose
from culinarycut_policies.openpi import OpenPIPolicy
from culinarycut_policies.standins.websocket_server import WebsocketPolicyServer

pytestmark = pytest.mark.filterwarnings("ignore:connect\\(\\) must be used as a context manager:DeprecationWarning")

# The axis-angle (0.3, 0.4, 0) rad as XYZ Euler angles (R = Rx Ry Rz), computed independently with
# scipy.spatial.transform.Rotation.from_rotvec([0.3, 0.4, 0]).as_euler("XYZ").
EULER_OF_ROTVEC = [0.3167456, 0.39362687, -0.06366925]


def test_axis_angle_delta_becomes_the_same_rotation_in_xyz_euler():
    _, values = delta_to_ee_delta_pose([0.0, 0.0, 0.0, 0.3, 0.4, 0.0], "metres_radians", "axis_angle")
    np.testing.assert_allclose(values[3:], np.array(EULER_OF_ROTVEC) / 0.1, atol=1e-6)
    _, values = delta_to_ee_delta_pose([0.0, 0.0, 0.0, 0.3, 0.4, 0.0], "metres_radians", "euler_xyz")
    np.testing.assert_allclose(values[3:], [3.0, 4.0, 0.0])
    _, single = delta_to_ee_delta_pose([0.0, 0.0, 0.0, 0.0, 0.0, 0.05], "metres_radians", "axis_angle")
    np.testing.assert_allclose(single[3:], [0.0, 0.0, 0.5], atol=1e-12)  # one axis: both conventions agree
    # and back, as the LIBERO export writes its OSC actions
    np.testing.assert_allclose(euler_xyz_to_axis_angle(EULER_OF_ROTVEC), [0.3, 0.4, 0.0], atol=1e-6)


@pytest.mark.parametrize("option, expected", [(None, np.array(EULER_OF_ROTVEC) / 0.1), ("euler_xyz", [3.0, 4.0, 0.0])])
def test_openpi_libero_actions_are_axis_angle_by_default(option, expected):
    # openpi's LIBERO checkpoints answer robosuite OSC units: rotation 1 = 0.5 rad, so (0.6, 0.8, 0) is (0.3, 0.4, 0) rad
    chunk = np.tile([0.0, 0.0, 0.0, 0.6, 0.8, 0.0, -1.0], (10, 1)).astype(np.float32)
    server = WebsocketPolicyServer(lambda request: {"actions": chunk}, {"model_family": "openpi"}).start()
    rng = np.random.Generator(np.random.PCG64(0))
    observation = {"sensor_data": {c: {"rgb": rng.integers(0, 256, (32, 32, 3), dtype=np.uint8)} for c in ("front", "wrist")},
                   "extra": {"tcp_pose": np.array([0.5, 0.0, 0.2, 0.0, 1.0, 0.0, 0.0])}}
    try:
        policy = OpenPIPolicy(url=server.url, rotation_delta=option)
        policy.reset("cut", {})
        mode, values = policy.act(observation)
        policy.close()
    finally:
        server.stop()
    assert mode == "pd_ee_delta_pose"
    np.testing.assert_allclose(values[3:], expected, atol=1e-6)
    with pytest.raises(ValueError, match="option rotation_delta='quaternion'"):
        OpenPIPolicy(url=server.url, rotation_delta="quaternion")

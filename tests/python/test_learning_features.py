"""The learned policy (learning/) sees and answers what the openpi adapter sends and executes: the
training features of a recorded step equal the serving features of the adapter's request for the same
observation, the training targets executed by the adapter's defaults reach the recorded target pose, and
the tokenizer reads numbers as values ("0.3", "30%", "three tenths" alike). No server, no torch training."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

# learning/ importable where scripts/install_deps.sh has not installed it (it installs it editable, from here)
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "learning"))

from culinarycut.datasets.object_frame import quat_to_matrix
from culinarycut.geometry import quat_from_axis_angle, quat_mul
from culinarycut_learning.features import (model_image, osc_actions, served_actions, state_from_request,
                                           state_from_tcp_poses)
from culinarycut_learning.language import COUNT, RATIO, Tokenizer, load_templates
from culinarycut_policies.actions import delta_to_ee_delta_pose
from culinarycut_policies.openpi import OpenPIPolicy

EDGE_DOWN = np.array([0.0, 1.0, 0.0, 0.0])


def tilted(rotvec) -> np.ndarray:
    return quat_mul(quat_from_axis_angle(np.asarray(rotvec, dtype=float)), EDGE_DOWN)


def euler_xyz_matrix(angles) -> np.ndarray:
    a, b, c = angles
    rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rz = np.array([[np.cos(c), -np.sin(c), 0], [np.sin(c), np.cos(c), 0], [0, 0, 1]])
    return rx @ ry @ rz


@pytest.mark.parametrize("rotvec", [(0.0, 0.0, 0.0), (0.03, -0.02, 0.01), (-0.05, 0.04, 0.3)])
def test_serving_features_equal_training_features(rotvec):
    """The adapter's LIBERO request for an observation gives the model what training gave it for the
    recorded step: the same state (through edge down, where the quaternion's sign flips) and images."""
    rng = np.random.Generator(np.random.PCG64(5))
    pose = np.r_[0.48, -0.03, 0.12, tilted(rotvec)]
    frames = {c: rng.integers(0, 256, (64, 64, 3), dtype=np.uint8) for c in ("front", "wrist")}
    observation = {"sensor_data": {c: {"rgb": f} for c, f in frames.items()},
                   "extra": {"tcp_pose": pose, "wrist_wrench": np.zeros(6)}, "agent": {"qpos": np.zeros(7)}}
    policy = OpenPIPolicy(url="ws://127.0.0.1:1", camera_size=64)
    request = policy.request(observation)
    np.testing.assert_allclose(state_from_request(request["observation/state"]), state_from_tcp_poses(pose[None])[0],
                               atol=1e-6)
    for key, camera in (("observation/image", "front"), ("observation/wrist_image", "wrist")):
        np.testing.assert_array_equal(model_image(request[key], 96), model_image(frames[camera], 96))


@pytest.mark.parametrize("delta_m, turn", [((0.004, -0.002, -0.01), (0.0, 0.0, 0.0)),
                                           ((-0.01, 0.02, 0.015), (0.02, -0.03, 0.05)),
                                           ((0.0, 0.0, -0.001), (0.0, 0.0, -0.08))])
def test_training_targets_executed_by_the_adapter_reach_the_recorded_target(delta_m, turn):
    """A recorded pd_ee_pose_quat target, as the OSC action the model learns, executed the way the adapter's
    defaults execute it (robosuite_osc units, axis-angle rotation, pd_ee_delta_pose from the measured TCP),
    lands on that target."""
    tcp = np.r_[0.5, 0.01, 0.1, tilted((0.02, 0.01, -0.1))]
    target = np.r_[tcp[:3] + delta_m, quat_mul(quat_from_axis_angle(np.asarray(turn)), tcp[3:])]
    action = osc_actions(target[None], tcp[None], "pd_ee_pose_quat")[0]
    chunk = served_actions(action[None])
    assert chunk.shape == (1, 7) and chunk[0, 6] == -1.0
    mode, values = delta_to_ee_delta_pose(chunk[0], "robosuite_osc", "axis_angle")
    assert mode == "pd_ee_delta_pose"
    np.testing.assert_allclose(tcp[:3] + 0.1 * values[:3], target[:3], atol=1e-6)
    reached = euler_xyz_matrix(0.1 * values[3:]) @ quat_to_matrix(tcp[3:])
    np.testing.assert_allclose(reached, quat_to_matrix(target[3:]), atol=1e-6)


def test_numbers_are_values_whatever_their_wording():
    tokenizer = Tokenizer.build(["cut the banana at 0.3 ratio from the left", "saw the banana into 4 pieces"],
                                load_templates(), 32)
    ratio = [("cut the banana at 0.3 ratio from the left", 0.3), ("cut three tenths of the way", 0.3),
             ("cut the banana at 30% from the left", 0.3), ("at thirty five percent, slice it", 0.35),
             ("at the 1/3 mark", 1 / 3), ("at two-thirds", 2 / 3), ("slice it halfway", 0.5)]
    for text, value in ratio:
        numbers = [(w, v) for w, v in tokenizer.pieces(text) if w in (RATIO, COUNT)]
        assert numbers == [(RATIO, pytest.approx(value))], (text, numbers)
    for text, count in [("saw the banana into 4 pieces", 4), ("split it into thirds", 3), ("into five parts", 5)]:
        numbers = [(w, v) for w, v in tokenizer.pieces(text) if w in (RATIO, COUNT)]
        assert numbers == [(COUNT, count)], (text, numbers)
    ids, values = tokenizer.encode("Cut the banana at 0.3 ratio from the left")
    same_ids, same_values = tokenizer.encode("cut the banana at three tenths ratio from the left")
    np.testing.assert_array_equal(ids, same_ids)
    np.testing.assert_allclose(values, same_values)
    # Wording never seen in training reads as <unk>, even where the generator has it (held out: "chop").
    assert "chop" in tokenizer.vocabulary and "chop" not in tokenizer.trained
    assert tokenizer.encode("chop the banana")[0][0] == tokenizer.index["<unk>"]

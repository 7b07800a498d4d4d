"""The statistics contract end to end: one planner episode generated through a real server, exported with
`culinarycut data export`, and its dataset_statistics.json loaded by every adapter's own loader; each
adapter takes its own key and refuses the others, naming the layout. The per-adapter layouts are
checked against the adapters' own state functions and against the recorded targets."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from culinarycut.datasets.adapter_layouts import delta_ee_actions, delta_ee_proprio, rdt_states
from culinarycut.datasets.episode_file import read_episode
from culinarycut.datasets.generate import generate
from culinarycut.datasets.jobs import DatasetConfig
from culinarycut.datasets.store import GenerationStore
from culinarycut_policies.actions import tcp_position_axis_angle
from culinarycut_policies.octo import OctoPolicy
from culinarycut_policies.openvla import OpenVLAPolicy
from culinarycut_policies.openvla_oft import OpenVLAOFTPolicy
from culinarycut_policies.rdt import RDTPolicy, robot_state
from culinarycut_policies.rotation import quat_wxyz_to_matrix
from culinarycut_policies.statistics import StatisticsError

SPEC = {"style": "normal", "state": "middle", "target_object": "cucumber"}
DELTA_ADAPTERS = (OpenVLAPolicy, OpenVLAOFTPolicy, OctoPolicy)


@pytest.fixture(scope="module")
def exported(address, tmp_path_factory):
    root = tmp_path_factory.mktemp("statistics")
    config = DatasetConfig(name="s", seed=5, tasks=(SPEC,), episodes_per_task=1, cameras=("front",), image_size=16)
    summary = generate(config, root / "data", [address], progress=False)
    assert summary.kept == 1
    # the CLI, as a user runs it
    subprocess.run([sys.executable, "-m", "culinarycut", "data", "export", str(root / "data"), "--out",
                    str(root / "export")], check=True)
    with GenerationStore(root / "data") as store:
        meta, steps = read_episode(root / "data" / store.rows(kept_only=True)[0]["file"])
    return {"statistics": root / "export" / "dataset_statistics.json", "meta": meta, "steps": steps}


def test_every_adapter_loads_its_key_of_the_export(exported):
    path = exported["statistics"]
    document = json.loads(path.read_text())
    assert sorted(document) == ["culinarycut", "culinarycut_delta_ee", "culinarycut_rdt"]
    for adapter in DELTA_ADAPTERS:  # no unnorm_key: the one key in the adapter's layout is chosen
        policy = adapter(statistics=str(path))
        assert policy.stats.key == "culinarycut_delta_ee" and policy.action_units == "metres_radians", adapter
        assert policy.stats.action.dim == 7 and policy.stats.proprio.dim == 8
        assert not policy.stats.action.mask[6] and not policy.stats.proprio.mask[6:].any()  # gripper slots
    oft = OpenVLAOFTPolicy(statistics=str(path))
    observation = {"extra": {"tcp_pose": exported["steps"]["obs/tcp_pose"][0]},
                   "sensor_data": {c: {"rgb": np.zeros((16, 16, 3), np.uint8)} for c in ("front", "wrist")}}
    assert oft.request(observation)["state"].shape == (8,)  # LIBERO's eef state, not padded past the file
    rdt = RDTPolicy(statistics=str(path), normalization="bounds").normalization.stats  # RDT's ManiSkill scaling
    assert rdt.key == "culinarycut_rdt" and rdt.action.dim == rdt.proprio.dim == 16
    entry = document["culinarycut_delta_ee"]
    # a cut holds the knife near edge down: its rotation vector stays near (+pi, ...), not split at -pi and pi
    q01, q99 = np.array(entry["proprio"]["q01"][3:6]), np.array(entry["proprio"]["q99"][3:6])
    assert q01[0] > 2.5 and q99[0] < 3.8 and (q99 - q01 < 0.6).all(), (q01, q99)
    assert entry["num_transitions"] == len(exported["steps"]["actions"]) and entry["num_trajectories"] == 1


@pytest.mark.parametrize("adapter", DELTA_ADAPTERS + (RDTPolicy,))
def test_adapters_refuse_the_keys_of_other_layouts(exported, adapter):
    path = str(exported["statistics"])
    options = {"normalization": "bounds"} if adapter is RDTPolicy else {}  # RDT reads statistics only then
    with pytest.raises(StatisticsError, match="'culinarycut'.* has action_layout 'pd_ee_pose_quat', but this adapter"):
        adapter(statistics=path, unnorm_key="culinarycut", **options)
    other = "culinarycut_delta_ee" if adapter is RDTPolicy else "culinarycut_rdt"
    with pytest.raises(StatisticsError, match=f"'{other}'.* has action_layout"):
        adapter(statistics=path, unnorm_key=other, **options)


def test_layouts_match_what_the_adapters_compute(exported):
    steps = exported["steps"]
    for t in (0, len(steps["actions"]) // 2):
        observation = {"extra": {"tcp_pose": steps["obs/tcp_pose"][t]}, "agent": {"qpos": steps["obs/qpos"][t]}}
        np.testing.assert_allclose(delta_ee_proprio(steps)[t, :6], tcp_position_axis_angle(observation), atol=1e-6)
        np.testing.assert_allclose(rdt_states(steps)[t], robot_state(observation), atol=1e-6)


def euler_xyz_matrix(angles) -> np.ndarray:
    """R = Rx(a) Ry(b) Rz(c) (docs/robot.md's pd_ee_pose convention), built from the three rotations."""
    a, b, c = angles
    rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rz = np.array([[np.cos(c), -np.sin(c), 0], [np.sin(c), np.cos(c), 0], [0, 0, 1]])
    return rx @ ry @ rz


def test_delta_actions_applied_to_the_tcp_give_the_recorded_targets(exported):
    steps, mode = exported["steps"], exported["meta"]["control_mode"]
    assert mode == "pd_ee_pose_quat"
    deltas = delta_ee_actions(steps, mode)
    assert np.abs(deltas[:, :3]).max() > 1e-4  # the knife moved: the check below is not about zeros
    for delta, pose, target in zip(deltas, steps["obs/tcp_pose"], steps["actions"]):
        np.testing.assert_allclose(pose[:3] + delta[:3], target[:3], atol=1e-6)
        # pd_ee_delta_pose applies the rotation in the root frame: R_target = dR R_tcp
        np.testing.assert_allclose(euler_xyz_matrix(delta[3:6]) @ quat_wxyz_to_matrix(pose[3:7]),
                                   quat_wxyz_to_matrix(target[3:7]), atol=1e-6)
    assert (deltas[:, 6] == 1.0).all()


def test_normalised_delta_pose_data_is_converted_to_metres_radians():
    # pd_ee_delta_pose values: 1 = 0.1 m / 0.1 rad, clipped to [-1, 1] (the rotation by its norm)
    steps = {"actions": np.array([[0.5, -2.0, 0.0, 0.0, 0.6, 0.8], [0.1, 0.0, 0.0, 0.0, 0.0, 3.0]]),
             "obs/tcp_pose": np.zeros((2, 7))}
    np.testing.assert_allclose(delta_ee_actions(steps, "pd_ee_delta_pose"),
                               [[0.05, -0.1, 0.0, 0.0, 0.06, 0.08, 1.0], [0.01, 0.0, 0.0, 0.0, 0.0, 0.1, 1.0]])
    with pytest.raises(ValueError, match="control mode 'pd_joint_pos' has no end-effector target"):
        delta_ee_actions(steps, "pd_joint_pos")


"""CulinaryCutEnv and Client against the real server: spaces, control modes, snapshots, concurrency."""
from __future__ import annotations

import threading

import numpy as np
import pytest

from culinarycut import Box, Client, CulinaryCutEnv, errors
from culinarycut.geometry import quat_angle, quat_conj, quat_from_axis_angle, quat_mul, quat_rotate, quat_to_axis_angle

PHYSICS_HZ = 500.0  # server default physics rate
# Franka Panda joint limits (rad), from the Franka datasheet.
PANDA_LOW = np.array([-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973])
PANDA_HIGH = np.array([2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973])
OBS_SHAPES = {"agent": {"qpos": (7,), "qvel": (7,), "qpos_target": (7,)},
              "extra": {"tcp_pose": (7,), "tcp_velocity": (6,), "flange_pose": (7,), "wrist_wrench": (6,)}}


def assert_obs_matches_space(space, obs):
    assert set(obs) == set(space) == set(OBS_SHAPES), (set(obs), set(space))
    for group, leaves in OBS_SHAPES.items():
        assert set(obs[group]) == set(space[group]) == set(leaves), group
        for name, shape in leaves.items():
            value, box = obs[group][name], space[group][name]
            assert isinstance(box, Box)
            assert box.shape == shape and value.shape == shape, (group, name, box.shape, value.shape)
            assert value.dtype == box.dtype == np.float32, (group, name, value.dtype, box.dtype)  # ManiSkill's
            assert np.all(np.isfinite(value)), (group, name, value)
    assert space.contains(obs)


def pose_error(tcp_pose, target) -> tuple[float, float]:
    """(position error m, orientation error rad) between two [x, y, z, qw, qx, qy, qz] poses."""
    return float(np.linalg.norm(tcp_pose[:3] - target[:3])), quat_angle(tcp_pose[3:], target[3:])


def fingerprint(response) -> bytes:
    """Everything a StepResponse says about the simulation, bit for bit (wall times excluded)."""
    copy = type(response)()
    copy.CopyFrom(response)
    for field in copy.info.DESCRIPTOR.fields:
        if field.name.endswith("_wall_time_ms"):
            setattr(copy.info, field.name, 0.0)
    return copy.SerializeToString(deterministic=True)


# ManiSkill's normalised modes are bounded by [-1, 1]; the absolute ones by the joint limits or workspace.
@pytest.mark.parametrize("mode, dim, bound", [("pd_joint_pos", 7, None), ("pd_joint_delta_pos", 7, 1.0),
                                              ("pd_ee_delta_pos", 3, 1.0), ("pd_ee_delta_pose", 6, 1.0),
                                              ("pd_ee_pose", 6, None), ("pd_ee_pose_quat", 7, None)])
def test_action_space_from_handshake(address, mode, dim, bound):
    with CulinaryCutEnv(address, control_mode=mode) as env:
        space = env.action_space
        assert isinstance(space, Box) and space.shape == (dim,) and space.dtype == np.float32  # ManiSkill's action dtype
        if bound is not None:
            np.testing.assert_array_equal(space.low, -bound)
            np.testing.assert_array_equal(space.high, bound)
        if mode == "pd_joint_pos":
            np.testing.assert_allclose(space.low, PANDA_LOW, atol=0.01)
            np.testing.assert_allclose(space.high, PANDA_HIGH, atol=0.01)
        assert space.contains(space.sample())


def test_env_rejects_unknown_control_mode_before_stepping(address):
    with pytest.raises(ValueError, match="pd_teleport"):
        CulinaryCutEnv(address, control_mode="pd_teleport")


def test_reset_and_step_match_spaces(address):
    with CulinaryCutEnv(address, control_mode="pd_joint_delta_pos") as env:
        assert env.spec is None and env.render_mode is None and isinstance(env.metadata, dict)
        obs, info = env.reset(seed=0)
        assert_obs_matches_space(env.observation_space, obs)
        assert info["frame_id"] == 0 and info["sim_time"] == 0.0 and info["seed"] == 0
        assert env.control_timestep == pytest.approx(0.05)  # 20 Hz default
        assert isinstance(env.np_random, np.random.Generator)
        env.action_space.seed(0)
        for k in range(1, 4):
            obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
            assert_obs_matches_space(env.observation_space, obs)
            assert type(reward) is float and type(terminated) is bool and type(truncated) is bool
            assert not terminated and not truncated  # no task and no step limit in the default scene
            assert info["frame_id"] == k
            assert info["sim_time"] == pytest.approx(k * env.control_timestep)
            assert info["substeps"] == round(env.control_timestep * PHYSICS_HZ)
            assert info["action_clipped"] is False
            assert set(info) >= {"ik_converged", "ik_position_error", "ik_orientation_error"}
            assert "step_wall_time_ms" in env.last_step_timings  # wall times stay out of info


def test_reset_pose_is_knife_down_above_table(address):
    with CulinaryCutEnv(address, control_mode="pd_ee_pose") as env:
        obs, _ = env.reset(seed=0)
        tcp = obs["extra"]["tcp_pose"]
        assert np.linalg.norm(tcp[3:]) == pytest.approx(1.0, abs=1e-9)
        tool_z = quat_rotate(tcp[3:], [0, 0, 1])  # the knife's TCP z axis in world
        assert tool_z[2] < -0.95, f"TCP z axis {tool_z} does not point down after reset"
        assert tcp[2] > 0.05, f"TCP {tcp[:3]} m is not above the table"


def test_initial_qpos_option(address):
    with CulinaryCutEnv(address, control_mode="pd_joint_delta_pos") as env:
        obs0, _ = env.reset(seed=0)
        q = obs0["agent"]["qpos"] + np.array([0.1, -0.1, 0.1, 0.1, -0.1, 0.1, 0.2])
        obs, _ = env.reset(seed=0, options={"initial_qpos": q})
        np.testing.assert_allclose(obs["agent"]["qpos"], q, atol=1e-9)
        with pytest.raises(ValueError, match="bogus"):
            env.reset(options={"bogus": 1})


def test_reset_seed_defaults_to_the_scene_seed(client):
    sid = client.create_session({"seed": 42}).session_id
    try:
        assert client.reset(sid).seed == 42
        assert client.reset(sid, seed=0).seed == 0  # an explicit 0 is a seed, not "unset"
        assert client.reset(sid, seed=123).seed == 123
    finally:
        client.close_session(sid)


def test_env_reset_seeding_follows_gymnasium(address):
    with CulinaryCutEnv(address, scene={"seed": 42}, control_mode="pd_joint_delta_pos") as env:
        _, info = env.reset()
        assert info["seed"] == 42  # first unseeded episode: the scene's seed
        _, info = env.reset(seed=5)
        assert info["seed"] == 5
        first = [env.reset()[1]["seed"] for _ in range(3)]  # later ones: drawn from np_random
        env.reset(seed=5)
        assert [env.reset()[1]["seed"] for _ in range(3)] == first
        assert len(set(first)) == 3


@pytest.mark.parametrize("target_kind", ["canonical", "offset_and_rotated"])
def test_ee_pose_reaches_target_within_1mm_1deg(address, target_kind):
    with CulinaryCutEnv(address, control_mode="pd_ee_pose_quat") as env:
        obs, _ = env.reset(seed=0)
        tcp0 = obs["extra"]["tcp_pose"]
        if target_kind == "canonical":
            target = np.array([0.5, 0.0, 0.2, 0.0, 1.0, 0.0, 0.0])  # knife down above the board
        else:
            q = quat_mul(quat_from_axis_angle([0.0, 0.0, np.deg2rad(15)]), tcp0[3:])
            target = np.concatenate([tcp0[:3] + [0.04, -0.03, -0.05], q])
        errs = pose_error(tcp0, target)
        for k in range(1, 61):  # 60 steps = 3 s at 20 Hz
            obs, _, _, _, info = env.step(target)
            errs = pose_error(obs["extra"]["tcp_pose"], target)
            if errs[0] < 1e-3 and errs[1] < np.deg2rad(1.0):
                break
        else:
            pytest.fail(f"after 60 steps TCP error {errs[0] * 1e3:.2f} mm, {np.rad2deg(errs[1]):.2f} deg "
                        f"(target {target}, last info {info})")
        for _ in range(5):  # and it holds the target
            obs, *_ = env.step(target)
            errs = pose_error(obs["extra"]["tcp_pose"], target)
            assert errs[0] < 1e-3 and errs[1] < np.deg2rad(1.0), errs


def test_out_of_bounds_action_is_clipped_not_rejected(client, session):
    response = client.step(session, "pd_joint_delta_pos", [5, 0, 0, 0, 0, 0, 0])  # normalised: [-1, 1]
    assert response.info.action_clipped
    response = client.step(session, "pd_joint_delta_pos", [0.5, 0, 0, 0, 0, 0, 0])
    assert not response.info.action_clipped


def run_actions(client, session_id, actions) -> list[bytes]:
    return [fingerprint(client.step(session_id, mode, values)) for mode, values in actions]


def mixed_actions(seed: int, n: int = 20):
    """A reproducible mix of joint-space and Cartesian actions (stays well inside the workspace)."""
    rng = np.random.default_rng(seed)
    actions = []
    for i in range(n):
        if i % 2:
            actions.append(("pd_ee_delta_pose", rng.uniform(-0.1, 0.1, 6)))  # normalised: 1 cm, 0.01 rad
        else:
            actions.append(("pd_joint_delta_pos", rng.uniform(-0.5, 0.5, 7)))  # normalised: 0.05 rad
    return actions


def test_snapshot_restore_reproduces_next_20_steps_bit_exactly(client, session):
    run_actions(client, session, mixed_actions(seed=1, n=5))  # leave the rest pose: nonzero velocities
    before = client.observe(session)
    snapshot = client.save_snapshot(session)
    assert isinstance(snapshot, bytes) and snapshot
    actions = mixed_actions(seed=2, n=20)
    first = run_actions(client, session, actions)

    restored = client.restore_snapshot(session, snapshot)
    assert restored.stamp == before.stamp
    assert restored.observation.SerializeToString(deterministic=True) == \
        before.observation.SerializeToString(deterministic=True)
    assert run_actions(client, session, actions) == first

    # A snapshot restores into another session of the same scene too.
    other = client.create_session(None).session_id
    try:
        client.reset(other, seed=7)
        client.restore_snapshot(other, snapshot)
        assert run_actions(client, other, actions) == first
    finally:
        client.close_session(other)


def test_concurrent_sessions_are_independent_and_deterministic(address):
    rng = np.random.default_rng(5)
    x = [("pd_joint_delta_pos", a) for a in rng.uniform(-0.5, 0.5, (30, 7))]  # normalised
    y = [("pd_ee_delta_pose", a) for a in rng.uniform(-0.1, 0.1, (30, 6))]
    neg_x = [(m, -a) for m, a in x]
    plans = [x, x, y, neg_x]  # sessions 0 and 1 must agree; 2 and 3 must differ from them
    results: list[list[bytes] | None] = [None] * len(plans)
    failures: list[BaseException] = []
    barrier = threading.Barrier(len(plans), timeout=60)  # interleave the steps of all sessions

    def worker(i: int):
        try:
            with Client(address) as c:
                sid = c.create_session(None).session_id
                c.reset(sid, seed=0)
                out = []
                for mode, values in plans[i]:
                    barrier.wait()
                    out.append(fingerprint(c.step(sid, mode, values)))
                results[i] = out
                c.close_session(sid)
        except BaseException as err:  # reported below: an assert in a thread would be lost
            failures.append(err)
            barrier.abort()

    threads = [threading.Thread(target=worker, args=(i,)) for i in range(len(plans))]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=120)
    assert not failures, failures
    assert results[0] == results[1], "same seed and actions gave different observations"
    assert results[2] != results[0] and results[3] != results[0]

    with Client(address) as c:  # the concurrent run equals a run with no neighbours
        sid = c.create_session(None).session_id
        c.reset(sid, seed=0)
        assert run_actions(c, sid, x) == results[0]
        c.close_session(sid)


@pytest.mark.parametrize("joint", range(7))
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_joint_delta_moves_the_commanded_joint(client, session, joint, sign):
    q0 = np.array(client.observe(session).observation.agent.qpos)
    action = np.zeros(7)
    action[joint] = sign * 0.5  # normalised: 0.05 rad per step
    for _ in range(5):
        response = client.step(session, "pd_joint_delta_pos", action)
    dq = np.array(response.observation.agent.qpos) - q0
    assert sign * dq[joint] > 0.05, f"joint {joint} moved {dq[joint]:+.4f} rad for 5 x {sign * 0.05:+.2f} rad"
    others = np.abs(np.delete(dq, joint))
    assert np.all(others < abs(dq[joint]) / 10), f"other joints moved too: dq = {dq}"


@pytest.mark.parametrize("axis", range(6))
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_ee_delta_moves_in_the_commanded_direction(client, session, axis, sign):
    tcp0 = np.array(client.observe(session).observation.tcp_pose)
    action = np.zeros(6)
    action[axis] = sign * 0.2  # normalised: 0.02 m or rad per step
    for _ in range(5):
        response = client.step(session, "pd_ee_delta_pose", action)
    tcp = np.array(response.observation.tcp_pose)
    dp = tcp[:3] - tcp0[:3]
    dr = quat_to_axis_angle(quat_mul(tcp[3:], quat_conj(tcp0[3:])))  # world-frame rotation since start
    moved, still = (dp, dr) if axis < 3 else (dr, dp)
    i = axis % 3
    assert sign * moved[i] > 0.02, f"axis {axis}: moved {moved} for 5 x {action}"
    assert np.all(np.abs(np.delete(moved, i)) < abs(moved[i]) / 5), f"axis {axis}: off-axis motion {moved}"
    if axis < 3:
        assert np.linalg.norm(still) < np.deg2rad(3), f"translation rotated the knife by {still} rad"
    else:
        assert np.linalg.norm(still) < 0.01, f"rotation about the TCP moved it by {still} m"


def test_env_close_is_idempotent_and_ends_the_session(address, client):
    env = CulinaryCutEnv(address, control_mode="pd_joint_delta_pos")
    sid = env.session_id
    env.reset(seed=0)
    env.close()
    env.close()
    with pytest.raises(errors.NotFound):
        client.observe(sid)
    with pytest.raises(RuntimeError, match="closed"):
        env.step(np.zeros(7))

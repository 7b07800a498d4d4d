"""CulinaryCutEnv as a gymnasium.Env against the real server: Gymnasium's env checker for every control mode,
a camera scene and a food scene; the registered ids; ManiSkill's observation dtypes; success and fail in info."""
from __future__ import annotations

import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from culinarycut import CulinaryCutEnv
from culinarycut.client import observation_to_dict
from culinarycut.policies import ScriptedOracle
from culinarycut.scenes import CUTTING_EFFECTS

# The checker's advice that does not apply: joint velocities, poses and wrenches are unbounded (ManiSkill
# declares its float observations unbounded too), and joint-position and pose actions are in rad and m.
EXPECTED_WARNINGS = ("A Box observation space minimum value is -infinity",
                     "A Box observation space maximum value is infinity",
                     "A Box action space minimum value is -infinity",
                     "A Box action space maximum value is infinity",
                     "For Box action spaces, we recommend using a symmetric and normalized space")
ALL_CHANNELS = ["rgb", "depth", "segmentation"]


def check_env_strictly(env) -> None:
    """gymnasium's check_env on the unwrapped env; any warning but the expected ones fails."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env.unwrapped)
    unexpected = [str(w.message) for w in caught if not any(text in str(w.message) for text in EXPECTED_WARNINGS)]
    assert not unexpected, unexpected


def control_modes(client) -> list[str]:
    handshake = client.create_session(None)
    client.close_session(handshake.session_id)
    return [mode.name for mode in handshake.control_modes]


def test_check_env_passes_for_every_control_mode(address, client):
    modes = control_modes(client)
    assert len(modes) >= 4, modes
    for mode in modes:
        env = gymnasium.make("CulinaryCut/Robot-v0", address=address, control_mode=mode)
        try:
            assert isinstance(env.unwrapped, gymnasium.Env) and env.unwrapped.control_mode == mode
            assert env.unwrapped.metadata["render_modes"] == []  # no camera: nothing to render
            check_env_strictly(env)
        finally:
            env.close()


def test_check_env_passes_for_a_camera_scene_with_rgb_array_rendering(address):
    scene = {"cameras": [{"name": "front", "width": 32, "height": 24, "channels": ALL_CHANNELS},
                         {"name": "wrist", "width": 16, "height": 16, "channels": ["depth"]}]}
    with gymnasium.make("CulinaryCut/Robot-v0", address=address, scene=scene, render_mode="rgb_array") as env:
        assert env.unwrapped.metadata["render_modes"] == ["rgb_array"]
        assert env.unwrapped.metadata["render_fps"] == pytest.approx(20.0)
        check_env_strictly(env)
        env.reset(seed=0)
        assert env.render().shape == (24, 32, 3)  # only the camera with rgb shows


def test_check_env_passes_for_the_registered_cutting_env(address):
    with gymnasium.make("CulinaryCut/CutCucumber-v0", address=address) as env:
        resolved = env.unwrapped.handshake.resolved_scene
        assert [o.food for o in resolved.objects] == ["cucumber"] and resolved.effects.mpm
        assert resolved.task.instruction and resolved.max_episode_steps > 0
        assert env.unwrapped.metadata["render_modes"] == ["rgb_array"]
        check_env_strictly(env)
        obs, info = env.reset(seed=0)
        assert obs["sensor_data"]["front"]["rgb"].shape == (224, 224, 3)
        assert info["instruction"] == resolved.task.instruction and len(info["food"]["pieces"]) == 1


def test_registered_ids_make_gymnasium_envs_with_their_spec(address):
    env = gymnasium.make("culinarycut:CulinaryCut/Robot-v0", address=address)  # the module:id form imports us
    try:
        assert env.spec.id == "CulinaryCut/Robot-v0" and env.unwrapped.spec.kwargs["address"] == address
        assert isinstance(env.unwrapped, CulinaryCutEnv) and isinstance(env.observation_space, gymnasium.spaces.Dict)
        obs, info = env.reset(seed=3)
        assert info["seed"] == 3 and obs in env.observation_space
    finally:
        env.close()
    with pytest.raises(ValueError, match="needs a camera with an rgb channel"):
        gymnasium.make("CulinaryCut/Robot-v0", address=address, render_mode="rgb_array")


def test_spaces_are_gymnasium_spaces_with_maniskills_dtypes_and_bounds(address):
    scene = {"cameras": [{"name": "front", "width": 40, "height": 30, "channels": ALL_CHANNELS}]}
    with CulinaryCutEnv(address, scene=scene, control_mode="pd_joint_delta_pos") as env:
        space = env.observation_space
        assert isinstance(space, gymnasium.spaces.Dict) and isinstance(env.action_space, gymnasium.spaces.Box)
        for group in ("agent", "extra"):
            assert all(box.dtype == np.float32 for box in space[group].values()), group
        assert all(box.dtype == np.float32 for box in space["sensor_param"]["front"].values())
        front = space["sensor_data"]["front"]
        assert front["rgb"].dtype == np.uint8 and front["rgb"].shape == (30, 40, 3)
        assert front["rgb"].low.min() == 0 and front["rgb"].high.max() == 255
        for channel in ("depth", "segmentation"):
            assert front[channel].dtype == np.int16 and front[channel].shape == (30, 40, 1)
            assert front[channel].low.min() == 0 and front[channel].high.max() == np.iinfo(np.int16).max
        # The joint limits the server declares survive the cast.
        qpos = space["agent"]["qpos"]
        assert np.all(np.isfinite(qpos.low)) and np.all(qpos.low < qpos.high)
        obs, _ = env.reset(seed=0)
        assert obs in space
        assert obs["agent"]["qpos"].flags.writeable and obs["sensor_data"]["front"]["rgb"].flags.writeable


def test_depth_is_int16_millimetres_of_the_servers_metres(address):
    scene = {"cameras": [{"name": "front", "width": 40, "height": 30, "channels": ALL_CHANNELS}]}
    with CulinaryCutEnv(address, scene=scene) as env:
        obs, _ = env.reset(seed=0)
        wire = observation_to_dict(env.client.observe(env.session_id).observation)  # metres, int32, float64
        depth_mm = obs["sensor_data"]["front"]["depth"]
        np.testing.assert_array_equal(depth_mm, np.rint(wire["sensor_data"]["front"]["depth"] * 1000).astype(np.int16))
        assert 100 < np.median(depth_mm[depth_mm > 0]) < 5000  # the scene is 0.1-5 m from the front camera
        np.testing.assert_array_equal(obs["sensor_data"]["front"]["segmentation"],
                                      wire["sensor_data"]["front"]["segmentation"])
        intrinsic = obs["sensor_param"]["front"]["intrinsic_cv"]
        assert intrinsic.dtype == np.float32
        np.testing.assert_array_equal(intrinsic, wire["sensor_param"]["front"]["intrinsic_cv"].astype(np.float32))


def test_info_counts_steps_and_keeps_wall_times_out(address):
    with CulinaryCutEnv(address, control_mode="pd_joint_delta_pos") as env:
        env.reset(seed=0)
        for k in range(1, 4):
            *_, info = env.step(np.zeros(7))
            assert info["elapsed_steps"] == k and info["success"] is False and info["fail"] is False
            assert not any(key.endswith("wall_time_ms") for key in info)
            assert set(env.last_step_timings) == {"step_wall_time_ms", "control_wall_time_ms", "physics_wall_time_ms",
                                                  "mpm_wall_time_ms", "topology_wall_time_ms", "render_wall_time_ms",
                                                  "safety_wall_time_ms", "rollback_wall_time_ms"}
            assert env.last_step_timings["physics_wall_time_ms"] > 0
        env.reset(seed=0)
        assert env.last_step_timings == {}


def test_fail_turns_true_once_an_extra_cut_makes_the_task_impossible(address):
    # The scene asks for one cut in the middle; the oracle is told to cut three pieces instead.
    scene = {"quality": "draft", "effects": CUTTING_EFFECTS,
             "objects": [{"food": "cucumber"}],
             "task": {"instruction": "cut the cucumber in the middle"}}
    with CulinaryCutEnv(address, scene=scene) as env:
        env.reset(seed=0)
        oracle = ScriptedOracle(env.client, env.session_id)
        oracle.reset("cut the cucumber into three equal pieces")
        history = []  # (pieces, success, fail, terminated) per step
        while not oracle.finished:
            _, values = oracle.act()
            _, _, terminated, _, info = env.step(values)
            history.append((len(info["food"]["pieces"]), info["success"], info["fail"], terminated))
    pieces, success, fail, terminated = zip(*history)
    assert max(pieces) == 3 and not any(success) and not any(terminated)
    first_fail = fail.index(True)
    assert all(fail[first_fail:]), "fail must stay true: cuts do not heal"
    # Two pieces (one misplaced cut) could still be scored; the third piece is the extra cut that fails.
    assert pieces[first_fail] == 3 and pieces[first_fail - 1] == 2

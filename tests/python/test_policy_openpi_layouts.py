"""openpi's three observation layouts (option `layout`): golden requests built the way openpi's own example
code builds them, sent through the real openpi-client to the stand-in and compared with what the adapter
sends; a request in the wrong layout named as such, not a KeyError; DROID's joint velocities and ALOHA's
joint positions executed in the model's time; and each layout's chunk driving a short episode on a real
server. Upstream: Physical-Intelligence/openpi, examples/ and src/openpi/policies/."""
from __future__ import annotations

import numpy as np
import pytest

import policy_support
from culinarycut.bench.episode import EpisodeOptions, run_episode
from culinarycut.bench.episode_scene import suite_episodes
from culinarycut.bench.suite import load_suite
from culinarycut_policies.openpi import OpenPIPolicy
from culinarycut_policies.standins.launch import make_standin
from culinarycut_policies.standins.process import StandinProcess
from culinarycut_policies.standins.websocket_server import WebsocketPolicyServer
from culinarycut_policies.transports.faults import PolicyServerError

# openpi-client 0.1.2 opens its websocket the way websockets 17.1 deprecated (it still works).
pytestmark = pytest.mark.filterwarnings("ignore:connect\\(\\) must be used as a context manager:DeprecationWarning")

INSTRUCTION = "cut the cucumber in the middle"
QPOS = np.array([0.12, -0.31, 0.05, -2.21, 0.03, 1.92, 0.74])  # a Panda pose near the knife's ready pose
TCP_WXYZ = np.array([0.08, 0.99, 0.06, -0.03]) / np.linalg.norm([0.08, 0.99, 0.06, -0.03])  # near edge down
STEPS = 12
CAMERA = 64


def observation(size: int = 96) -> dict:
    rng = np.random.Generator(np.random.PCG64(11))
    frames = {c: {"rgb": rng.integers(0, 256, (size, size, 3), dtype=np.uint8)} for c in ("front", "wrist")}
    return {"sensor_data": frames,
            "extra": {"tcp_pose": np.r_[0.45, 0.02, 0.21, TCP_WXYZ]},
            "agent": {"qpos": QPOS.astype(np.float32)}}  # CulinaryCutEnv's float32


# --- golden requests, built as upstream's examples build them ---------------------------------------------
def robosuite_quat2axisangle(xyzw: np.ndarray) -> np.ndarray:
    """robosuite.utils.transform_utils.quat2axisangle, which examples/libero/main.py's _quat2axisangle is."""
    w = float(np.clip(xyzw[3], -1.0, 1.0))
    den = np.sqrt(1.0 - w * w)
    return np.zeros(3) if np.isclose(den, 0.0) else xyzw[:3] * 2.0 * np.arccos(w) / den


def libero_golden(obs: dict) -> dict:
    # examples/libero/main.py: the `element` dict. LIBERO renders upside down and the example turns its
    # frames (img[::-1, ::-1]); our cameras are upright. The eef is the knife's TCP, its gripper_qpos the two
    # finger slots a knife does not have (0).
    from openpi_client import image_tools
    img = image_tools.convert_to_uint8(image_tools.resize_with_pad(obs["sensor_data"]["front"]["rgb"], 224, 224))
    wrist_img = image_tools.convert_to_uint8(image_tools.resize_with_pad(obs["sensor_data"]["wrist"]["rgb"], 224, 224))
    pose = obs["extra"]["tcp_pose"]
    return {"observation/image": img, "observation/wrist_image": wrist_img,
            "observation/state": np.concatenate((pose[:3], robosuite_quat2axisangle(np.r_[pose[4:7], pose[3]]),
                                                 np.zeros(2))),
            "prompt": str(INSTRUCTION)}


def droid_golden(obs: dict) -> dict:
    # examples/droid/main.py: _extract_observation's curr_obs, then request_data. The robot state's
    # joint_positions are the Panda's, its gripper_position 1.0 (closed on the knife's handle).
    from openpi_client import image_tools
    curr_obs = {"left_image": obs["sensor_data"]["front"]["rgb"], "wrist_image": obs["sensor_data"]["wrist"]["rgb"],
                "joint_position": np.array([float(q) for q in obs["agent"]["qpos"]]),
                "gripper_position": np.array([1.0])}
    return {"observation/exterior_image_1_left": image_tools.resize_with_pad(curr_obs["left_image"], 224, 224),
            "observation/wrist_image_left": image_tools.resize_with_pad(curr_obs["wrist_image"], 224, 224),
            "observation/joint_position": curr_obs["joint_position"],
            "observation/gripper_position": curr_obs["gripper_position"],
            "prompt": INSTRUCTION}


def aloha_golden(obs: dict, reset_pose) -> dict:
    # examples/aloha_real/env.py get_observation, with real_env.py's get_qpos: [left arm (6), left gripper,
    # right arm (6), right gripper]. Our arm is the left one (Panda joints 1, 2, 4, 5, 6, 7), its gripper
    # closed (0), the right arm at the server's reset_pose with its gripper open (1); the images our scene
    # has, resized with pad and channels first. aloha_real's runtime sends no prompt (the server's
    # default_prompt); make_aloha_example in src/openpi/policies/aloha_policy.py has one, as we send.
    from openpi_client import image_tools
    qpos = np.asarray(obs["agent"]["qpos"], dtype=np.float64)
    state = np.concatenate([qpos[[0, 1, 3, 4, 5, 6]], [0.0], np.asarray(reset_pose[:6], dtype=np.float64), [1.0]])
    images = {"cam_high": obs["sensor_data"]["front"]["rgb"], "cam_left_wrist": obs["sensor_data"]["wrist"]["rgb"]}
    for name in images:
        img = image_tools.convert_to_uint8(image_tools.resize_with_pad(images[name], 224, 224))
        images[name] = np.transpose(img, (2, 0, 1))  # einops.rearrange(img, "h w c -> c h w")
    return {"state": state, "images": images, "prompt": INSTRUCTION}


def golden(layout: str, obs: dict, metadata: dict) -> dict:
    return {"libero": libero_golden, "droid": droid_golden}[layout](obs) if layout != "aloha" \
        else aloha_golden(obs, metadata["reset_pose"])


def assert_same_request(ours: dict, theirs: dict, where: str = "") -> None:
    assert list(ours) == list(theirs), where
    for key, expected in theirs.items():
        value = ours[key]
        if isinstance(expected, dict):
            assert_same_request(value, expected, f"{where}{key}/")
        elif isinstance(expected, np.ndarray):
            assert isinstance(value, np.ndarray) and value.shape == expected.shape, f"{where}{key}"
            assert value.dtype == expected.dtype, f"{where}{key}: {value.dtype} != {expected.dtype}"
            if expected.dtype == np.uint8:
                np.testing.assert_array_equal(value, expected, err_msg=f"{where}{key}")
            else:
                np.testing.assert_allclose(value, expected, rtol=0, atol=1e-12, err_msg=f"{where}{key}")
        else:
            assert value == expected and type(value) is type(expected), f"{where}{key}"


@pytest.mark.parametrize("layout, actions", [("libero", (10, 7)), ("droid", (10, 8)), ("aloha", (50, 14))])
def test_adapter_sends_what_upstream_example_sends(layout, actions):
    from openpi_client.websocket_client_policy import WebsocketClientPolicy
    server, fake = make_standin("openpi", layout=layout)
    server.start()
    obs = observation()
    try:
        upstream = WebsocketClientPolicy(server.host, server.port)
        metadata = upstream.get_server_metadata()
        assert metadata["layout"] == layout
        reply = upstream.infer(golden(layout, obs, metadata))
        upstream._ws.close()
        assert reply["actions"].shape == actions
        theirs = fake.last_request  # as the server decoded it
        policy = OpenPIPolicy(url=server.url, layout=layout, camera_size=96)
        policy.reset(INSTRUCTION, {"control_frequency_hz": 20.0})
        mode, _ = policy.act(obs)
        policy.close()
    finally:
        server.stop()
    assert mode == ("pd_ee_delta_pose" if layout == "libero" else "pd_joint_pos")
    assert_same_request(fake.last_request, theirs)


def test_aloha_without_a_wrist_camera_sends_cam_high_only():
    server, fake = make_standin("openpi", layout="aloha")
    server.start()
    try:
        policy = OpenPIPolicy(url=server.url, layout="aloha", wrist_camera="")
        assert [c["name"] for c in policy.cameras] == ["front"]
        policy.reset(INSTRUCTION, {})
        policy.act(observation())
        policy.close()
    finally:
        server.stop()
    assert list(fake.last_request["images"]) == ["cam_high"]  # AlohaInputs masks the missing wrists



def test_extra_observations_only_when_the_server_asks():
    """A server's metadata `extra_observations` adds those keys after the layout's (CulinaryCut's trained
    policy asks for the wrist force); a key the adapter does not know stops it before the first query."""
    wrench = np.array([1.5, -2.0, 30.0, 0.1, -0.2, 0.05])
    obs = observation()
    obs["extra"]["wrist_wrench"] = wrench.astype(np.float64)
    seen = []
    metadata = {"layout": "libero", "extra_observations": ["observation/wrist_wrench"]}
    server = WebsocketPolicyServer(lambda request: seen.append(request) or {"actions": np.zeros((10, 7))},
                                   metadata).start()
    try:
        policy = OpenPIPolicy(url=server.url, camera_size=96)
        policy.reset(INSTRUCTION, {"control_frequency_hz": 20.0})
        policy.act(obs)
        policy.close()
    finally:
        server.stop()
    assert list(seen[0]) == ["observation/image", "observation/wrist_image", "observation/state", "prompt",
                             "observation/wrist_wrench"]
    np.testing.assert_array_equal(seen[0]["observation/wrist_wrench"], wrench)
    server = WebsocketPolicyServer(lambda request: {"actions": np.zeros((10, 7))},
                                   {"extra_observations": ["observation/smell"]}).start()
    try:
        with pytest.raises(PolicyServerError, match="asks for extra observations \\['observation/smell'\\]"):
            OpenPIPolicy(url=server.url).preflight()
    finally:
        server.stop()


def test_connection_model_keeps_state_per_connection():
    """connection_model: one model per connection, so a model's per-episode state starts afresh."""
    made = []

    def connection_model():
        count = {"queries": 0}
        made.append(count)

        def model(request):
            count["queries"] += 1
            return {"actions": np.full((10, 7), float(count["queries"]))}
        return model
    server = WebsocketPolicyServer(None, {"layout": "libero"}, connection_model=connection_model).start()
    try:
        for _ in range(2):
            policy = OpenPIPolicy(url=server.url, camera_size=96, replan_steps=1)
            policy.reset(INSTRUCTION, {"control_frequency_hz": 20.0})
            for _ in range(3):
                policy.act(observation())
            policy.close()
    finally:
        server.stop()
    assert [m["queries"] for m in made] == [3, 3]

# --- the wrong layout --------------------------------------------------------------------------------------
def test_a_request_in_the_wrong_layout_is_named():
    from openpi_client.websocket_client_policy import WebsocketClientPolicy
    server, _ = make_standin("openpi", layout="droid")
    server.start()
    try:
        # openpi-client sending the LIBERO example to a DROID server: the stand-in says why, no KeyError.
        upstream = WebsocketClientPolicy(server.host, server.port)
        with pytest.raises(RuntimeError) as refused:
            upstream.infer(libero_golden(observation()))
        assert "reads the droid layout" in str(refused.value) and "is in the libero layout" in str(refused.value)
        assert "KeyError" not in str(refused.value)
        # The adapter learns the stand-in's layout from its metadata and stops before the first query.
        policy = OpenPIPolicy(url=server.url, layout="libero")
        with pytest.raises(PolicyServerError, match="droid layout, not libero: set option layout=droid"):
            policy.preflight()
    finally:
        server.stop()


@pytest.mark.parametrize("read, served", [("observation/exterior_image_1_left", "droid"), ("state", "aloha"),
                                          ("observation/image", "libero")])
def test_a_real_servers_key_error_names_the_layout_it_reads(read, served):
    # A real openpi server names no layout; its input transform (DroidInputs, AlohaInputs, LiberoInputs)
    # fails on the first key it lacks, and the traceback comes back as a text frame.
    server = WebsocketPolicyServer(lambda request: {"actions": request[read]}, {}).start()
    layout = "aloha" if served != "aloha" else "droid"
    try:
        policy = OpenPIPolicy(url=server.url, layout=layout)
        policy.reset(INSTRUCTION, {})
        with pytest.raises(PolicyServerError) as failed:
            policy.act(observation())
        policy.close()
    finally:
        server.stop()
    message = str(failed.value)
    assert f"reads {read!r}, a key of openpi's {served} layout" in message and f"set option layout={served}" in message


def test_options_are_checked_per_layout():
    with pytest.raises(ValueError, match="layout='bridge'; choose one of libero, droid, aloha"):
        OpenPIPolicy(layout="bridge")
    with pytest.raises(ValueError, match="option state_dim, action_units applies to layout=libero only, not droid"):
        OpenPIPolicy(layout="droid", action_units="metres_radians", state_dim=8)
    with pytest.raises(ValueError, match="layout droid sends a wrist image, which openpi's DroidInputs requires"):
        OpenPIPolicy(layout="droid", wrist_camera="")
    with pytest.raises(ValueError, match="layout libero sends a wrist image, which openpi's LiberoInputs requires"):
        OpenPIPolicy(layout="libero", wrist_camera="")
    assert OpenPIPolicy().control_mode == "pd_ee_delta_pose"
    assert OpenPIPolicy(layout="aloha").control_mode == "pd_joint_pos"


# --- joint actions in the model's time ---------------------------------------------------------------------
def serve(chunk: np.ndarray, metadata: dict | None = None):
    queries = []

    def model(request):
        queries.append(request)
        return {"actions": chunk}
    return WebsocketPolicyServer(model, metadata or {}).start(), queries


@pytest.mark.parametrize("control_hz, steps_per_chunk", [(15.0, 8), (20.0, 11)])
def test_droid_joint_velocities_become_joint_targets_at_droids_rate(control_hz, steps_per_chunk):
    # examples/droid/main.py clips each action to [-1, 1]; DROID's RobotEnv(action_space="joint_velocity") then
    # targets q + 0.2 v (droid/robot_ik/robot_ik_solver.py: max_joint_delta 0.2 rad per 15 Hz step).
    chunk = np.zeros((10, 8))
    chunk[:, 0] = 0.1 * np.arange(1, 11)
    chunk[:, 3] = -3.0  # clipped to -1
    chunk[:, 7] = 1.0   # the gripper: ignored
    server, queries = serve(chunk)
    obs = observation(32)
    try:
        policy = OpenPIPolicy(url=server.url, layout="droid")
        policy.reset(INSTRUCTION, {"control_frequency_hz": control_hz})
        commands = [policy.act(obs) for _ in range(steps_per_chunk)]
        assert len(queries) == 1
        policy.act(obs)
        assert len(queries) == 2
        policy.close()
    finally:
        server.stop()
    assert {mode for mode, _ in commands} == {"pd_joint_pos"}
    deltas = np.array([values for _, values in commands]) - QPOS.astype(np.float32)
    per_step = 15.0 / control_hz  # model steps per control step
    # each control step [a, b) (in model steps) takes each element for the part of its model step it covers
    expected = []
    for k in range(steps_per_chunk):
        a, b = k * per_step, (k + 1) * per_step
        expected.append(sum((min(b, i + 1) - max(a, i)) * chunk[i, 0] for i in range(int(a), int(np.ceil(b - 1e-9)))))
    np.testing.assert_allclose(deltas[:, 0], 0.2 * np.array(expected), atol=1e-12)
    np.testing.assert_allclose(deltas[:, 3], -0.2 * per_step, atol=1e-12)
    np.testing.assert_allclose(deltas[:, [1, 2, 4, 5, 6]], 0.0, atol=1e-12)
    if control_hz == 15.0:  # DROID's own rate: exactly one element per step
        np.testing.assert_allclose(deltas[:, 0], 0.2 * chunk[:8, 0], atol=1e-12)


@pytest.mark.parametrize("control_hz, steps_per_chunk", [(50.0, 25), (20.0, 10)])
def test_aloha_left_arm_positions_drive_the_panda(control_hz, steps_per_chunk):
    # Element k of the chunk is ALOHA's 14-D target at the end of its 50 Hz step k (examples/aloha_real/
    # real_env.py step: left arm joints, left gripper, right arm joints, right gripper).
    k = np.arange(50)[:, None]
    chunk = np.hstack([0.01 * k + np.arange(6) * 0.1, np.full((50, 1), 0.5), np.full((50, 7), 9.0)])
    server, queries = serve(chunk, {"reset_pose": [0.0, -1.5, 1.5, 0.0, 0.0, 0.0]})
    obs = observation(32)
    try:
        policy = OpenPIPolicy(url=server.url, layout="aloha")
        policy.reset(INSTRUCTION, {"control_frequency_hz": control_hz})
        commands = [policy.act(obs) for _ in range(steps_per_chunk)]
        assert len(queries) == 1
        policy.act(obs)
        assert len(queries) == 2
        policy.close()
    finally:
        server.stop()
    state = queries[0]["state"]
    np.testing.assert_allclose(state, np.r_[QPOS[[0, 1, 3, 4, 5, 6]], 0.0, 0.0, -1.5, 1.5, 0.0, 0.0, 0.0, 1.0],
                               atol=1e-6)  # float32 joints; the right arm at the server's reset_pose
    targets = np.array([values for _, values in commands])
    sampled = np.arange(1, steps_per_chunk + 1) * 50.0 / control_hz - 1  # the element at each step's end
    np.testing.assert_allclose(targets[:, [0, 1, 3, 4, 5, 6]], 0.01 * sampled[:, None] + np.arange(6) * 0.1, atol=1e-12)
    np.testing.assert_allclose(targets[:, 2], np.float32(QPOS[2]), atol=1e-12)  # joint 3 held


def test_the_standin_serves_a_layout_from_the_command_line():
    from openpi_client.websocket_client_policy import WebsocketClientPolicy
    standin = StandinProcess("openpi", "--layout", "aloha")
    try:
        upstream = WebsocketClientPolicy(standin.url)
        assert upstream.get_server_metadata()["layout"] == "aloha"
        reply = upstream.infer(aloha_golden(observation(), [0.0] * 6))
        upstream._ws.close()
    finally:
        standin.close()
    assert reply["actions"].shape == (50, 14)
    with pytest.raises(ValueError, match="a layout is the openpi stand-in's"):
        make_standin("octo", layout="droid")


# --- a short episode per layout on a real server -----------------------------------------------------------
@pytest.fixture(scope="module")
def spec(tmp_path_factory):
    return suite_episodes(load_suite(str(policy_support.write_suite(tmp_path_factory.mktemp("openpi"), STEPS))))[0]


def episode(spec, address, layout: str) -> list[dict]:
    """The stand-in's requests over one STEPS-step episode (at the scene's 20 Hz) in `layout`."""
    server, fake = make_standin("openpi", layout=layout)
    requests = []
    server.model = lambda request: (requests.append(request), fake(request))[1]
    server.start()
    try:
        result = run_episode(spec, address, EpisodeOptions(
            policy="culinarycut_policies.openpi:OpenPIPolicy",
            policy_options={"url": server.url, "layout": layout, "camera_size": CAMERA}))
    finally:
        server.stop()
    row = result.row
    assert (row["error"], row["end_reason"], row["steps"]) == ("", "step_limit", STEPS), row["error"]
    return requests


def test_libero_episode(spec, address):
    requests = episode(spec, address, "libero")
    assert len(requests) == 3  # steps 0, 5, 10
    assert requests[0]["observation/state"].shape == (8,)


def test_droid_episode_turns_joint_1_at_the_chunks_velocity(spec, address):
    requests = episode(spec, address, "droid")
    assert len(requests) == 2  # 8 DROID steps last 11 control steps at 20 Hz
    moved = requests[1]["observation/joint_position"] - requests[0]["observation/joint_position"]
    commanded = 0.2 * 0.05 * 11 * 0.75  # the stand-in's velocity 0.05 for the 11 steps before the second query
    # each step's target is the measured joint plus the step's delta; the joint PD's 50 ms time constant
    # covers about 0.63 of it in a 50 ms step (measured: 0.64)
    assert 0.5 * commanded < moved[0] < commanded, moved
    assert np.abs(moved[1:]).max() < 1e-3, moved
    assert requests[0]["observation/gripper_position"].tolist() == [1.0]


def test_aloha_episode_holds_the_arm_but_the_waist(spec, address):
    requests = episode(spec, address, "aloha")
    assert len(requests) == 2  # 25 ALOHA steps last 10 control steps at 20 Hz
    first, second = requests[0]["state"], requests[1]["state"]
    np.testing.assert_allclose(second[6:], [0.0, 0.0, -1.5, 1.5, 0.0, 0.0, 0.0, 1.0])  # the stand-in's reset_pose
    moved = second[:6] - first[:6]
    assert 0.04 < moved[0] < 0.0505, moved  # the stand-in's waist target: 0.002 (k + 1), k = 24 by then
    assert np.abs(moved[1:]).max() < 1e-3, moved
    assert set(requests[0]["images"]) == {"cam_high", "cam_left_wrist"}

"""Camera images through the server: ManiSkill's sensor_data / sensor_param, only the channels asked
for, known depth and segmentation, encodings, the wrist camera, render() and bad camera specs."""
from __future__ import annotations

import math

import numpy as np
import pytest

from culinarycut import CulinaryCutEnv, errors
from culinarycut.client import observation_to_dict, segmentation_labels_to_dict

BOARD_TOP_Z_M = 0.02
# A camera 0.3 m above a point of the board, looking straight down: the OpenCV frame rotated by pi
# about (1, 1, 0) / sqrt(2) has x along world y, y along world x and z (forward) down.
DOWN = [0.0, math.sqrt(0.5), math.sqrt(0.5), 0.0]
BOARD_POINT_M = [0.62, 0.10, BOARD_TOP_Z_M]
HEIGHT_ABOVE_BOARD_M = 0.3


def looking_down(name: str, **fields) -> dict:
    eye = [BOARD_POINT_M[0], BOARD_POINT_M[1], BOARD_TOP_Z_M + HEIGHT_ABOVE_BOARD_M]
    return {"name": name, "pose": {"position": eye, "quaternion": DOWN}, "width": 65, "height": 49, **fields}


def reset_observation(client, scene: dict, seed: int = 0):
    handshake = client.create_session(scene)
    response = client.reset(handshake.session_id, seed=seed)
    return handshake, response


def test_default_cameras_give_maniskill_sensor_data_and_param(client):
    scene = {"cameras": [{"name": "front", "channels": ["rgb", "depth", "segmentation"]}, {"name": "left"},
                         {"name": "right", "width": 96, "height": 64}]}
    handshake, response = reset_observation(client, scene)
    obs = observation_to_dict(response.observation)
    assert list(obs["sensor_data"]) == ["front", "left", "right"]
    front = obs["sensor_data"]["front"]
    assert front["rgb"].shape == (224, 224, 3) and front["rgb"].dtype == np.uint8
    assert front["depth"].shape == (224, 224, 1) and front["depth"].dtype == np.float32
    assert front["segmentation"].shape == (224, 224, 1) and front["segmentation"].dtype == np.int32
    assert set(obs["sensor_data"]["left"]) == {"rgb"}  # only the channels asked for travel
    assert obs["sensor_data"]["right"]["rgb"].shape == (64, 96, 3)
    param = obs["sensor_param"]["right"]
    assert param["intrinsic_cv"][0, 2] == pytest.approx((96 - 1) / 2)
    assert param["extrinsic_cv"].shape == (3, 4) and param["cam2world_gl"].shape == (4, 4)
    # cam2world_gl is the OpenGL frame (y up, z back) of the same pose as extrinsic_cv.
    world_to_cv = np.vstack([param["extrinsic_cv"], [0, 0, 0, 1]])
    np.testing.assert_allclose(np.linalg.inv(world_to_cv) @ np.diag([1, -1, -1, 1]), param["cam2world_gl"], atol=1e-9)
    # The handshake describes exactly these arrays.
    specs = {spec.name: (tuple(spec.shape), spec.dtype) for spec in handshake.observation_spec}
    assert specs["sensor_data/front/depth"] == ((224, 224, 1), "float32")
    assert specs["sensor_data/right/rgb"] == ((64, 96, 3), "uint8")
    assert "sensor_data/left/depth" not in specs
    # The background of the front view is the scene, not black: something was drawn.
    assert front["rgb"].mean() > 50 and (front["depth"] > 0).mean() > 0.5
    client.close_session(handshake.session_id)


def test_depth_and_segmentation_of_the_board_are_exact_below_a_known_camera(client):
    handshake, response = reset_observation(client, {"cameras": [looking_down("down", channels=["depth", "segmentation"])]})
    obs = observation_to_dict(response.observation)
    down = obs["sensor_data"]["down"]
    assert "rgb" not in down
    assert down["depth"][24, 32, 0] == pytest.approx(HEIGHT_ABOVE_BOARD_M, abs=1e-3)
    labels = segmentation_labels_to_dict(response.observation)
    assert labels[int(down["segmentation"][24, 32, 0])]["kind"] == "board"
    # The board point projects to the image centre through K [R | t].
    param = obs["sensor_param"]["down"]
    pixel = param["intrinsic_cv"] @ param["extrinsic_cv"] @ np.array([*BOARD_POINT_M, 1.0])
    np.testing.assert_allclose(pixel[:2] / pixel[2], [32.0, 24.0], atol=1e-6)
    client.close_session(handshake.session_id)


def test_food_shows_in_segmentation_with_its_label(client):
    scene = {"quality": "draft", "effects": {"mpm": True, "topology": True}, "objects": [{"food": "cucumber"}],
             "cameras": [{"name": "front", "channels": ["segmentation"]}]}
    handshake, response = reset_observation(client, scene)
    segmentation = observation_to_dict(response.observation)["sensor_data"]["front"]["segmentation"]
    labels = segmentation_labels_to_dict(response.observation)
    food_ids = [i for i, label in labels.items() if label["kind"] == "food"]
    assert [labels[i]["food"] for i in food_ids] == ["cucumber"]
    assert (segmentation == food_ids[0]).sum() > 100
    client.close_session(handshake.session_id)


def test_images_are_deterministic_and_png_is_lossless(client):
    # front_png takes front's resolved pose explicitly, read back from a probe session.
    probe = client.create_session({"cameras": [{"name": "front", "width": 80, "height": 60}]})
    pose = probe.resolved_scene.cameras[0].pose
    client.close_session(probe.session_id)
    front_png = {"name": "front_png", "pose": {"position": list(pose.position), "quaternion": list(pose.quaternion)},
                 "width": 80, "height": 60, "rgbEncoding": "png"}
    scene = {"cameras": [{"name": "front", "width": 80, "height": 60}, front_png]}
    first_session, first = reset_observation(client, scene)
    second_session, second = reset_observation(client, scene)
    a, b = observation_to_dict(first.observation), observation_to_dict(second.observation)
    assert first.observation.cameras[1].rgb_encoding == "png"
    assert len(first.observation.cameras[1].rgb) < len(first.observation.cameras[0].rgb)
    np.testing.assert_array_equal(a["sensor_data"]["front"]["rgb"], b["sensor_data"]["front"]["rgb"])
    np.testing.assert_array_equal(a["sensor_data"]["front"]["rgb"], a["sensor_data"]["front_png"]["rgb"])
    client.close_session(first_session.session_id)
    client.close_session(second_session.session_id)


def test_the_wrist_camera_moves_with_the_robot_and_the_world_cameras_stay(client):
    handshake, response = reset_observation(client, {"cameras": [{"name": "wrist"}, {"name": "front"}]})
    before = observation_to_dict(response.observation)["sensor_param"]
    step = client.step(handshake.session_id, "pd_ee_delta_pose", [0.0, 0.5, 0.0, 0.0, 0.0, 0.0])
    after = observation_to_dict(step.observation)["sensor_param"]
    moved_m = np.linalg.norm(after["wrist"]["cam2world_gl"][:3, 3] - before["wrist"]["cam2world_gl"][:3, 3])
    assert moved_m > 0.005
    np.testing.assert_array_equal(after["front"]["cam2world_gl"], before["front"]["cam2world_gl"])
    assert step.info.render_wall_time_ms > 0.0
    stats = client.session_stats(handshake.session_id)
    assert stats.stage_calls["render"] == 2 and stats.stage_wall_time_s["render"] > 0.0
    client.close_session(handshake.session_id)


def test_the_kitchen_scene_looks_different_from_the_plain_table(client):
    images = {}
    for scene_name in ("table", "kitchen"):
        handshake, response = reset_observation(client, {"scene": scene_name, "cameras": [{"name": "left"}]})
        assert handshake.resolved_scene.scene == scene_name
        images[scene_name] = observation_to_dict(response.observation)["sensor_data"]["left"]["rgb"].astype(int)
        client.close_session(handshake.session_id)
    assert np.abs(images["kitchen"] - images["table"]).mean() > 5.0


def test_a_scene_without_cameras_renders_nothing(client):
    handshake, response = reset_observation(client, {})
    assert len(response.observation.cameras) == 0 and "sensor_data" not in observation_to_dict(response.observation)
    step = client.step(handshake.session_id, "pd_ee_delta_pose", np.zeros(6))
    assert step.info.render_wall_time_ms == 0.0
    assert client.session_stats(handshake.session_id).stage_calls["render"] == 0
    client.close_session(handshake.session_id)


def test_env_render_tiles_the_rgb_cameras_and_spaces_hold_the_images(address):
    scene = {"cameras": [{"name": "front", "width": 64, "height": 48}, {"name": "left", "width": 32, "height": 32},
                         {"name": "depth_only", "pose": looking_down("x")["pose"], "channels": ["depth"]}]}
    with CulinaryCutEnv(address, scene=scene, render_mode="rgb_array") as env:
        obs, info = env.reset(seed=0)
        assert env.observation_space["sensor_data"]["front"]["rgb"].shape == (48, 64, 3)
        assert env.observation_space["sensor_data"].contains(obs["sensor_data"])
        assert "segmentation_labels" not in info  # no camera asked for segmentation
        frame = env.render()
        assert frame.shape == (48, 64 + 32, 3) and frame.dtype == np.uint8
        np.testing.assert_array_equal(frame[:, :64], obs["sensor_data"]["front"]["rgb"])
        assert not frame[32:, 64:].any()  # the shorter camera is padded with black
    with pytest.raises(ValueError, match="rgb channel"):
        CulinaryCutEnv(address, scene={}, render_mode="rgb_array")


@pytest.mark.parametrize("camera, field", [
    ({"name": "front", "channels": ["infrared"]}, r"scene.cameras\[0\].channels"),
    ({"name": "overhead"}, r"scene.cameras\[0\] \(\"overhead\"\) needs a pose"),
    ({"name": "front", "width": 5000}, r"scene.cameras\[0\].width"),
    ({"name": "bad name!"}, r"scene.cameras\[0\].name"),
    ({"name": "front", "rgbEncoding": "gif"}, r"scene.cameras\[0\].rgb_encoding"),
    ({**looking_down("hand"), "attachedLink": "panda_link99"}, r"scene.cameras\[0\].attached_link"),
    ({"name": "front", "pose": {"position": [0, 0, 1]}}, r"scene.cameras\[0\].pose"),
])
def test_bad_cameras_are_refused_with_the_field_named(client, camera, field):
    with pytest.raises(errors.InvalidArgument, match=field):
        client.create_session({"cameras": [camera]})


def test_two_cameras_with_one_name_are_refused(client):
    with pytest.raises(errors.InvalidArgument, match="used twice"):
        client.create_session({"cameras": [{"name": "front"}, {"name": "front"}]})

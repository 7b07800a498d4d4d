"""The paper's tasks end to end through the server: a scene with a task, the scripted oracle driving
the Panda, the MPM food cut, and the scored outcome in info (draft preset, real food materials)."""
from __future__ import annotations

import numpy as np
import pytest

from culinarycut import CulinaryCutEnv, errors
from culinarycut.policies import ScriptedOracle

CUTTING_EFFECTS = {"mpm": True, "damage": True, "friction": True, "topology": True, "force_sensing": True}


def task_scene(food: str, task: dict, cameras=()) -> dict:
    return {"quality": "draft", "effects": CUTTING_EFFECTS, "objects": [{"food": food}],
            "task": task, "cameras": list(cameras)}


def run_oracle(env: CulinaryCutEnv, seed: int = 0):
    """Reset, then step the scene task's oracle until the episode terminates or the plan ends."""
    observation, reset_info = env.reset(seed=seed)
    oracle = ScriptedOracle(env.client, env.session_id)
    oracle.reset()  # no instruction: the scene's task
    rewards, terminated, info = [], False, {}
    while not (oracle.finished or terminated):
        mode, values = oracle.act()
        assert mode == env.control_mode
        observation, reward, terminated, truncated, info = env.step(values)
        rewards.append(reward)
    return reset_info, observation, rewards, terminated, info


def test_cutting_the_cucumber_at_0_3_from_the_left_succeeds_and_shows_two_pieces(address):
    scene = task_scene("cucumber", {"instruction": "cut the cucumber at 0.3 ratio from the left"},
                       cameras=[{"name": "front", "channels": ["rgb", "segmentation"]}])
    with CulinaryCutEnv(address, scene=scene) as env:
        reset_info, observation, rewards, terminated, info = run_oracle(env)
    assert reset_info["instruction"] == "cut the cucumber at 0.3 ratio from the left"
    assert terminated and info["success"] and rewards[-1] == 1.0 and set(rewards[:-1]) == {0.0}
    cut = info["task"]["required"][0]
    assert cut["target_fraction"] == pytest.approx(0.3) and cut["position_error_fraction"] < 0.1
    # The two pieces are two food segments in the front camera's segmentation.
    labels = info["segmentation_labels"]
    food_ids = [i for i, label in labels.items() if label["kind"] == "food"]
    assert len(food_ids) == 2 and {labels[i]["piece"] for i in food_ids} == {0, 1}
    segmentation = observation["sensor_data"]["front"]["segmentation"]
    assert all((segmentation == i).sum() >= 20 for i in food_ids)


def test_a_guillotine_cut_of_an_apple_in_the_middle_succeeds(address):
    with CulinaryCutEnv(address, scene=task_scene("apple", {"cut_style": "guillotine", "cut_state": "middle"})) as env:
        assert env.handshake.resolved_scene.task.target_object == "apple"
        _, _, _, terminated, info = run_oracle(env)
    assert terminated and info["success"]
    assert info["task"]["required"][0]["position_error_fraction"] < 0.1


def test_a_3_way_split_of_a_banana_places_both_cuts(address):
    with CulinaryCutEnv(address, scene=task_scene("banana", {"cut_state": "split", "split_pieces": 3})) as env:
        _, _, _, terminated, info = run_oracle(env)
    assert terminated and info["success"]
    assert info["task"]["cuts_required"] == 2 and info["task"]["cuts_within_position_tolerance"] == 2
    assert [round(cut["target_fraction"], 3) for cut in info["task"]["required"]] == [0.333, 0.667]
    assert len(info["food"]["pieces"]) == 3


def test_without_topology_updates_the_cut_is_scored_but_the_food_is_observed_whole(address):
    """The paper's topology ablation: the observed food keeps its connectivity, the score does not."""
    scene = task_scene("cucumber", {"instruction": "cut the cucumber at 0.3 ratio from the left"},
                       cameras=[{"name": "front", "width": 64, "height": 64, "channels": ["segmentation"]}])
    scene["effects"] = {**CUTTING_EFFECTS, "topology": False}
    with CulinaryCutEnv(address, scene=scene) as env:
        _, _, _, terminated, info = run_oracle(env)
    assert terminated and info["success"]
    assert info["task"]["required"][0]["position_error_fraction"] < 0.1
    assert len(info["food"]["pieces"]) == 1  # observed as at reset
    food_ids = [i for i, label in info["segmentation_labels"].items() if label["kind"] == "food"]
    assert len(food_ids) == 1


def test_before_the_cut_the_task_is_scored_as_not_done(client):
    handshake = client.create_session(task_scene("cucumber", {"cut_state": "ratio", "ratio": 0.3, "reference": "left"}))
    resolved = handshake.resolved_scene.task
    assert (resolved.cut_style, resolved.cut_state, resolved.reference) == ("normal", "ratio", "left")
    reset = client.reset(handshake.session_id)
    assert reset.observation.instruction  # generated from the spec
    step = client.step(handshake.session_id, "pd_ee_delta_pose", np.zeros(6))
    assert not step.terminated and step.reward == 0.0
    assert not step.task_score.success and step.task_score.cuts_required == 1
    assert not step.task_score.required[0].placed
    client.close_session(handshake.session_id)


@pytest.mark.parametrize("scene, message", [
    (task_scene("cucumber", {"instruction": "cut the cucumber in half", "cut_state": "middle"}), "not both"),
    (task_scene("cucumber", {"instruction": "make me a sandwich"}), r"scene.task.instruction"),
    (task_scene("cucumber", {"cut_state": "ratio"}), r"scene.task.ratio"),
    (task_scene("cucumber", {"target_object": "apple"}), "targets apple"),
    (task_scene("cucumber", {"cut_style": "chop"}), "scene.task"),
    ({"task": {"cut_state": "middle", "target_object": "cucumber"}}, "needs food"),
])
def test_bad_tasks_are_refused_with_the_field_named(client, scene, message):
    with pytest.raises(errors.InvalidArgument, match=message):
        client.create_session(scene)

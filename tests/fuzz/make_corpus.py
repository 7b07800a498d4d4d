#!/usr/bin/env python3
"""Writes the seed inputs of the scene and action fuzz targets (tests/fuzz/corpus/<target>/): a few
valid requests of each kind, from which libFuzzer mutates. The snapshot target's seeds are written by
the target itself: CULINARYCUT_FUZZ_WRITE_SEEDS=DIR build-fuzz/tests/fuzz/fuzz_snapshot -runs=0."""
from __future__ import annotations

from pathlib import Path

from culinarycut.client import scene_to_proto
from culinarycut.v1 import simulator_pb2

HERE = Path(__file__).resolve().parent
CUTTING = {"mpm": True, "damage": True, "friction": True, "topology": True, "force_sensing": True}
SCENES = {
    "robot_only": {},
    "robot_settings": {"robot": {"control_frequency_hz": 10, "physics_frequency_hz": 1000, "joint_stiffness": 30}},
    "cucumber_task": {"quality": "draft", "effects": CUTTING, "objects": [{"food": "cucumber"}],
                      "task": {"instruction": "cut the cucumber at 0.3 ratio from the left"}},
    "two_foods": {"quality": "draft", "effects": CUTTING, "objects": [
        {"food": "apple", "pose": {"position": [0.45, 0.05]}},
        {"food": "banana", "scale": 1.2, "material": "banana", "material_overrides": {"youngs_modulus_pa": 3e5}}],
        "task": {"cut_style": "saw", "cut_state": "split", "split_pieces": 3, "target_object": "banana"}},
    "cameras": {"cameras": [{"name": "front", "channels": ["rgb", "depth", "segmentation"], "width": 32, "height": 24},
                            {"name": "mine", "pose": {"position": [1, 0, 0.5], "quaternion": [0, 0, 1, 0]},
                             "fov_y_deg": 40, "attached_link": "panda_hand", "rgb_encoding": "png"}]},
    "resolution": {"quality": "draft", "effects": {"mpm": True}, "objects": [{"food": "strawberry"}],
                   "mpm": {"dx": 0.01, "particles_per_cell": 2, "cfl": 0.4}, "max_episode_steps": 5, "seed": "7"},
}
ACTIONS = {
    "joint_pos": ("pd_joint_pos", [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8]),
    "joint_delta": ("pd_joint_delta_pos", [0.1] * 7),
    "ee_delta_pos": ("pd_ee_delta_pos", [0.0, 0.0, -0.5]),
    "ee_delta_pose": ("pd_ee_delta_pose", [0.1, 0.0, -0.2, 0.0, 0.3, 0.0]),
    "ee_pose": ("pd_ee_pose", [0.5, 0.0, 0.2, 3.14, 0.0, 0.0]),
    "ee_pose_quat": ("pd_ee_pose_quat", [0.5, 0.0, 0.15, 0.0, 1.0, 0.0, 0.0]),
    "default_mode": ("", [0.0] * 7),
}


def main() -> None:
    scenes, actions = HERE / "corpus" / "fuzz_scene", HERE / "corpus" / "fuzz_action"
    scenes.mkdir(parents=True, exist_ok=True)
    actions.mkdir(parents=True, exist_ok=True)
    for name, scene in SCENES.items():
        (scenes / f"{name}.pb").write_bytes(scene_to_proto(scene).SerializeToString())
    for name, (mode, values) in ACTIONS.items():
        request = simulator_pb2.StepRequest(session_id="s-0", action=simulator_pb2.Action(control_mode=mode,
                                                                                         values=values))
        (actions / f"{name}.pb").write_bytes(request.SerializeToString())


if __name__ == "__main__":
    main()

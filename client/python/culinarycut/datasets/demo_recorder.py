"""Records a Demonstration from the observations of a session while someone (or something) drives it."""
from __future__ import annotations

import json

import numpy as np

from culinarycut.datasets.demo import Demonstration
from culinarycut.datasets.object_frame import half_extents_in_object_frame, to_object_frame


def target_object(resolved_scene: dict, index: int = 0) -> tuple[np.ndarray, float]:
    """The target's resolved pose [m x3, wxyz] and scale."""
    obj = resolved_scene["objects"][index]
    pose = obj["pose"]
    return np.array(list(pose["position"]) + list(pose.get("quaternion", [1, 0, 0, 0])), float), \
        float(obj.get("scale", 1.0))


class DemoRecorder:
    """start(resolved_scene, seed, spec, reset_info); add(observation, info) after every step; result()."""

    def __init__(self, resolved_scene: dict, seed: int, spec: dict, reset_info: dict, control_mode: str):
        self.object_pose, _ = target_object(resolved_scene)
        piece = reset_info["food"]["pieces"][0]
        self.half_extents = half_extents_in_object_frame(self.object_pose[3:], piece["bounds_min"],
                                                         piece["bounds_max"])
        self.resolved_scene = json.loads(json.dumps(resolved_scene))
        self.seed, self.spec, self.control_mode = int(seed), dict(spec), control_mode
        self.time_s: list[float] = []
        self.poses: list[list[float]] = []
        self.contact: list[bool] = []

    def add(self, observation: dict, info: dict) -> None:
        self.time_s.append(float(info["sim_time"]))
        tcp = observation["extra"]["tcp_pose"]
        self.poses.append(to_object_frame(tcp, self.object_pose, self.half_extents).tolist())
        self.contact.append(bool(info.get("food", {}).get("knife_contact", False)))

    def result(self, operator: str = "", rating: str = "") -> Demonstration:
        return Demonstration(spec=self.spec, seed=self.seed, resolved_scene=self.resolved_scene,
                             object_pose=self.object_pose.tolist(), half_extents_m=self.half_extents.tolist(),
                             time_s=self.time_s, relative_pose=self.poses, knife_contact=self.contact,
                             control_mode=self.control_mode, operator=operator, rating=rating)

"""One episode's scene, drawn from its seed alone: the target's position, yaw and scale on the board
and the distractor foods around it (the paper's "novel object positions and scales")."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from culinarycut.bench.suite import Suite, Task, episode_seed
from culinarycut.datasets.object_frame import half_extents_in_object_frame

FOODS = ("banana", "cucumber", "apple", "peach", "melon", "orange", "strawberry")
BOARD_CENTER_XY_M = (0.50, 0.0)  # the cutting board's centre on the table (sim/core/scene_layout.h)
# Distractor slots around the target (dx, dy in m), clear of everything the knife sweeps while it cuts the
# target (knife_reach.py: the blade lies along x, its tip 10 cm ahead of the edge's middle and its handle 21 cm
# behind it, towards the robot, plus a saw stroke): ahead, 28 cm clears a melon given the jitter; behind,
# no slot on the blade's line (a food there would sit at the robot's base); along y, 28 cm clears the
# longest foods end to end.
DISTRACTOR_SLOTS_M = ((0.28, 0.0), (0.0, 0.28), (0.0, -0.28),
                      (0.28, 0.28), (0.28, -0.28), (-0.22, 0.28), (-0.22, -0.28))
CUTTING_EFFECTS = {"mpm": True, "damage": True, "friction": True, "force_sensing": True}


@dataclass(frozen=True)
class EpisodeSpec:
    """What one row of the results is: a suite's task, a trial, its seed and its scene."""

    suite: str
    task: Task
    trial: int
    seed: int
    scene: dict            # SceneSpec in proto-JSON form; the instruction is added at run time
    language: str          # the template split the instruction is drawn from

    @property
    def key(self) -> tuple[str, int]:
        return (self.task.name, self.trial)


def _yaw_quaternion(yaw_rad: float) -> list[float]:
    """(w, x, y, z) of a rotation about world z; the food's default is 90 deg (long axis along y)."""
    half = 0.5 * (math.pi / 2 + yaw_rad)
    return [math.cos(half), 0.0, 0.0, math.sin(half)]


def _food(name: str, xy_m, yaw_rad: float, scale: float, overrides: dict) -> dict:
    food = {"food": name, "scale": scale,
            "pose": {"position": [float(xy_m[0]), float(xy_m[1])], "quaternion": _yaw_quaternion(yaw_rad)}}
    if overrides:
        food["material_overrides"] = dict(overrides)
    return food


def episode_spec(suite: Suite, task: Task, trial: int) -> EpisodeSpec:
    """The episode (suite, task, trial): the same inputs give the same scene on any machine."""
    seed = episode_seed(suite.name, task.seed_name or task.name, trial)
    rng = np.random.Generator(np.random.PCG64(seed))
    randomize = suite.randomize
    jitter = randomize["position_m"]

    def draw_pose():
        offset = rng.uniform(-jitter, jitter, size=2)
        yaw = math.radians(rng.uniform(-randomize["yaw_deg"], randomize["yaw_deg"]))
        scale = float(rng.uniform(*randomize["scale"]))
        return offset, yaw, scale

    offset, yaw, scale = draw_pose()
    target_xy = np.add(BOARD_CENTER_XY_M, offset)
    objects = [_food(task.food, target_xy, yaw, scale, task.material_overrides)]
    others = [f for f in FOODS if f != task.food]
    kinds = rng.choice(others, size=task.distractors, replace=False) if task.distractors else []
    slots = rng.choice(len(DISTRACTOR_SLOTS_M), size=task.distractors, replace=False) if task.distractors else []
    for kind, slot in zip(kinds, slots):
        offset, yaw, scale = draw_pose()
        objects.append(_food(str(kind), target_xy + np.add(DISTRACTOR_SLOTS_M[slot], offset), yaw, scale,
                             task.material_overrides))
    scene = {
        "seed": str(seed),  # proto-JSON writes 64-bit integers as strings
        "quality": task.quality,
        "scene": task.scene,
        "effects": {**CUTTING_EFFECTS, "topology": task.topology},
        "objects": objects,
        "max_episode_steps": task.max_episode_steps,
        "cameras": [dict(camera) for camera in suite.cameras],
    }
    if task.mpm:
        scene["mpm"] = dict(task.mpm)
    if task.safety_limiter:
        scene["effects"]["safety_limiter"] = True
        scene["safety"] = task.safety_spec()
    return EpisodeSpec(suite=suite.name, task=task, trial=trial, seed=seed, scene=scene, language=task.language)


def suite_episodes(suite: Suite) -> list[EpisodeSpec]:
    """Every episode of the suite, task by task, trial by trial."""
    return [episode_spec(suite, task, trial) for task in suite.tasks for trial in range(task.trials)]


def object_boxes(resolved_scene: dict, food: dict | None) -> list[dict]:
    """Each food object's box at rest, as Tasks' ObjectBox takes it (culinarycut.tasks.object_box_to_proto):
    named "<food>_<index>" as the server names it, centred on the world bounding box of its particles in the
    reset observation (`food`: info["food"]), the resolved scene's orientation, and its full side lengths
    along its own axes solved from that bounding box (m). An object without pieces keeps its resolved pose
    and no extent."""
    pieces = (food or {}).get("pieces", [])
    boxes = []
    for index, obj in enumerate(resolved_scene.get("objects", [])):
        pose = obj.get("pose", {})
        quaternion = [float(v) for v in pose.get("quaternion", [])] or [1.0, 0.0, 0.0, 0.0]
        box = {"name": f"{obj.get('food', '')}_{index}", "food": obj.get("food", ""),
               "position": [float(v) for v in pose.get("position", [])], "quaternion": quaternion}
        own = [p for p in pieces if int(p["object"]) == index]
        if own:
            low = np.min([p["bounds_min"] for p in own], axis=0)
            high = np.max([p["bounds_max"] for p in own], axis=0)
            box["position"] = (0.5 * (low + high)).tolist()
            box["extent_m"] = (2.0 * half_extents_in_object_frame(quaternion, low, high)).tolist()
        boxes.append(box)
    return boxes

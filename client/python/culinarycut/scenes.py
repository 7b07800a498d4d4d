"""Ready-made scene specs (plain dicts in SceneSpec's proto-JSON form) for the registered environments,
the example and the benchmarks."""
from __future__ import annotations

from typing import Sequence

CUT_CUCUMBER_INSTRUCTION = "cut the cucumber at 0.3 ratio from the left"
CUTTING_EFFECTS = {"mpm": True, "damage": True, "friction": True, "topology": True, "force_sensing": True}


def cut_cucumber_scene(instruction: str = CUT_CUCUMBER_INSTRUCTION, quality: str = "draft", width: int = 224,
                       height: int = 224, cameras: Sequence[str] = ("front", "left", "right"),
                       max_episode_steps: int = 0) -> dict:
    """One cucumber (its real material preset) on the board with the cutting effects, a task and RGB cameras
    of width x height pixels (default cameras by name); max_episode_steps 0 means no step limit."""
    food = {"food": "cucumber"}
    scene = {
        "quality": quality,
        "effects": dict(CUTTING_EFFECTS),
        "objects": [food],
        "task": {"instruction": instruction},
        "cameras": [{"name": name, "width": width, "height": height} for name in cameras],
    }
    if max_episode_steps:
        scene["max_episode_steps"] = max_episode_steps
    return scene


__all__ = ["cut_cucumber_scene", "CUT_CUCUMBER_INSTRUCTION", "CUTTING_EFFECTS"]

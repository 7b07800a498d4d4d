"""The smoke pass's tiny cases: the same code as a full run on the cheapest cut the engine makes, in seconds."""
from __future__ import annotations

import copy
from pathlib import Path

# The smallest food: the oracle's middle cut of it at draft takes about 2 s, a cucumber's 20 s.
FOOD = "strawberry"
# Coarser than any preset: a cut then takes a fraction of a second (and may leave the food whole, which the smoke
# pass does not judge).
COARSE_MPM = {"dx": 0.008, "particles_per_cell": 2, "cfl": 0.8}
IMAGE_SIZE = 32  # px: cameras are rendered, cheaply


def food_scene(scene: dict, coarse: bool = False) -> dict:
    """`scene` (a SceneSpec dict with one food and a task) with the strawberry instead, cut in the middle; with
    `coarse`, at COARSE_MPM."""
    scene = copy.deepcopy(scene)
    scene.update(objects=[{**scene["objects"][0], "food": FOOD}], task={"cut_state": "middle"})
    for camera in scene.get("cameras", []):
        camera.update(width=IMAGE_SIZE, height=IMAGE_SIZE)
    if coarse:
        scene["mpm"] = dict(COARSE_MPM)
    return scene


def suite(folder: Path, style: str = "normal") -> Path:
    """A one-episode suite (the strawberry's middle cut at draft) as a TOML file for `culinarycut bench run`."""
    path = folder / "quick.toml"
    path.write_text('name = "quick"\n'
                    'description = "The benchmark harness\'s smoke pass: one strawberry middle cut at draft."\n'
                    'trials = 1\nmax_episode_steps = 400\nquality = "draft"\n\n'
                    f'[[tasks]]\nfood = "{FOOD}"\nstyle = "{style}"\nstate = "middle"\n')
    return path

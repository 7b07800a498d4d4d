"""The Gymnasium ids of CulinaryCut's environments, registered when culinarycut is imported (gymnasium 1.x
has no plugin entry points), so `gymnasium.make("CulinaryCut/Robot-v0", address=...)` works after
`import culinarycut`, and `gymnasium.make("culinarycut:CulinaryCut/Robot-v0", ...)` without it.

Every keyword of CulinaryCutEnv can be given to make(): address, scene (replaces the registered one),
control_mode, client, render_mode.
"""
from __future__ import annotations

from culinarycut.gymnasium_support import gymnasium
from culinarycut.scenes import cut_cucumber_scene

ENTRY_POINT = "culinarycut.env:CulinaryCutEnv"
CUT_EPISODE_STEPS = 200  # 10 s at 20 Hz; the scripted oracle's cut takes about 111 steps

# id -> the keyword arguments it stands for.
ENVIRONMENTS = {
    # The Panda with its knife above the board: no food, no cameras.
    "CulinaryCut/Robot-v0": {},
    # The example's task: cut a (softened) cucumber at 0.3 from the left, seen by the front camera at 224 x 224.
    "CulinaryCut/CutCucumber-v0": {"scene": cut_cucumber_scene(cameras=("front",),
                                                               max_episode_steps=CUT_EPISODE_STEPS)},
}


def register_environments() -> None:
    """Registers the ids with gymnasium (once; nothing without gymnasium)."""
    if gymnasium is None:
        return
    for env_id, kwargs in ENVIRONMENTS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(id=env_id, entry_point=ENTRY_POINT, kwargs=kwargs)


__all__ = ["ENVIRONMENTS", "register_environments"]

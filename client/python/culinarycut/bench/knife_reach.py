"""What the knife sweeps on the table while it cuts a food the way the scripted oracle does, and whether a
distractor lies in it: the knife is longer behind its cutting edge than ahead of it (the handle), so a food
placed beside the target along the blade can be pressed by the handle while the target is cut.

Written here rather than asked of the server: a suite's scenes are drawn on the client from the seed alone,
before any server is reached. The sizes below are the server's (tested against a live reset)."""
from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from culinarycut.datasets.object_frame import quat_to_matrix

# The knife in its TCP frame (docs/robot.md; sim/mpm/colliders.h, KnifeGeometry): x along the blade.
KNIFE_AHEAD_M = 0.10      # the tip, half the 20 cm blade
KNIFE_BEHIND_M = 0.21     # the handle's end: its 11 cm box centred 15.5 cm behind the TCP
KNIFE_HALF_WIDTH_M = 0.01  # the handle's 20 mm; the blade is 2 mm
SAW_AMPLITUDE_MAX_M = 0.025  # the longest saw stroke's half-length along the blade (the cut planner's range)

# Each food's footprint at scale 1: half its length along its own x (its long axis) and half its width
# across it (m), from the food shapes (sim/mpm/food_shapes.cc; the banana's width holds its bow).
FOOD_HALF_FOOTPRINT_M = {
    "cucumber": (0.10, 0.020),
    "banana": (0.09, 0.034),
    "apple": (0.04, 0.040),
    "peach": (0.035, 0.035),
    "orange": (0.0375, 0.0375),
    "melon": (0.10, 0.075),
    "strawberry": (0.0175, 0.0125),
}
# The cut positions the suites ask for: fractions 0.1-0.9 of the length, from either end.
CUT_FRACTIONS = (0.1, 0.9)


def _long_axis_xy(quaternion: Sequence[float]) -> np.ndarray:
    """Where a food's long axis (its own x) points on the table: a unit vector, from its (w, x, y, z) pose."""
    axis = quat_to_matrix(quaternion)[:2, 0]
    return axis / np.linalg.norm(axis)


def _rectangle(center_xy, u: np.ndarray, along: tuple[float, float], across: tuple[float, float]) -> np.ndarray:
    """The 4 corners (m) of a rectangle on the table: `along` and `across` are its (low, high) extents from
    `center_xy` along the unit vector `u` and across it."""
    v = np.array([-u[1], u[0]])
    c = np.asarray(center_xy, dtype=float)
    corners = ((along[0], across[0]), (along[0], across[1]), (along[1], across[1]), (along[1], across[0]))
    return np.array([c + a * u + b * v for a, b in corners])


def _separated(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two convex polygons on the table do not overlap (the separating axis test: a few lines, where a
    geometry library would be a dependency for one question)."""
    for polygon in (a, b):
        for i in range(len(polygon)):
            edge = polygon[(i + 1) % len(polygon)] - polygon[i]
            normal = np.array([-edge[1], edge[0]])
            pa, pb = a @ normal, b @ normal
            if pa.max() < pb.min() or pb.max() < pa.min():
                return True
    return False


def food_footprint(food: dict) -> np.ndarray:
    """A scene object's footprint on the table (its rotated box's corners, m)."""
    half_length, half_width = FOOD_HALF_FOOTPRINT_M[food["food"]]
    scale = float(food.get("scale", 1.0))
    position = food["pose"]["position"]
    return _rectangle(position[:2], _long_axis_xy(food["pose"]["quaternion"]),
                      (-scale * half_length, scale * half_length), (-scale * half_width, scale * half_width))


def knife_sweep(target: dict, fractions: tuple[float, float] = CUT_FRACTIONS) -> np.ndarray:
    """What the knife covers on the table (corners, m) cutting `target` across its long axis anywhere from
    `fractions[0]` to `fractions[1]` of its length from either end, the blade square to the food, its handle
    towards the robot (world -x) and swinging the longest saw stroke along the blade."""
    half_length, _ = FOOD_HALF_FOOTPRINT_M[target["food"]]
    scale = float(target.get("scale", 1.0))
    reach_m = scale * half_length * (1.0 - 2.0 * min(fractions[0], 1.0 - fractions[1]))  # TCP from the centre
    long_axis = _long_axis_xy(target["pose"]["quaternion"])
    tip = np.array([-long_axis[1], long_axis[0]])  # the blade lies square to the food's long axis
    if tip[0] < 0.0:  # the tip points away from the robot (world +x), the handle towards it
        tip = -tip
    position = target["pose"]["position"]
    along = (-KNIFE_BEHIND_M - SAW_AMPLITUDE_MAX_M, KNIFE_AHEAD_M + SAW_AMPLITUDE_MAX_M)
    across = (-reach_m - KNIFE_HALF_WIDTH_M, reach_m + KNIFE_HALF_WIDTH_M)
    return _rectangle(position[:2], tip, along, across)


def distractors_in_reach(objects: Iterable[dict]) -> list[int]:
    """Indices of the scene's distractors (every object after the first, the target) that the knife can
    touch while it cuts the target anywhere the suites ask."""
    objects = list(objects)
    sweep = knife_sweep(objects[0])
    return [i for i, food in enumerate(objects[1:], start=1) if not _separated(sweep, food_footprint(food))]

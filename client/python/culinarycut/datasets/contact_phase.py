"""The contact phase of a step a demonstration drives, read from the knife's state relative to the food
(the planner reports its own): the planner's names, with "cut" from the drawn cutting height above the
food's top down through the food, as the planner's cut segment runs."""
from __future__ import annotations

import numpy as np

STILL_M_S = 0.005          # TCP speeds below this are the controller's noise, not motion
CUT_HEIGHT_MARGIN_M = 0.002  # the tracked knife lags its target by about this at the cut's start


def food_top_z_m(info: dict) -> float | None:
    """The highest point of the food (m, world z); None without food."""
    pieces = info.get("food", {}).get("pieces", [])
    return max(float(piece["bounds_max"][2]) for piece in pieces) if pieces else None


class DemoContactPhase:
    """phase(observation, info) for each step, in order: "cut" in contact with the food or moving down
    within the cut height above its top; "descend" moving mostly down above that; "approach" before the
    first cut and "retreat" (rising or still) or "transfer" (moving sideways) after one."""

    def __init__(self, cut_height_m: float):
        self.cut_height_m = cut_height_m
        self.has_cut = False

    def phase(self, observation: dict, info: dict) -> str:
        if info.get("food", {}).get("knife_contact", False):
            self.has_cut = True
            return "cut"
        velocity = np.asarray(observation["extra"]["tcp_velocity"][:3], float)  # m/s
        sideways_m_s, down_m_s = float(np.hypot(velocity[0], velocity[1])), -float(velocity[2])
        if down_m_s > STILL_M_S and down_m_s >= sideways_m_s:
            top_z = food_top_z_m(info)
            height_m = float(observation["extra"]["tcp_pose"][2]) - top_z if top_z is not None else np.inf
            return "cut" if height_m <= self.cut_height_m + CUT_HEIGHT_MARGIN_M else "descend"
        if not self.has_cut:
            return "approach"
        return "transfer" if sideways_m_s > max(STILL_M_S, abs(velocity[2])) else "retreat"

"""v_safe = max v with F_hat(v, m) <= F_max, found by bisection exactly as the server's limiter does
(sim/safety/safe_speed.cc): the top of the speed range if it is safe; else bisection on [low, high] of the
range, or on [0, low] below it, where the out-of-range factor applies; 0 if even a still knife is too much."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from culinarycut.safety.asset import ForceModel
from culinarycut.safety.posynomial import INPUTS, SPEED

TOLERANCE_M_S = 1e-4  # the server's kSafeSpeedToleranceMS


@dataclass(frozen=True)
class SafeSpeed:
    v_safe_m_s: float
    predicted_force_n: float  # F_hat(v_safe), factor included
    out_of_range: bool


def material_inputs(speed_m_s: float, youngs_mpa: float, yield_kpa: float, toughness_j_m2: float,
                    edge_length_m: float) -> np.ndarray:
    x = np.empty(len(INPUTS))
    x[:] = (speed_m_s, youngs_mpa, yield_kpa, toughness_j_m2, edge_length_m)
    return x


def safe_speed(model: ForceModel, x: np.ndarray, max_force_n: float, tolerance_m_s: float = TOLERANCE_M_S) -> SafeSpeed:
    """x: the inputs in INPUTS order (its speed is ignored)."""
    low_range, high_range = model.ranges[SPEED]

    def at(speed_m_s: float) -> tuple[float, bool]:
        point = np.array(x, dtype=float)
        point[SPEED] = speed_m_s
        return model.predict(point)

    def feasible(speed_m_s: float) -> bool:
        return at(speed_m_s)[0] <= max_force_n

    def result(speed_m_s: float) -> SafeSpeed:
        return SafeSpeed(speed_m_s, *at(speed_m_s))

    if feasible(high_range):
        return result(high_range)
    low, high = 0.0, low_range  # feasible at low, not at high
    if feasible(low_range):
        low, high = low_range, high_range
    elif not feasible(0.0):
        return result(0.0)
    while high - low > tolerance_m_s:
        middle = 0.5 * (low + high)
        if feasible(middle):
            low = middle
        else:
            high = middle
    return result(low)

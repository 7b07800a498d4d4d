"""A demonstration's path fitted to another object (actors.retarget): wherever the drawn cutting height
puts the start of the cut, the knife never moves faster than the drawn cutting speed on its way in."""
from __future__ import annotations

import numpy as np
import pytest
from culinarycut.datasets.actors import resample_path, retarget
from culinarycut.datasets.demo import Demonstration

STEP_S = 0.05            # the demonstration's sample period (20 Hz)
DEMO_SPEED_M_S = 0.03    # it moves at this speed everywhere
DEMO_HALF_M = np.array([0.08, 0.02, 0.02])
TOLERANCE = 1.02         # 2 %: rounding of the piecewise-linear path


def _constant_speed_demo() -> Demonstration:
    """Slides above the object 2 mm over its top, cuts straight down to below its bottom, rises back."""
    step = DEMO_SPEED_M_S * STEP_S
    hover_z = DEMO_HALF_M[2] + 0.002
    points = [np.array([-0.04 + i * step, 0.0, hover_z]) for i in range(10)]
    while points[-1][2] > -DEMO_HALF_M[2] - 0.005:
        points.append(points[-1] - [0, 0, step])
    while points[-1][2] < hover_z + 0.02:
        points.append(points[-1] + [0, 0, step])
    contact = [bool(abs(p[2]) < DEMO_HALF_M[2]) for p in points]
    relative = [list(p / DEMO_HALF_M) + [1.0, 0.0, 0.0, 0.0] for p in points]
    return Demonstration(spec={}, seed=0, resolved_scene={}, object_pose=[0, 0, 0, 1, 0, 0, 0],
                         half_extents_m=DEMO_HALF_M.tolist(), time_s=[i * STEP_S for i in range(len(points))],
                         relative_pose=relative, knife_contact=contact)


def _speeds_m_s(time_s: np.ndarray, path: np.ndarray) -> np.ndarray:
    return np.linalg.norm(np.diff(path[:, :3], axis=0), axis=1) / np.diff(time_s)


@pytest.mark.parametrize("cut_height_m, cut_speed_m_s, scale", [(0.01, 0.02, 1.0), (0.02, 0.05, 1.15),
                                                                 (0.03, 0.035, 0.85)])
def test_retargeted_knife_never_outruns_the_cutting_speed(cut_height_m, cut_speed_m_s, scale):
    demo = _constant_speed_demo()
    object_pose = np.array([0.5, 0.1, 0.03, np.cos(0.1), 0.0, 0.0, np.sin(0.1)])  # moved and yawed
    half_m = DEMO_HALF_M * scale
    time_s, path = retarget(demo, object_pose, half_m, cut_height_m, cut_speed_m_s)
    assert np.all(np.diff(time_s) > 0)
    assert _speeds_m_s(time_s, path).max() <= cut_speed_m_s * TOLERANCE
    # and so does the follower, which samples the path once per 50 ms control step
    at_s = np.arange(0.0, time_s[-1] + STEP_S, STEP_S)
    followed = np.array([resample_path(time_s, path, t) for t in at_s])
    assert _speeds_m_s(at_s, followed).max() <= cut_speed_m_s * TOLERANCE
    # the cut starts at the drawn height above the new object's top, and still goes through it
    top_z = object_pose[2] + half_m[2]
    entry = int(np.argmax(demo.knife_contact))  # the vertical descent sits just before the first contact
    assert path[entry - 1, 2] - top_z == pytest.approx(cut_height_m, abs=1e-9)
    assert path[:, 2].min() < object_pose[2] - half_m[2]


def test_a_non_positive_cutting_speed_is_refused():
    with pytest.raises(ValueError, match="cut_speed_m_s"):
        retarget(_constant_speed_demo(), np.array([0, 0, 0, 1.0, 0, 0, 0]), DEMO_HALF_M, 0.02, 0.0)

"""A recorded cut as the style generator sees it: per control step the action in the unit the learned
policy emits, and whether the knife touched the food; its contact segments; resampling to another length.

The unit: the learned policy answers LIBERO's OSC_POSE deltas (features.py, serve.py): the commanded TCP
target relative to the measured TCP, position / 0.05 m and axis-angle rotation / 0.5 rad, clipped to
[-1, 1]. A recording in pd_ee_pose_quat (the scripted oracle's targets) or pd_ee_delta_pose is converted
with the function the policy's trainer uses (features.osc_actions), so the generator's inputs and outputs
are the same numbers the policy's chunks hold."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from culinarycut_learning.features import ACTION_DIMS, osc_actions


@dataclass
class Trajectory:
    style: str
    actions: np.ndarray        # (T, 6) OSC_POSE deltas (1 = 0.05 m, 0.5 rad)
    contact: np.ndarray        # (T,) bool: the knife touched the food when the step's action was chosen
    seed: int = 0

    def __post_init__(self):
        self.actions = np.asarray(self.actions, dtype=np.float32).reshape(-1, ACTION_DIMS)
        self.contact = np.asarray(self.contact, dtype=bool).reshape(-1)
        if len(self.actions) != len(self.contact):
            raise ValueError(f"{len(self.actions)} actions but {len(self.contact)} contact flags")

    @classmethod
    def from_recording(cls, style: str, actions: np.ndarray, tcp_poses: np.ndarray, contact: np.ndarray,
                       control_mode: str, seed: int = 0) -> "Trajectory":
        """From recorded actions in `control_mode`, the measured TCP poses before each step ([m x3,
        quaternion wxyz]) and the contact flags."""
        return cls(style, osc_actions(actions, tcp_poses, control_mode), contact, seed)


def contact_segments(contact: np.ndarray, max_gap: int = 2, min_steps: int = 3) -> list[tuple[int, int]]:
    """[start, end) of each run of contact steps; runs apart by at most `max_gap` steps without contact are one
    segment (the contact flag flickers as the blade slides), runs shorter than `min_steps` are dropped (a
    graze on the way down is no cut)."""
    steps = np.flatnonzero(np.asarray(contact, dtype=bool))
    if not len(steps):
        return []
    segments, start, last = [], int(steps[0]), int(steps[0])
    for step in steps[1:]:
        if step - last > max_gap + 1:
            segments.append((start, last + 1))
            start = int(step)
        last = int(step)
    segments.append((start, last + 1))
    return [(a, b) for a, b in segments if b - a >= min_steps]


def resample(values: np.ndarray, length: int) -> np.ndarray:
    """(T, D) -> (length, D): linear interpolation at `length` evenly spaced points of normalised time
    [0, 1] (first and last steps kept); a single step is repeated."""
    values = np.asarray(values, dtype=np.float64)
    if length < 1:
        raise ValueError(f"length must be at least 1, got {length}")
    if len(values) == 1:
        return np.repeat(values, length, axis=0).astype(np.float32)
    source = np.linspace(0.0, 1.0, len(values))
    target = np.linspace(0.0, 1.0, length)
    columns = [np.interp(target, source, values[:, d]) for d in range(values.shape[1])]
    return np.stack(columns, axis=1).astype(np.float32)

"""Policies that give a suite's floor: one that does nothing and one that moves at random."""
from __future__ import annotations

import numpy as np

from culinarycut.policies.base import Policy


class NoOpPolicy(Policy):
    """Holds the knife still: the success rate of doing nothing (zero, unless a task is already done)."""

    name = "noop"
    version = "1"
    control_mode = "pd_ee_delta_pose"

    def act(self, observation):
        return self.control_mode, np.zeros(6)


class RandomPolicy(Policy):
    """Uniform normalised end-effector deltas, seeded from the episode's seed (so runs repeat)."""

    name = "random"
    version = "1"
    control_mode = "pd_ee_delta_pose"

    def __init__(self, scale: float = 1.0):
        super().__init__()
        if not 0 < scale <= 1:
            raise ValueError(f"policy random: option scale must be in (0, 1], got {scale}")
        self.scale = float(scale)
        self.rng = np.random.Generator(np.random.PCG64(0))

    def reset(self, instruction, info):
        super().reset(instruction, info)
        self.rng = np.random.Generator(np.random.PCG64(int(info["seed"])))

    def act(self, observation):
        return self.control_mode, self.scale * self.rng.uniform(-1.0, 1.0, size=6)

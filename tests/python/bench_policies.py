"""Policies that misbehave, for the benchmark runner's tests (loaded as bench_policies:Class)."""
from __future__ import annotations

import os
import time

import numpy as np

from culinarycut.policies import Policy


class RaisingPolicy(Policy):
    name = "raising"
    control_mode = "pd_ee_delta_pose"

    def act(self, observation):
        if observation["agent"]["qpos"].size and getattr(self, "_steps", 0) >= 2:
            raise RuntimeError("the model ran out of ideas")
        self._steps = getattr(self, "_steps", 0) + 1
        return self.control_mode, np.zeros(6)


class SlowPolicy(Policy):
    name = "slow"
    control_mode = "pd_ee_delta_pose"

    def act(self, observation):
        time.sleep(5.0)
        return self.control_mode, np.zeros(6)


class CamerasBugPolicy(Policy):
    """A policy with a bug the episode does not record as the policy's error: its camera list raises a
    ValueError on the worker, so the episode's task fails."""
    name = "cameras-bug"
    control_mode = "pd_ee_delta_pose"

    @property
    def cameras(self):
        raise ValueError("camera 'wrist' has no resolution")

    def act(self, observation):
        return self.control_mode, np.zeros(6)


class WorkerKillingPolicy(Policy):
    """Ends the process it runs in at its first action, as the kernel's OOM killer would a Dask worker."""
    name = "worker-killing"
    control_mode = "pd_ee_delta_pose"

    def act(self, observation):
        os._exit(1)

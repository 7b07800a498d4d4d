"""The policy interface the benchmark runner drives: reset with the instruction, then one action per step.

A policy is a small class; the runner makes one per episode from its registered name and options:

    class MyPolicy(Policy):
        name = "my-policy"
        version = "1"
        control_mode = "pd_ee_delta_pose"      # the mode its actions are in (ManiSkill's names)
        cameras = ({"name": "front"},)          # what it needs to see; added to the episode's scene

        def reset(self, instruction, info): ...
        def act(self, observation): return self.control_mode, action

`observation` is CulinaryCutEnv's (ManiSkill's layout); `info` at reset holds the seed, the episode's
`session` (client and session id, for policies that plan on the server such as the oracle), the
scene's `objects` (as the scene gives them), `object_boxes` (each food's box at rest: name, food, position,
quaternion, extent_m; world frame, m) and `control_frequency_hz`. A policy that is done early sets
`finished`; the episode then ends. A policy that plans on the server sets `needs_session`: served over the
policy protocol (culinarycut.policy_server), only such a policy is given the session and its token. Optional: `close()` (called when the episode ends), `latency_summary()` (a dict stored
with the episode as `policy_latency`) and `preflight()` (called once on a fresh instance before a run's
first episode; raising stops the run, e.g. a model server that does not answer), as the model adapters in
policies/ have.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

# Values per action of each control mode (docs/robot.md: ManiSkill's panda_stick modes, no gripper).
ACTION_DIMS = {"pd_joint_pos": 7, "pd_joint_delta_pos": 7, "pd_ee_delta_pos": 3, "pd_ee_delta_pose": 6,
               "pd_ee_pose": 6, "pd_ee_pose_quat": 7}


@dataclass(frozen=True)
class EpisodeSession:
    """The server session an episode runs in (for policies that call the server themselves)."""

    client: Any        # culinarycut.client.Client
    session_id: str


class Policy:
    name = "policy"
    version = "0"
    control_mode = "pd_ee_delta_pose"
    cameras: tuple = ()
    needs_session = False   # it calls the server itself with info["session"]

    def __init__(self, **options):
        if options:
            raise ValueError(f"policy {self.name!r} takes no options; got {sorted(options)}")
        self.finished = False

    def reset(self, instruction: str, info: dict[str, Any]) -> None:
        self.finished = False

    def act(self, observation: dict[str, Any]) -> tuple[str, np.ndarray]:
        raise NotImplementedError

"""The scripted oracle as a benchmark policy: it reads the instruction, plans on the server and follows the plan."""
from __future__ import annotations

from culinarycut.policies.base import Policy
from culinarycut.policies.scripted_oracle import ScriptedOracle


class OraclePolicy(Policy):
    """The instruction is parsed and the cut planned by the server's oracle (Tasks.StartOracle) from the
    objects' boxes; it finishes when its plan ends."""

    name = "oracle"
    version = "1"
    control_mode = "pd_ee_pose_quat"
    needs_session = True  # it plans on the server, in the episode's session

    def __init__(self, control_mode: str = "pd_ee_pose_quat"):
        super().__init__()
        self.control_mode = control_mode
        self._oracle: ScriptedOracle | None = None

    def reset(self, instruction, info):
        super().reset(instruction, info)
        session = info["session"]
        self._oracle = ScriptedOracle(session.client, session.session_id)
        self._oracle.reset(instruction, control_mode=self.control_mode, seed=int(info["seed"]))

    def act(self, observation):
        mode, values = self._oracle.act(observation)
        self.finished = self._oracle.finished
        return mode, values

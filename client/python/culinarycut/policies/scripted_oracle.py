"""The scripted oracle: instruction + object boxes -> a planned cut, executed step by step.

Parsing, planning and the conversion to actions run on the server (Tasks.StartOracle and
Tasks.OracleAction, the C++ ScriptedOracle), so Python and C++ users get the same behaviour.
"""
from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from culinarycut.client import Client
from culinarycut.tasks import TaskClient


class ScriptedOracle:
    """Plans on `reset`, then `act()` gives the action for the session's next Step.

    Example::

        oracle = ScriptedOracle(client, session_id)
        plan = oracle.reset("cut the cucumber at 0.3 ratio from the left", objects=[cucumber_box])
        while not oracle.finished:
            mode, values = oracle.act()
            client.step(session_id, mode, values)
    """

    def __init__(self, client: Client, session_id: str):
        self.tasks: TaskClient = client.tasks
        self.session_id = session_id
        self.plan: dict[str, Any] | None = None
        self.finished = False
        self.phase = ""

    def reset(self, instruction: str | None = None, *, objects: Sequence = (), spec=None,
              target_name: str = "", control_mode: str = "", options=None,
              seed: int | None = None) -> dict[str, Any]:
        """Plan a new cut from the robot's current state; returns the plan (see tasks.plan_to_dict).
        Without objects the oracle sees the scene's own food objects; without instruction and spec
        it does the scene's task (SceneSpec.task)."""
        self.plan = self.tasks.start_oracle(self.session_id, objects, instruction=instruction, spec=spec,
                                            target_name=target_name, control_mode=control_mode,
                                            options=options, seed=seed)
        self.finished = False
        self.phase = ""
        return self.plan

    def act(self, observation=None) -> tuple[str, np.ndarray]:
        """(control_mode, values) for the next Step. The server reads the robot's state itself, so
        `observation` is accepted for the usual policy signature and not used."""
        del observation
        response = self.tasks.oracle_action(self.session_id)
        self.finished = response.finished
        self.phase = response.phase
        return response.action.control_mode, np.asarray(response.action.values, dtype=np.float64)

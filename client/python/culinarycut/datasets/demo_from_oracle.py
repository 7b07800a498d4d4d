"""A demonstration recorded from the planner's own cut (for tests and for seeding a dataset when no
person has demonstrated a style yet): the same recorder teleoperation uses, driven by the oracle."""
from __future__ import annotations

from pathlib import Path

from google.protobuf import json_format

from culinarycut.client import Client
from culinarycut.datasets.demo import Demonstration, save_demonstration
from culinarycut.datasets.demo_recorder import DemoRecorder
from culinarycut.env import CulinaryCutEnv
from culinarycut.policies.scripted_oracle import ScriptedOracle

CONTROL_MODE = "pd_ee_pose_quat"


def record_oracle_demonstration(client: Client, scene: dict, spec: dict, seed: int, path: Path | None = None,
                                max_steps: int = 600) -> Demonstration:
    with CulinaryCutEnv(client=client, scene=scene, control_mode=CONTROL_MODE) as env:
        resolved = json_format.MessageToDict(env.handshake.resolved_scene, preserving_proto_field_name=True)
        observation, info = env.reset(seed=seed)
        recorder = DemoRecorder(resolved, seed, spec, info, CONTROL_MODE)
        recorder.add(observation, info)
        oracle = ScriptedOracle(client, env.session_id)
        oracle.reset(spec=spec, control_mode=CONTROL_MODE, seed=seed)
        for _ in range(max_steps):
            if oracle.finished:
                break
            _, action = oracle.act()
            observation, _, _, _, info = env.step(action)
            recorder.add(observation, info)
        demo = recorder.result(operator="oracle", rating="good" if info.get("success") else "bad")
    if path is not None:
        save_demonstration(demo, path)
    return demo

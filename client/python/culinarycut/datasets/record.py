"""One generated episode through the full simulator (MPM, cameras, wrist force): the job's scene, its
actor stepped to the end, every step recorded; kept only when the task scores a success, otherwise
the reason is returned."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from google.protobuf import json_format

from culinarycut.client import Client
from culinarycut.datasets.actors import DemoActor, PlannerActor
from culinarycut.datasets.demo import load_demonstration
from culinarycut.datasets.jobs import DatasetConfig, EpisodeJob, planner_options
from culinarycut.env import CulinaryCutEnv

PROPRIO_KEYS = ("qpos", "qvel")                                   # agent
EXTRA_KEYS = ("tcp_pose", "tcp_velocity", "wrist_wrench")         # extra


@dataclass
class RecordedEpisode:
    job: EpisodeJob
    success: bool
    reason: str                      # "success" or why the episode is not kept
    meta: dict[str, Any]             # instructions, cut spec, resolved scene, seed, control mode ...
    steps: dict[str, np.ndarray] = field(default_factory=dict)   # name -> (T, ...) array


def _observation_arrays(observation: dict) -> dict[str, np.ndarray]:
    arrays = {f"obs/{k}": observation["agent"][k] for k in PROPRIO_KEYS}
    arrays.update({f"obs/{k}": observation["extra"][k] for k in EXTRA_KEYS})
    for camera, data in observation.get("sensor_data", {}).items():
        arrays[f"obs/{camera}_rgb"] = data["rgb"]
    return arrays


def record_episode(job: EpisodeJob, config: DatasetConfig, client: Client) -> RecordedEpisode:
    instructions = client.tasks.generate_instructions(job.spec, seed=job.seed, count=config.instructions_per_episode,
                                                      split="train")
    paraphrases = []
    if config.paraphrase_endpoint:
        from culinarycut.paraphrase import paraphrase
        paraphrases, _ = paraphrase(client.tasks, instructions, config.paraphrase_endpoint, config.paraphrase_model)
    scene = {**job.scene, "task": {"instruction": instructions[0]}}
    columns: dict[str, list] = {}
    with CulinaryCutEnv(client=client, scene=scene, control_mode=config.control_mode) as env:
        resolved = json_format.MessageToDict(env.handshake.resolved_scene, preserving_proto_field_name=True)
        observation, info = env.reset(seed=job.seed)
        if job.source == "planner":
            actor = PlannerActor(client, env.session_id, job.spec, planner_options(job.spec, job.variation),
                                 job.seed, config.control_mode)
        else:
            if config.control_mode != DemoActor.control_mode:
                raise ValueError(f"demonstrations replay in {DemoActor.control_mode}; the dataset records "
                                 f"{config.control_mode}")
            control_hz = resolved["robot"]["control_frequency_hz"]
            actor = DemoActor(load_demonstration(job.source), resolved, info, job.variation, 1.0 / control_hz)
        reason, info_end = "step_limit", info
        for _ in range(config.max_episode_steps):
            if actor.finished:
                reason = "actor_finished"
                break
            action, phase = actor.act(observation, info)
            for name, value in _observation_arrays(observation).items():
                columns.setdefault(name, []).append(value)
            contact = bool(info.get("food", {}).get("knife_contact", False))
            observation, reward, terminated, truncated, info = env.step(action)
            for name, value in (("actions", action), ("rewards", reward), ("phase", phase),
                                ("knife_contact", contact), ("sim_time_s", info["sim_time"])):
                columns.setdefault(name, []).append(value)
            info_end = info
            if info["fail"]:
                reason = "task_failed"
                break
            if truncated:
                reason = "truncated"
                break
    score = info_end.get("task", {})
    success = bool(info_end.get("success", False))
    if success:
        reason = "success"
    elif reason == "actor_finished":
        reason = "not_successful"
    steps = {name: np.asarray(values) for name, values in columns.items()}
    if steps:
        steps["dones"] = np.zeros(len(steps["rewards"]), dtype=np.uint8)
        steps["dones"][-1] = 1
    meta = {"key": job.key, "seed": job.seed, "source": job.source, "cut_spec": job.spec,
            "variation": job.variation, "instructions": instructions + paraphrases,
            "paraphrases": len(paraphrases), "resolved_scene": resolved,
            "control_mode": config.control_mode, "score_summary": score.get("summary", ""),
            "pieces": len(info_end.get("food", {}).get("pieces", []))}
    return RecordedEpisode(job=job, success=success, reason=reason if success else
                           f"{reason}: {score.get('summary', '')}".rstrip(": "), meta=meta, steps=steps)

"""One episode of the scripted oracle on a scene's own task, through CulinaryCutEnv, recorded as a trace
(for the example cut and the episode benchmark)."""
from __future__ import annotations

import time

from culinarycut.client import Client
from culinarycut.env import CulinaryCutEnv
from culinarycut.policies.scripted_oracle import ScriptedOracle


def run_oracle_episode(client: Client, scene: dict, seed: int = 0, on_step=None, max_steps: int = 2000,
                       max_wall_s: float = float("inf")) -> dict:
    """Resets a session of `scene`, runs the scene task's oracle until its plan ends (or max_steps /
    max_wall_s; then "complete" is false), and returns the trace: per step the sim time (s), wrist
    force (N, flange frame), knife height (m), phase, reward and client wall time (s); the final score;
    per-stage server wall time (s). `on_step(step, obs, info)` sees every observation (e.g. for video frames)."""
    with CulinaryCutEnv(client=client, scene=scene) as env:
        started = time.perf_counter()
        observation, info = env.reset(seed=seed)
        if on_step:
            on_step(0, observation, info)
        oracle = ScriptedOracle(client, env.session_id)
        oracle.reset()  # the scene's task
        trace = {"time_s": [], "wrist_force_n": [], "tcp_z_m": [], "phase": [], "reward": [], "step_wall_s": [],
                 "first_contact_step": None, "terminated_step": None}
        step = 0
        while not oracle.finished and step < max_steps and time.perf_counter() - started < max_wall_s:
            step_started = time.perf_counter()
            _, values = oracle.act()
            observation, reward, terminated, truncated, info = env.step(values)
            trace["step_wall_s"].append(time.perf_counter() - step_started)
            step += 1
            trace["time_s"].append(info["sim_time"])
            trace["wrist_force_n"].append(observation["extra"]["wrist_wrench"][:3].tolist())
            trace["tcp_z_m"].append(float(observation["extra"]["tcp_pose"][2]))  # the knife edge's height
            trace["phase"].append(oracle.phase)
            trace["reward"].append(reward)
            if info["first_contact"]:
                trace["first_contact_step"] = step
            if terminated and trace["terminated_step"] is None:
                trace["terminated_step"] = step
            if on_step:
                on_step(step, observation, info)
        trace["client_wall_s"] = time.perf_counter() - started
        trace["steps"] = step
        trace["complete"] = oracle.finished
        trace["instruction"] = info.get("instruction", env.handshake.resolved_scene.task.instruction)
        trace["score"] = info.get("task", {})
        trace["success"] = bool(info.get("success", False))
        trace["pieces"] = len(info.get("food", {}).get("pieces", []))
        stats = client.session_stats(env.session_id)
        trace["stage_wall_s"] = dict(stats.stage_wall_time_s)
        trace["mpm_particles"] = int(stats.mpm_particles)
        trace["mpm_substeps"] = int(stats.mpm_substeps)
        trace["resolution"] = {"dx_m": stats.mpm_dx, "particles_per_cell": stats.mpm_particles_per_cell,
                               "cfl": stats.mpm_cfl, "mass_scaling": env.handshake.resolved_scene.mpm.mass_scaling}
    return trace

"""One benchmark episode on one server: a session of the episode's scene, the policy stepped until the
task is done, fails, runs out of steps or the policy finishes; the outcome as one results row."""
from __future__ import annotations

import concurrent.futures
import json
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from google.protobuf import json_format

from culinarycut.bench.episode_scene import EpisodeSpec, object_boxes
from culinarycut.bench.style_signature import along_blade_m, blade_pitch_deg, signature
from culinarycut.bench.suite import ALL_GUARDS
from culinarycut.client import Client
from culinarycut.env import CulinaryCutEnv
from culinarycut.errors import CulinaryCutError, Unavailable
from culinarycut.policies.base import EpisodeSession, Policy
from culinarycut.policies.grpc_policy import PolicyServerError
from culinarycut.policies.registry import make_policy

DEFAULT_MAX_FORCE_N = 100.0  # the server's F_max when the settings give none (docs/safety.md)

# --record-failures films the default front view; a policy that sees "front" itself shares its images.
RECORD_CAMERA = {"name": "front", "width": 160, "height": 120, "channels": ["rgb"]}


class ServerLost(Exception):
    """The server stopped answering during the episode: run it again elsewhere."""


@dataclass
class EpisodeOptions:
    policy: str
    policy_options: dict = field(default_factory=dict)
    act_timeout_s: float = 60.0       # a policy that takes longer for one action is a policy_error
    record_video: bool = False        # frames of the "record" camera, kept for failed episodes
    rpc_timeout_s: float = 600.0      # a draft Step is well under a second; a fine one can take minutes


@dataclass
class EpisodeResult:
    row: dict[str, Any]
    trace: dict[str, list]
    frames: list = field(default_factory=list)  # HxWx3 uint8, only with record_video


def _instruction(client: Client, spec: EpisodeSpec) -> str:
    return client.tasks.generate_instructions(spec.task.cut_spec(), seed=spec.seed, count=1,
                                              split=spec.language)[0]


class ActTimeout(Exception):
    """The policy took longer than act_timeout_s for one action."""


def _act(pool: concurrent.futures.ThreadPoolExecutor, policy: Policy, observation, timeout_s: float):
    """The policy's action, or ActTimeout when it takes longer than timeout_s (its thread is left to finish).
    A TimeoutError the policy raises itself (a remote model's query timeout) stays the policy's error:
    future.result(timeout) would raise the same class for both."""
    future = pool.submit(policy.act, observation)
    done, _ = concurrent.futures.wait([future], timeout=timeout_s)
    if not done:
        raise ActTimeout
    return future.result()


def _task_row(spec: EpisodeSpec) -> dict[str, Any]:
    task = spec.task
    return {"suite": spec.suite, "task": task.name, "trial": spec.trial, "seed": spec.seed, "group_name": task.group,
            "food": task.food, "style": task.style, "state": task.state,
            "ratio": task.ratio if task.state == "ratio" else None, "side": task.side,
            "pieces_required": task.pieces if task.state == "split" else None, "distractors": task.distractors,
            "topology": int(task.topology), "scene": task.scene, "language": task.language, "quality": task.quality,
            **_safety_fields(task)}


def _safety_fields(task) -> dict[str, Any]:
    """The limiter's switch and settings; its counts start at 0 (the session's totals fill them in)."""
    on = task.safety_limiter
    return {"safety_limiter": int(on), "safety_settings": json.dumps(task.safety, sort_keys=True) if on else None,
            "safety_max_force_n": float(task.safety.get("max_force_n", DEFAULT_MAX_FORCE_N)) if on else None,
            "safety_acted_steps": 0, "peak_commanded_speed_m_s": 0.0 if on else None,
            **{f"interventions_{guard}": 0 for guard in ALL_GUARDS}}


def _score_fields(score: dict | None) -> dict[str, Any]:
    score = score or {}
    cuts = [{"target_fraction": c["target_fraction"], "placed": c["placed"],
             "measured_fraction": c["measured_fraction"], "position_error_fraction": c["position_error_fraction"],
             "angle_error_deg": float(np.degrees(c["angle_error_rad"])) if c["angle_measured"] else None,
             "blade_angle_error_deg": (float(np.degrees(c["blade_angle_error_rad"]))
                                       if c.get("blade_angle_measured") else None),
             "correct": c["correct"]} for c in score.get("required", [])]
    return {"cuts_required": score.get("cuts_required", 0), "cuts_correct": score.get("cuts_correct", 0),
            "cuts_within_tolerance": score.get("cuts_within_position_tolerance", 0),
            "extra_cuts": score.get("extra_cuts", 0), "wrong_object_cuts": score.get("wrong_object_cuts", 0),
            "cuts": json.dumps(cuts), "score_summary": score.get("summary", "")}


def run_episode(spec: EpisodeSpec, server: str, options: EpisodeOptions) -> EpisodeResult:
    """Runs the episode on `server` (host:port). Raises ServerLost when the server stops answering;
    every other fault (policy, scene, server error) ends in a row that says what happened."""
    started = time.perf_counter()
    row = _task_row(spec)
    row.update(policy=options.policy, policy_options=json.dumps(options.policy_options, sort_keys=True),
               server=server, outcome="error", end_reason="", error="", steps=0, sim_time_s=0.0,
               peak_force_n=0.0, peak_speed_m_s=0.0, stalled_steps=0, pieces=0, instruction="", resolved_scene="",
               env_wall_s=0.0, policy_wall_s=0.0, stage_wall_s="{}", server_version="", build_id="", simd="",
               policy_name="", policy_version="", **_score_fields(None))
    trace: dict[str, list] = {"time_s": [], "force_n": [], "speed_m_s": [], "tcp_z_m": [], "tcp_along_cut_m": [],
                              "tcp_along_blade_m": [], "blade_pitch_deg": [], "knife_contact": [], "safety_acted": []}
    frames: list = []
    try:
        with Client(server, timeout_s=options.rpc_timeout_s) as client:
            info = client.server_info()
            row.update(server_version=info.version, build_id=info.build_id, simd=info.simd)
            policy = make_policy(options.policy, options.policy_options)
            try:
                _play(client, spec, policy, options, row, trace, frames)
            finally:
                # After the episode: a remote policy (grpc) says its own name and version when it connects.
                row.update(policy_name=str(getattr(policy, "name", "")),
                           policy_version=str(getattr(policy, "version", "0")))
                _finish_policy(policy, row)
    except Unavailable as err:
        raise ServerLost(f"{server}: {err.details}") from None
    except CulinaryCutError as err:
        row.update(outcome="error", end_reason="server_error", error=f"{err.code.name}: {err.details}"[:2000])
    row["wall_s"] = time.perf_counter() - started
    return EpisodeResult(row=row, trace=trace, frames=frames)


def _finish_policy(policy: Policy, row: dict) -> None:
    """A remote policy's query latencies go into the row; its connection to the model server is closed."""
    summary = getattr(policy, "latency_summary", None)
    if summary is not None:
        row["policy_latency"] = json.dumps(summary(), sort_keys=True)
    close = getattr(policy, "close", None)
    if close is not None:
        try:
            close()
        except Exception:  # a model server already gone: nothing left to close
            pass


def _play(client: Client, spec: EpisodeSpec, policy: Policy, options: EpisodeOptions, row: dict, trace: dict,
          frames: list) -> None:
    scene = dict(spec.scene)
    try:  # a remote policy (grpc) asks its server for these
        policy_cameras = [dict(c) for c in getattr(policy, "cameras", ())]
        control_mode = policy.control_mode
    except Unavailable:
        raise
    except (ConnectionError, PolicyServerError) as err:  # the policy's server, not a bug in its code
        row.update(outcome="error", end_reason="policy_error", error=f"metadata: {type(err).__name__}: {err}"[:2000])
        return
    cameras = list(scene.get("cameras", [])) + policy_cameras
    if options.record_video and not any(c["name"] == RECORD_CAMERA["name"] for c in cameras):
        cameras.append(dict(RECORD_CAMERA))
    scene["cameras"] = cameras
    instruction = _instruction(client, spec)
    scene["task"] = {"instruction": instruction}
    row["instruction"] = instruction
    env_wall = policy_wall = 0.0
    clock = time.perf_counter()
    with CulinaryCutEnv(client=client, scene=scene, control_mode=control_mode) as env, \
            concurrent.futures.ThreadPoolExecutor(1, thread_name_prefix="policy") as pool:
        row["resolved_scene"] = json_format.MessageToJson(env.handshake.resolved_scene, indent=None,
                                                          preserving_proto_field_name=True)
        observation, info = env.reset(seed=spec.seed)
        env_wall += time.perf_counter() - clock
        info["session"] = EpisodeSession(client, env.session_id)
        info["objects"] = scene["objects"]
        info["object_boxes"] = object_boxes(json_format.MessageToDict(env.handshake.resolved_scene,
                                                                      preserving_proto_field_name=True),
                                            info.get("food"))
        info["control_frequency_hz"] = 1.0 / env.control_timestep if env.control_timestep > 0 else None
        try:
            clock = time.perf_counter()
            policy.reset(instruction, info)
            policy_wall += time.perf_counter() - clock
        except Unavailable:
            raise
        except Exception as err:  # the policy's own fault: recorded, the suite goes on
            row.update(outcome="error", end_reason="policy_error", error=f"reset: {type(err).__name__}: {err}"[:2000])
            return
        end_reason, info = "step_limit", {}
        for step in range(spec.task.max_episode_steps):
            clock = time.perf_counter()
            try:
                mode, action = _act(pool, policy, observation, options.act_timeout_s)
            except ActTimeout:
                row.update(outcome="error", end_reason="policy_error", steps=step,
                           error=f"act took longer than {options.act_timeout_s:g} s at step {step}")
                return
            except Unavailable:
                raise
            except Exception as err:
                row.update(outcome="error", end_reason="policy_error", steps=step,
                           error=f"act at step {step}: {type(err).__name__}: {err}"[:2000])
                return
            policy_wall += time.perf_counter() - clock
            if mode != env.control_mode:
                env.control_mode = mode  # the server checks the action against the mode
            clock = time.perf_counter()
            observation, _, terminated, truncated, info = env.step(action)
            env_wall += time.perf_counter() - clock
            _record_step(observation, info, trace, row, frames if options.record_video else None)
            if terminated:
                end_reason = "success"
                break
            if info["fail"]:
                end_reason = "task_failed"
                break
            if truncated:
                break
            if policy.finished:
                end_reason = "policy_finished"
                break
        row["steps"] = len(trace["time_s"])
        row["sim_time_s"] = trace["time_s"][-1] if trace["time_s"] else 0.0
        row["pieces"] = len(info.get("food", {}).get("pieces", []))
        row.update(_score_fields(info.get("task")))
        row.update(signature(trace["tcp_along_blade_m"], trace["blade_pitch_deg"], trace["knife_contact"]))
        row["outcome"] = "success" if info.get("success") else "failure"
        # A failure in which the arm pushed with all it has: the food was too hard for the Panda here.
        if row["outcome"] == "failure" and row["stalled_steps"] > 0 and end_reason in ("step_limit", "policy_finished"):
            end_reason = "knife_stalled"
        row["end_reason"] = end_reason
        stats = client.session_stats(env.session_id)
        row["stage_wall_s"] = json.dumps({k: round(v, 6) for k, v in sorted(stats.stage_wall_time_s.items())})
        _record_safety_totals(stats, row)
    row["env_wall_s"] = env_wall
    row["policy_wall_s"] = policy_wall


def _record_safety_totals(stats, row: dict) -> None:
    """The session's safety totals: the knife's peaks (limiter on or off) and, with the limiter, its
    interventions per guard."""
    if not stats.HasField("safety"):
        return
    row["peak_knife_force_n"] = float(stats.safety.peak_knife_force_n)
    row["peak_cutting_speed_m_s"] = float(stats.safety.peak_cutting_speed_m_s)
    for guard in ALL_GUARDS:
        row[f"interventions_{guard}"] = int(stats.safety.interventions.get(guard, 0))


def _along_cut_m(tcp_pose) -> float:
    """The TCP's position on its own cutting direction (+z, the edge leads; docs/safety.md): with the blade's
    orientation held, its change is the knife's travel along the cut."""
    w, x, y, z = (float(v) for v in tcp_pose[3:7])
    z_axis = np.array([2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)])
    return float(np.dot(np.asarray(tcp_pose[:3], dtype=float), z_axis))


def _record_step(observation, info, trace, row, frames) -> None:
    extra = observation["extra"]
    force_n = float(np.linalg.norm(extra["wrist_wrench"][:3]))
    speed_m_s = float(np.linalg.norm(extra["tcp_velocity"][:3]))
    safety = info.get("safety", {})
    acted = bool(safety.get("acted", False))
    trace["time_s"].append(round(info["sim_time"], 6))
    trace["force_n"].append(round(force_n, 4))
    trace["speed_m_s"].append(round(speed_m_s, 5))
    trace["tcp_z_m"].append(round(float(extra["tcp_pose"][2]), 5))
    trace["tcp_along_cut_m"].append(round(_along_cut_m(extra["tcp_pose"]), 5))
    trace["tcp_along_blade_m"].append(round(along_blade_m(extra["tcp_pose"]), 5))
    trace["blade_pitch_deg"].append(round(blade_pitch_deg(extra["tcp_pose"]), 3))
    trace["knife_contact"].append(int(info.get("food", {}).get("knife_contact", False)))
    trace["safety_acted"].append(int(acted))
    row["safety_acted_steps"] += int(acted)
    if safety:
        row["peak_commanded_speed_m_s"] = max(row["peak_commanded_speed_m_s"], safety["commanded_speed_m_s"])
    row["peak_force_n"] = max(row["peak_force_n"], force_n)
    row["peak_speed_m_s"] = max(row["peak_speed_m_s"], speed_m_s)
    row["stalled_steps"] += int(info.get("knife_stalled", False))
    recorded = observation.get("sensor_data", {}).get(RECORD_CAMERA["name"], {})
    if frames is not None and "rgb" in recorded:
        frames.append(recorded["rgb"].copy())

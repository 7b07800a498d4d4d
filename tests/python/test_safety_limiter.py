"""The safety limiter through a real server: the capability and the loaded force model in GetServerInfo,
bad settings refused naming the field, a missing model refused as FAILED_PRECONDITION, a limited episode
reporting its interventions in the env's info and the session stats, the limiter off costing nothing, and
an aggressive cut that still succeeds with the limiter on, held to v_safe and under F_max."""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest
import zmq

from culinarycut import CulinaryCutEnv, errors
from culinarycut.launch import ServerProcess, server_binary
from culinarycut.v1 import simulator_pb2
from google.protobuf import json_format

TEST_FORCE_MODEL = Path(__file__).resolve().parents[1] / "sim" / "safety" / "test_force_model.json"

# A small, stiff food at the draft preset (the C++ test_limiter_step uses the same).
FOOD = {"food": "cucumber", "scale": 0.6,
        "materialOverrides": {"youngs_modulus_pa": 2.5e6, "fracture_toughness_j_m2": 1000.0}}
EFFECTS = {"mpm": True, "damage": True, "friction": True, "forceSensing": True}


def limiter_scene(**safety) -> dict:
    return {"quality": "draft", "robot": {"jointStiffness": 40}, "objects": [FOOD],
            "effects": {**EFFECTS, "safetyLimiter": True}, "safety": safety}


def start(extra_args: list[str]) -> ServerProcess:
    binary = server_binary()
    if not binary.is_file():
        pytest.fail(f"culinarycut-server not found at {binary}", pytrace=False)
    return ServerProcess(binary, max_sessions=4, idle_timeout_s=60, extra_args=extra_args)


@pytest.fixture(scope="module")
def safety_server():
    server = start(["--safety-model", str(TEST_FORCE_MODEL)])
    yield server
    assert server.stop() == 0, server.output()


@pytest.fixture(scope="module")
def safety_address(safety_server):
    return safety_server.address


@pytest.fixture(scope="module")
def modelless_address():
    server = start(["--safety-model", "/nonexistent/force_model.json"])
    yield server.address
    assert server.stop() == 0, server.output()


def knife_at(position) -> np.ndarray:
    """pd_ee_pose_quat: the knife pointing straight down, its blade along world x."""
    return np.array([*position, 0.0, 1.0, 0.0, 0.0])


def test_capability_and_the_loaded_model_are_listed(safety_address):
    from culinarycut import Client
    with Client(safety_address) as client:
        info = client.server_info()
    assert "safety_limiter" in info.capabilities
    model = info.safety_model
    assert model.loaded and model.version == 1 and model.path == str(TEST_FORCE_MODEL)
    assert (model.ranges["speed_m_s"].low, model.ranges["speed_m_s"].high) == (0.02, 4.0)
    assert model.terms == 2 and model.out_of_range_factor == 1.5


def test_without_the_model_the_limiter_is_refused_naming_the_problem(modelless_address):
    from culinarycut import Client
    with Client(modelless_address) as client:
        info = client.server_info()
        assert "safety_limiter" not in info.capabilities
        assert not info.safety_model.loaded and "/nonexistent/force_model.json" in info.safety_model.load_error
        with pytest.raises(errors.FailedPrecondition, match="/nonexistent/force_model.json"):
            client.create_session(limiter_scene())


@pytest.mark.parametrize("safety, field", [
    ({"maxForceN": -5.0}, "scene.safety.max_force_n"),
    ({"margin": 0.95}, "scene.safety.margin"),
    ({"margin": -0.1}, "scene.safety.margin"),
    ({"guards": ["speed", "brake"]}, "scene.safety.guards[1]"),
    ({"maxEntryAngleDeg": "Infinity"}, "scene.safety.max_entry_angle_deg"),  # proto-JSON spelling of inf
    ({"maxEntryAngleDeg": 120.0}, "scene.safety.max_entry_angle_deg"),
])
def test_bad_settings_are_refused_naming_the_field(safety_address, safety, field):
    from culinarycut import Client
    with Client(safety_address) as client, pytest.raises(errors.InvalidArgument, match=field.replace("[", r"\[")):
        client.create_session(limiter_scene(**safety))


def test_settings_without_the_limiter_are_refused(safety_address):
    from culinarycut import Client
    scene = {**limiter_scene(margin=0.2), "effects": EFFECTS}
    with Client(safety_address) as client, pytest.raises(errors.InvalidArgument, match="scene.safety"):
        client.create_session(scene)


def test_resolved_scene_echoes_the_settings(safety_address):
    from culinarycut import Client
    with Client(safety_address) as client:
        response = client.create_session(limiter_scene(maxForceN=8.0, margin=0.0, guards=["force"]))
        client.close_session(response.session_id)
    safety = response.resolved_scene.safety
    assert (safety.max_force_n, safety.margin.value, list(safety.guards), safety.max_entry_angle_deg) == (8.0, 0.0, ["force"], 15.0)
    assert response.resolved_scene.effects.safety_limiter


def descend(env: CulinaryCutEnv, steps: int) -> list[dict]:
    """Knife 3 cm above the food, then commanded to just above the board at once; the infos of the descent."""
    env.reset(seed=0)
    centre = env.handshake.resolved_scene.objects[0].pose.position  # the food's box centre, resolved by the server
    above = [centre[0], centre[1], centre[2] + 0.05]
    for _ in range(40):
        env.step(knife_at(above))
    return [env.step(knife_at([centre[0], centre[1], 0.024]))[-1] for _ in range(steps)]


def test_a_limited_descent_reports_interventions_in_info_and_stats(safety_address):
    with CulinaryCutEnv(safety_address, scene=limiter_scene(maxForceN=8.0), control_mode="pd_ee_pose_quat") as env:
        infos = descend(env, 12)
        stats = env.client.session_stats(env._session_id)
    acted = [info["safety"] for info in infos if info["safety"]["acted"]]
    assert acted, [info["safety"] for info in infos]
    assert all(step["reason"] for step in acted)
    assert any(step["guard_counts"]["speed"] == 1 and step["v_safe_m_s"] is not None for step in acted)
    totals = stats.safety
    assert sum(totals.interventions.values()) == sum(sum(s["guard_counts"].values()) for s in acted)
    assert stats.stage_calls["safety"] == 52 and stats.stage_wall_time_s["safety"] > 0
    assert totals.peak_knife_force_n <= 8.0


def test_telemetry_says_when_the_limiter_acted_and_keeps_a_zero_v_safe(safety_server):
    """A telemetry subscriber sees each Step's intervention and binding guards, and v_safe only when a food was
    near the edge: absent above the food, present (0 included) in it."""
    context = zmq.Context()
    subscriber = context.socket(zmq.SUB)
    subscriber.setsockopt(zmq.LINGER, 0)
    subscriber.setsockopt(zmq.SUBSCRIBE, b"telemetry/")
    subscriber.connect(safety_server.telemetry)
    time.sleep(0.5)  # ZeroMQ "slow joiner"
    try:
        with CulinaryCutEnv(safety_server.address, scene=limiter_scene(maxForceN=8.0),
                            control_mode="pd_ee_pose_quat") as env:
            infos = descend(env, 12)
        frames = []
        while subscriber.poll(1000):
            frames.append(simulator_pb2.TelemetryFrame.FromString(subscriber.recv_multipart()[1]))
    finally:
        subscriber.close()
        context.term()
    acted = {info["safety"]["reason"] for info in infos if info["safety"]["acted"]}
    assert acted and any(frame.limiter_acted for frame in frames)
    for frame in frames:
        assert frame.limiter_acted == bool(frame.bound_guards), frame
        assert set(frame.bound_guards) <= {"speed", "force", "entry_angle"}
    assert not frames[0].assessed  # the reset: the knife far above the food
    near = [frame for frame in frames if frame.assessed]
    assert near
    # At F_max 8 N the model holds the knife: v_safe 0, which JSON drops, yet the frame still says it was assessed.
    held = [frame for frame in near if frame.v_safe_m_s == 0.0]
    assert held and all(json_format.MessageToDict(frame)["assessed"] for frame in held)
    assert any(list(frame.bound_guards) == ["speed"] for frame in frames)


def test_the_limiter_off_costs_nothing(safety_address):
    scene = {**limiter_scene(), "effects": EFFECTS}
    del scene["safety"]
    with CulinaryCutEnv(safety_address, scene=scene, control_mode="pd_ee_pose_quat") as env:
        infos = descend(env, 3)
        stats = env.client.session_stats(env._session_id)
        assert env.last_step_timings["safety_wall_time_ms"] == 0.0
    assert all("safety" not in info for info in infos)
    assert stats.stage_calls["safety"] == 0 and stats.stage_wall_time_s["safety"] == 0.0
    assert dict(stats.safety.interventions) == {}


# A cut that succeeds with the limiter on. The engine's peak force is the food's toughness times the edge in
# it, whatever the knife's speed: a preset 0.6-scale cucumber (calibrated toughness 488 J/m^2) peaked within
# about 1 % of 12.5 N at knife speeds from 0.02 to 0.54 m/s, and at 13.5 N both with and without the limiter
# here. So no F_max is passed without the limiter and kept with it while the cut still succeeds: under the
# peak (13.0 or 13.4 N) the force guard holds the limited knife in the food and the cucumber stays whole
# (the force still creeps to 13.4 N). What this shows instead is the speed guard. The test asset
# F_hat = G L + 400 v sqrt(E) L grades v_safe with F_max (the shipped model is nearly flat in speed, so its
# v_safe is all or nothing: docs/safety.md): at F_max 15 N v_safe is about 0.21 m/s, under the 0.55 m/s the
# aggressive oracle's knife reaches in the food without the limiter, where F_hat is past F_max. With the
# limiter the knife is held to v_safe (1 - margin), the force stays under F_max and the cucumber is cut in two.
CUT_F_MAX_N = 15.0
CUT_MARGIN = 0.1
CUT_INSTRUCTION = "Make a normal cut through the cucumber at the middle"


def cut_scene(limiter: bool) -> dict:
    scene = {"quality": "draft", "objects": [{"food": "cucumber", "scale": 0.6}],
             "effects": {**EFFECTS, "topology": True}, "task": {"instruction": CUT_INSTRUCTION},
             "maxEpisodeSteps": 120}
    if limiter:
        scene["effects"]["safetyLimiter"] = True
        scene["safety"] = {"maxForceN": CUT_F_MAX_N, "margin": CUT_MARGIN}
    return scene


def aggressive_cut(address: str, limiter: bool) -> dict:
    """One episode of the aggressive oracle (the cut commanded at 3.6 m/s, as in the safety ablation) on
    cut_scene(limiter), seed 0: the per-step limiter infos, the outcome and the session's safety totals."""
    from culinarycut import Client
    from culinarycut.policies.base import EpisodeSession
    from culinarycut.policies.registry import make_policy
    policy = make_policy("oracle-aggressive", {})
    with Client(address) as client, \
            CulinaryCutEnv(client=client, scene=cut_scene(limiter), control_mode=policy.control_mode) as env:
        observation, info = env.reset(seed=0)
        info.update(session=EpisodeSession(client, env.session_id), control_frequency_hz=1.0 / env.control_timestep)
        policy.reset(CUT_INSTRUCTION, info)
        safety_steps = []
        for _ in range(120):
            observation, _, terminated, truncated, info = env.step(policy.act(observation)[1])
            if "safety" in info:
                safety_steps.append(info["safety"])
            if terminated or truncated or info["fail"] or policy.finished:
                break
        stats = env.client.session_stats(env.session_id)
    return {"success": info["success"], "pieces": len(info["food"]["pieces"]), "safety_steps": safety_steps,
            "stats": stats.safety}


def test_with_the_limiter_a_fast_cut_succeeds_at_v_safe_under_f_max(safety_address):
    off = aggressive_cut(safety_address, limiter=False)
    on = aggressive_cut(safety_address, limiter=True)
    # Off: the aggressive knife cuts the cucumber in two.
    assert off["success"] and off["pieces"] == 2
    assert off["safety_steps"] == [] and dict(off["stats"].interventions) == {}
    # On: v_safe is graded (neither 0 nor the top of the model's range) and F_hat there is F_max.
    assessed = [s for s in on["safety_steps"] if s["v_safe_m_s"] is not None]
    v_safe = [s["v_safe_m_s"] for s in assessed]
    assert assessed and 0.1 < min(v_safe) and max(v_safe) < 0.4, v_safe
    assert all(abs(s["predicted_force_n"] - CUT_F_MAX_N) < 0.01 for s in assessed)
    # Without the limiter the knife goes into the food well above v_safe: the model predicts more than F_max.
    assert off["stats"].peak_cutting_speed_m_s > 2 * max(v_safe), (off["stats"].peak_cutting_speed_m_s, v_safe)
    # The limiter acted: the speed guard bound on the steps into the food, each counted once.
    acted = [s for s in on["safety_steps"] if s["acted"]]
    assert len(acted) >= 3
    assert all(s["guard_counts"]["speed"] == 1 and "above v_safe" in s["reason"] and s["target_scale"] < 1.0
               and s["commanded_speed_m_s"] > (1 - CUT_MARGIN) * s["v_safe_m_s"] for s in acted)
    assert max(s["commanded_speed_m_s"] for s in acted) > 1.0  # what the policy asked for before the limit
    interventions = on["stats"].interventions
    assert interventions["speed"] == len(acted) and interventions["force"] == interventions["entry_angle"] == 0
    # ...and the cut still succeeded, the knife held to v_safe (1 - margin) and its force under F_max.
    assert on["success"] and on["pieces"] == 2
    assert on["stats"].peak_cutting_speed_m_s <= (1 - CUT_MARGIN) * max(v_safe)
    assert on["stats"].peak_knife_force_n <= CUT_F_MAX_N
    assert on["stats"].peak_knife_force_n > 5.0  # it did cut through the food, not stop at its surface

"""The safety limiter through a real server: the capability and the loaded force model in GetServerInfo,
bad settings refused naming the field, a missing model refused as FAILED_PRECONDITION, a limited episode
reporting its interventions in the env's info and the session stats, and the limiter off costing nothing."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from culinarycut import CulinaryCutEnv, errors
from culinarycut.launch import ServerProcess, server_binary

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
def safety_address():
    server = start(["--safety-model", str(TEST_FORCE_MODEL)])
    yield server.address
    assert server.stop() == 0, server.output()


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

"""The robot, the MPM food and their coupling through the server, at the draft preset."""
from __future__ import annotations

import math

import numpy as np
import pytest

from culinarycut import errors
from culinarycut.bench.knife_reach import FOOD_HALF_FOOTPRINT_M
from culinarycut.client import food_to_dict
from culinarycut.policies import ScriptedOracle, run_oracle_episode

CUCUMBER = {"food": "cucumber"}  # the real material preset
# The same with a Maxwell branch: its stress is state that a snapshot must carry.
VISCOELASTIC_CUCUMBER = {"food": "cucumber",
                         "material_overrides": {"maxwell_modulus_ratio": 1.0, "maxwell_relaxation_time_s": 0.05}}
CUTTING_EFFECTS = {"mpm": True, "damage": True, "friction": True, "topology": True, "force_sensing": True}


def cutting_scene(*objects) -> dict:
    return {"quality": "draft", "effects": CUTTING_EFFECTS, "objects": list(objects)}


def test_a_robot_only_scene_allocates_no_mpm(client):
    session = client.create_session({}).session_id
    client.reset(session)
    response = client.step(session, "pd_ee_delta_pose", np.zeros(6))
    assert response.info.mpm_substeps == 0
    stats = client.session_stats(session)
    assert not stats.mpm_allocated and stats.mpm_substeps == 0 and stats.mpm_particles == 0
    client.close_session(session)


def test_food_scenes_are_checked_with_the_field_named(client):
    with pytest.raises(errors.InvalidArgument, match="effects.mpm"):
        client.create_session({"objects": [{"food": "cucumber"}]})
    with pytest.raises(errors.InvalidArgument, match=r"scene.objects\[0\]"):
        client.create_session(cutting_scene({"food": "durian"}))
    with pytest.raises(errors.InvalidArgument, match="youngs_modulus_pa"):
        client.create_session(cutting_scene({"food": "cucumber", "material_overrides": {"stiffness": 1.0}}))
    with pytest.raises(errors.InvalidArgument, match="scene.mpm.dx"):
        client.create_session({**cutting_scene(CUCUMBER), "mpm": {"dx": 1.0}})
    with pytest.raises(errors.InvalidArgument, match="scene.mpm.mass_scaling"):
        client.create_session({**cutting_scene(CUCUMBER), "mpm": {"mass_scaling": 0.5}})
    with pytest.raises(errors.InvalidArgument, match=r"scene.mpm.activity_radius must be 0 \(off\) or in \[5 dx"):
        client.create_session({**cutting_scene(CUCUMBER), "mpm": {"activity_radius": 0.01}})  # draft dx: 8 mm


def test_mass_scaling_is_echoed_and_cuts_in_fewer_substeps(client):
    """The same oracle cut with the food's inertia x16: the same two pieces in about a quarter of the substeps."""
    substeps, pieces = {}, {}
    for scaling in (1.0, 16.0):
        handshake = client.create_session({**cutting_scene(CUCUMBER), "mpm": {"mass_scaling": scaling}})
        assert handshake.resolved_scene.mpm.mass_scaling == scaling
        session = handshake.session_id
        client.reset(session, seed=3)
        oracle = ScriptedOracle(client, session)
        oracle.reset("cut the cucumber in the middle")
        response = None
        while not oracle.finished:
            response = client.step(session, *oracle.act())
        pieces[scaling] = len(food_to_dict(response.observation)["pieces"])
        substeps[scaling] = client.session_stats(session).mpm_substeps
        client.close_session(session)
    assert pieces == {1.0: 2, 16.0: 2}
    assert 0 < substeps[16.0] <= 0.35 * substeps[1.0], substeps


def test_activity_is_echoed_and_the_oracle_still_cuts_in_two(client):
    """Food 5 cells from the knife may freeze (SceneSpec mpm.activity_radius): the oracle's cut still makes two pieces."""
    handshake = client.create_session({**cutting_scene(CUCUMBER), "mpm": {"activity_radius": 0.04}})
    assert handshake.resolved_scene.mpm.activity_radius == pytest.approx(0.04)
    assert "activity 40 mm" in handshake.resolved_scene.expected_accuracy.setting
    session = handshake.session_id
    client.reset(session, seed=3)
    oracle = ScriptedOracle(client, session)
    oracle.reset("cut the cucumber in the middle")
    response, most_frozen = None, 0
    while not oracle.finished:
        response = client.step(session, *oracle.act())
        stats = client.session_stats(session)
        most_frozen = max(most_frozen, stats.mpm_frozen_particles)
    assert len(food_to_dict(response.observation)["pieces"]) == 2
    assert 0 < most_frozen < stats.mpm_particles  # part of the food froze while the knife was elsewhere
    client.close_session(session)


def test_the_resolved_scene_places_the_food_and_names_the_resolution(client):
    handshake = client.create_session(cutting_scene(CUCUMBER))
    scene = handshake.resolved_scene
    assert scene.mpm.dx == pytest.approx(0.008) and scene.mpm.particles_per_cell == 4
    assert scene.mpm.mass_scaling == 1.0  # real mass unless asked
    assert scene.mpm.activity_radius == 0.0  # every particle integrated unless asked
    position = np.asarray(scene.objects[0].pose.position)
    assert position[2] > 0.02  # resting on the board, whose top is at z = 0.02 m
    client.close_session(handshake.session_id)


def test_a_small_food_refines_the_preset_grid_and_is_cut_in_every_style(client):
    """A strawberry at draft's 8 mm would be 13 cells and crumble; the draft grid is refined until it spans 64."""
    explicit = client.create_session({**cutting_scene({"food": "strawberry"}), "mpm": {"dx": 0.008}})
    assert explicit.resolved_scene.mpm.dx == pytest.approx(0.008)  # an explicit dx is kept as given
    client.close_session(explicit.session_id)
    handshake = client.create_session(cutting_scene({"food": "strawberry"}))
    assert 0.004 < handshake.resolved_scene.mpm.dx < 0.006, handshake.resolved_scene.mpm.dx
    assert not handshake.resolved_scene.expected_accuracy.measured  # the study did not measure the refined grid
    client.close_session(handshake.session_id)
    for style in ("normal", "bias", "guillotine", "saw"):
        scene = {**cutting_scene({"food": "strawberry"}), "task": {"instruction": f"{style} cut the strawberry at the middle"}}
        trace = run_oracle_episode(client, scene, seed=1)
        assert trace["success"] and trace["pieces"] == 2, (style, trace["score"])
        cut = trace["score"]["required"][0]
        assert cut["angle_measured"] and cut["angle_ok"], (style, cut)  # the cut surface's plane was scored


def test_an_accuracy_target_gets_the_cheapest_measured_setting_and_says_what_to_expect(client):
    """`quality: {force_error: 0.1}` instead of a preset name: the server picks from its accuracy study."""
    presets = {p.name: p for p in client.server_info().quality_presets}
    assert list(presets) == ["draft", "standard", "fine"]
    draft, standard = presets["draft"].expected, presets["standard"].expected
    assert draft.measured and standard.measured and not presets["fine"].expected.measured
    unmeasured = presets["fine"].expected  # no number rather than a zero error at zero cost
    assert all(math.isnan(getattr(unmeasured, field)) for field in
               ("force_error", "mean_force_error", "force_curve_error", "cut_position_error_mm", "relative_cost"))
    assert standard.relative_cost == pytest.approx(1.0) and draft.relative_cost < 0.25  # at least 4x cheaper
    assert standard.force_error < draft.force_error and presets["standard"].mpm.cfl == pytest.approx(0.8)

    # A bound looser than the standard's but tighter than draft's: a setting between them, cheaper than standard.
    bound = 0.25
    handshake = client.create_session({**cutting_scene(CUCUMBER), "quality": {"force_error": bound}})
    resolved = handshake.resolved_scene
    client.close_session(handshake.session_id)
    expected = resolved.expected_accuracy
    assert resolved.accuracy_target.force_error == pytest.approx(bound)
    assert expected.measured and expected.force_error <= bound < draft.force_error and expected.relative_cost < 1.0
    assert expected.setting == (f"dx {resolved.mpm.dx * 1e3:g} mm, {resolved.mpm.particles_per_cell} ppc, "
                                f"CFL {resolved.mpm.cfl:g}")
    # The resolved quality names what the target chose: not the default "standard" it was sent with.
    grid = (resolved.mpm.dx, resolved.mpm.particles_per_cell, resolved.mpm.cfl)
    chosen = {name for name, p in presets.items() if (p.mpm.dx, p.mpm.particles_per_cell, p.mpm.cfl) == grid}
    assert resolved.quality == (chosen.pop() if chosen else "accuracy_target"), resolved.quality
    # No measured setting is cheaper and as accurate: the presets are among the candidates.
    assert not any(p.expected.measured and p.expected.force_error <= bound and p.expected.relative_cost
                   < expected.relative_cost for p in presets.values())
    # The resolved scene, sent again, resolves to the same setting.
    again = client.create_session(resolved)
    assert again.resolved_scene.mpm == resolved.mpm
    client.close_session(again.session_id)
    with pytest.raises(errors.InvalidArgument, match="scene.accuracy_target.force_error 0.001 is below"):
        client.create_session({**cutting_scene(CUCUMBER), "quality": {"force_error": 0.001}})
    with pytest.raises(errors.InvalidArgument, match="scene.accuracy_target sets no bound"):
        client.create_session({**cutting_scene(CUCUMBER), "quality": {}})
    with pytest.raises(errors.InvalidArgument, match='"accuracy_target" needs scene.accuracy_target'):
        client.create_session({**cutting_scene(CUCUMBER), "quality": "accuracy_target"})


def test_a_food_given_only_x_and_y_rests_on_the_board_there(client):
    default = client.create_session(cutting_scene(CUCUMBER))
    lying = default.resolved_scene.objects[0].pose.position
    client.close_session(default.session_id)
    handshake = client.create_session(cutting_scene({**CUCUMBER, "pose": {"position": [0.45, 0.05]}}))
    position = np.asarray(handshake.resolved_scene.objects[0].pose.position)
    np.testing.assert_allclose(position, [0.45, 0.05, lying[2]], atol=1e-12)  # same height as the default
    client.close_session(handshake.session_id)
    with pytest.raises(errors.InvalidArgument, match=r"scene.objects\[0\].pose.position"):
        client.create_session(cutting_scene({**CUCUMBER, "pose": {"position": [0.45]}}))
    with pytest.raises(errors.InvalidArgument, match=r"off the table"):
        client.create_session(cutting_scene({**CUCUMBER, "pose": {"position": [5.0, 0.0]}}))


def test_mpm_sleeps_until_the_knife_approaches(client):
    session = client.create_session(cutting_scene(CUCUMBER)).session_id
    client.reset(session)
    for _ in range(3):
        response = client.step(session, "pd_ee_delta_pose", np.zeros(6))
        assert response.info.mpm_substeps == 0
    stats = client.session_stats(session)
    assert stats.mpm_allocated and stats.mpm_particles > 1000
    assert stats.mpm_substeps == 0 and not stats.has_contact
    client.close_session(session)


def test_an_oracle_cut_splits_the_cucumber_and_loads_the_wrist_only_in_contact(client):
    session = client.create_session(cutting_scene(CUCUMBER)).session_id
    client.reset(session, seed=3)
    oracle = ScriptedOracle(client, session)
    oracle.reset("cut the cucumber in the middle")
    forces, first_contact_step = [], None
    response = None
    while not oracle.finished:
        mode, values = oracle.act()
        response = client.step(session, mode, values)
        forces.append(float(np.linalg.norm(np.asarray(response.observation.wrist_wrench)[:3])))
        if response.info.first_contact:
            first_contact_step = len(forces) - 1
    assert first_contact_step is not None, "the knife never touched the cucumber"
    assert max(forces[:first_contact_step], default=0.0) < 1e-6
    assert max(forces[first_contact_step:]) > 1.0
    pieces = food_to_dict(response.observation)["pieces"]
    assert len(pieces) == 2
    stats = client.session_stats(session)
    assert stats.has_contact and stats.first_contact_frame == first_contact_step + 1
    assert stats.stage_calls["mpm"] > 0 and stats.stage_wall_time_s["mpm"] > 0
    client.close_session(session)


@pytest.mark.parametrize("mpm, food", [({}, CUCUMBER), ({"activity_radius": 0.04}, CUCUMBER),
                                       ({}, VISCOELASTIC_CUCUMBER)],
                         ids=["every particle", "activity", "viscoelastic"])
def test_restore_then_replay_gives_identical_force_traces(client, mpm, food):
    """Snapshot in the middle of a cut; the replayed steps give bit-identical wrenches and pieces (with activity
    too: which particles are frozen travels in the snapshot, and so does a Maxwell branch's stress)."""
    session = client.create_session({**cutting_scene(food), "mpm": mpm}).session_id
    client.reset(session, seed=5)
    oracle = ScriptedOracle(client, session)
    oracle.reset("cut the cucumber in the middle")
    actions, original, snapshot = [], [], None
    while not oracle.finished:
        mode, values = oracle.act()
        observation = client.step(session, mode, values).observation
        if snapshot is None and observation.food.knife_contact:
            snapshot = client.save_snapshot(session)  # in contact: the MPM state matters
        elif snapshot is not None:
            actions.append((mode, values))
            original.append((tuple(observation.wrist_wrench), len(observation.food.pieces)))
        if len(actions) == 8:
            break
    assert snapshot is not None and len(actions) == 8

    def replay():
        client.restore_snapshot(session, snapshot)
        trace = []
        for mode, values in actions:
            observation = client.step(session, mode, values).observation
            trace.append((tuple(observation.wrist_wrench), len(observation.food.pieces)))
        return trace

    assert replay() == original
    assert replay() == original
    assert any(np.linalg.norm(wrench[:3]) > 0 for wrench, _ in original)
    client.close_session(session)


def test_the_knife_reach_footprints_hold_each_food_the_server_makes(client):
    """The distractor layout's food footprints (bench/knife_reach.py) against the particles of each food at
    scale 1 lying along world x: each footprint covers its food, within one draft cell of slack."""
    scene = cutting_scene(*[{"food": food, "pose": {"position": [0.30 + 0.25 * (i % 3), -0.30 + 0.30 * (i // 3)],
                                                    "quaternion": [1.0, 0.0, 0.0, 0.0]}}
                            for i, food in enumerate(FOOD_HALF_FOOTPRINT_M)])
    handshake = client.create_session(scene)
    response = client.reset(handshake.session_id, seed=0)
    pieces = food_to_dict(response.observation)["pieces"]
    for index, (food, (half_length_m, half_width_m)) in enumerate(FOOD_HALF_FOOTPRINT_M.items()):
        own = [p for p in pieces if p["object"] == index]
        low = np.min([p["bounds_min"] for p in own], axis=0)
        high = np.max([p["bounds_max"] for p in own], axis=0)
        half = 0.5 * (high - low)[:2]
        assert half[0] <= half_length_m + 1e-3 and half[1] <= half_width_m + 1e-3, (food, half)
        assert half[0] >= half_length_m - 0.008 and half[1] >= half_width_m - 0.008, (food, half)  # not loose
    client.close_session(handshake.session_id)

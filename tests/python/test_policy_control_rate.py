"""A model trained at a slower rate than the simulator's: its delta actions are spread over k = f_sim /
f_model control steps (delta / k each) and it is queried once per k steps; the default rate is the
statistics' upstream dataset's."""
from __future__ import annotations

import json

import numpy as np
import pytest

from culinarycut_policies.control_rate import ModelRate
from culinarycut_policies.openvla import OpenVLAPolicy
from culinarycut_policies.standins.rest_server import JsonNumpyRestServer

TWENTY_HZ = {"control_frequency_hz": 20.0}


def steps_for(option, key, info=TWENTY_HZ):
    rate = ModelRate(option, key, "openvla")
    rate.reset(info)
    return rate.steps


def test_upstream_rates_by_dataset_key():
    # RDT's configs/dataset_control_freq.json: bridgev2 5 Hz, droid 15 Hz; LIBERO's environments 20 Hz
    # (libero/libero/envs/bddl_base_domain.py control_freq=20).
    assert steps_for(None, "bridge_orig") == 4 and steps_for(None, "bridge_dataset") == 4
    assert steps_for(None, "libero_spatial_no_noops") == 1 and steps_for(None, "libero_10") == 1
    assert steps_for(None, "culinarycut_delta_ee") == 1  # trained on our export: the simulator's rate
    assert steps_for(10.0, "bridge_orig") == 2  # the option wins
    with pytest.raises(ValueError, match="15 Hz does not divide the control rate 20 Hz"):
        steps_for(None, "droid")
    with pytest.raises(ValueError, match="model_rate_hz needs the episode's control rate"):
        steps_for(5.0, None, {})
    with pytest.raises(ValueError, match="model_rate_hz must be positive"):
        ModelRate(0, None, "openvla")


def test_bridge_trained_openvla_is_queried_at_5_hz_and_its_delta_spread_over_4_steps(tmp_path):
    # OpenVLA's own statistics for Bridge (no CulinaryCut layout: units from option action_units)
    bounds = {"mean": [0.0] * 7, "std": [1.0] * 7, "min": [-1.0] * 7, "max": [1.0] * 7,
              "q01": [-0.02] * 6 + [0.0], "q99": [0.02] * 6 + [1.0], "mask": [True] * 6 + [False]}
    path = tmp_path / "dataset_statistics.json"
    path.write_text(json.dumps({"bridge_orig": {"action": bounds, "num_transitions": 1, "num_trajectories": 1}}))
    queries = []

    def model(payload):
        queries.append(payload)
        return np.array([0.008, -0.004, 0.0, 0.01, -0.02, 0.016, 1.0])

    server = JsonNumpyRestServer(model).start()
    observation = {"sensor_data": {"front": {"rgb": np.zeros((32, 32, 3), np.uint8)}}}
    try:
        policy = OpenVLAPolicy(url=server.url, statistics=str(path), action_units="metres_radians")
        policy.reset("cut", TWENTY_HZ)
        steps = [policy.act(observation) for _ in range(8)]
        policy.close()
    finally:
        server.stop()
    assert len(queries) == 2  # 8 steps at 20 Hz are 2 Bridge steps
    assert {mode for mode, _ in steps} == {"pd_ee_delta_pose"}
    # pd_ee_delta_pose units are 0.1 m / 0.1 rad: the 8 mm delta is 0.08, a quarter of it per step
    np.testing.assert_allclose(steps[0][1], [0.02, -0.01, 0.0, 0.025, -0.05, 0.04])
    np.testing.assert_allclose(sum(values for _, values in steps[:4]), [0.08, -0.04, 0.0, 0.1, -0.2, 0.16])

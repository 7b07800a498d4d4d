"""Octo as its own code feeds and un-normalises it: ResizeImageWrapper's centre crop of image_primary
(octo/utils/gym_wrappers.py) and a dataset_statistics file as Octo writes it, with p01/p99
(octo/data/utils/data_utils.py get_dataset_statistics, the mask from octo/data/dataset.py)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from culinarycut_policies import images, statistics
from culinarycut_policies.octo import OctoPolicy
from culinarycut_policies.standins.websocket_server import WebsocketPolicyServer

pytestmark = pytest.mark.filterwarnings("ignore:connect\\(\\) must be used as a context manager:DeprecationWarning")

# What get_dataset_statistics writes per dataset (its key names and no others), the action mask
# make_dataset_from_rlds adds; keyed by dataset name as OctoModel.dataset_statistics is.
OCTO_STATISTICS = {"bridge_dataset": {
    "action": {"mean": [0.001, 0.0, -0.002, 0.0, 0.0, 0.003, 0.6], "std": [0.01, 0.012, 0.011, 0.03, 0.03, 0.05, 0.5],
               "max": [0.04, 0.04, 0.04, 0.1, 0.1, 0.2, 1.0], "min": [-0.04, -0.04, -0.04, -0.1, -0.1, -0.2, 0.0],
               "p99": [0.03, 0.03, 0.03, 0.08, 0.08, 0.15, 1.0], "p01": [-0.03, -0.03, -0.03, -0.08, -0.08, -0.15, 0.0],
               "mask": [True] * 6 + [False]},
    "proprio": {"mean": [0.0] * 8, "std": [1.0] * 8, "max": [1.0] * 8, "min": [-1.0] * 8,
                "p99": [0.9] * 8, "p01": [-0.9] * 8},
    "num_transitions": 2135463, "num_trajectories": 60064}}


def test_octo_crop_by_hand():
    # A quarter-area box is [0.25, 0.75] of a 4 x 4 image of 20 y + 10 x: crop_and_resize to 4 x 4 samples
    # y, x at 0.75 + i 0.5; the 0-255 float result goes through tf.round (half to even), as the wrapper does.
    y, x = np.mgrid[0:4, 0:4]
    image = np.repeat((20 * y + 10 * x).astype(np.uint8)[:, :, None], 3, axis=2)
    out = images.octo_center_crop(image, 0.25)
    # every sample lands on a half: 22.5 -> 22, 27.5 -> 28, ...
    np.testing.assert_array_equal(out[:, :, 0], [[22, 28, 32, 38], [32, 38, 42, 48], [42, 48, 52, 58],
                                                 [52, 58, 62, 68]])


def test_octo_crop_of_image_primary_keeps_the_central_0_9_of_the_area():
    # ResizeImageWrapper's box: side sqrt(0.9), offset (1 - side) / 2, TF's sample positions on a 256
    # ramp: x_j = offset 255 + j side 255 / 255; bilinear is exact on a ramp, then rounded.
    ramp = np.repeat(np.broadcast_to(np.arange(256, dtype=np.uint8)[None, :], (256, 256))[:, :, None], 3, axis=2)
    out = images.octo_center_crop(ramp, 0.9)
    side = float(np.sqrt(np.float32(0.9)))
    expected = np.round((1 - side) / 2 * 255 + np.arange(256) * side)
    np.testing.assert_array_equal(out[128, :, 1], expected)
    assert out[0, 0, 0] == 7 and out[0, 255, 0] == 248


def test_octos_own_statistics_are_read_with_p01_p99(tmp_path):
    path = tmp_path / "octo_statistics.json"
    path.write_text(json.dumps(OCTO_STATISTICS))
    loaded = statistics.load_statistics(path, "bridge_dataset", policy="octo")
    np.testing.assert_array_equal(loaded.action.q01, OCTO_STATISTICS["bridge_dataset"]["action"]["p01"])
    np.testing.assert_array_equal(loaded.proprio.q99, [0.9] * 8)
    contradicting = {"k": {"action": dict(OCTO_STATISTICS["bridge_dataset"]["action"], q01=[0.0] * 7)}}
    path.write_text(json.dumps(contradicting))
    with pytest.raises(statistics.StatisticsError, match="has both q01 and p01, and they differ"):
        statistics.load_statistics(path, "k", policy="octo")


def frame(seed: int) -> dict:
    rng = np.random.Generator(np.random.PCG64(seed))
    return {"sensor_data": {"front": {"rgb": rng.integers(0, 256, (60, 80, 3), dtype=np.uint8)}},
            "extra": {"tcp_pose": np.array([0.45, -0.05, 0.25, 0.0, 1.0, 0.0, 0.0])}}


@pytest.mark.parametrize("crop_primary", [True, False])
def test_octo_workflow_with_octos_statistics_and_cropped_primary_over_the_wire(tmp_path, crop_primary):
    path = tmp_path / "octo_statistics.json"
    path.write_text(json.dumps(OCTO_STATISTICS))  # as serve_octo.py --write-statistics exports it
    seen = []

    def model(request):
        seen.append(request)
        return {"actions": np.ones((1, 4, 7), np.float32)}

    server = WebsocketPolicyServer(model, {"model_family": "octo", "window": 2, "action_horizon": 4}).start()
    try:
        policy = OctoPolicy(url=server.url, statistics=str(path), unnorm_key="bridge_dataset",
                            action_units="metres_radians", crop_primary=crop_primary)
        policy.reset("cut the cucumber", {})
        mode, values = policy.act(frame(0))
        policy.close()
    finally:
        server.stop()
    squashed = images.squash_resize(frame(0)["sensor_data"]["front"]["rgb"], 256, 256)
    sent = seen[0]["observation"]["image_primary"][0, -1]
    np.testing.assert_array_equal(sent, images.octo_center_crop(squashed, 0.9) if crop_primary else squashed)
    action = OCTO_STATISTICS["bridge_dataset"]["action"]
    expected = (np.array(action["mean"]) + np.array(action["std"]))[:6] / 0.1  # pd_ee_delta_pose: 1 = 0.1 m, rad
    assert mode == "pd_ee_delta_pose"
    np.testing.assert_allclose(values, expected, rtol=1e-9)

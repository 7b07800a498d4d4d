"""Golden values of every pre- and post-processing step of the policy adapters (no server, no model):
resizes and crops on images whose right answer is known in closed form, the prompt text,
un-normalisation, the 6-D rotation, chunk execution order and ensembling weights, msgpack encoding."""
from __future__ import annotations

import json

import numpy as np
import pytest

import policy_support
from culinarycut_policies import actions, chunking, images, rotation, statistics
from culinarycut_policies.octo import OctoHistory
from culinarycut_policies.openvla import openvla_image, openvla_prompt
from culinarycut_policies.transports import msgpack_numpy


def ramp(height: int, width: int, axis: int) -> np.ndarray:
    """value = column (axis 1) or row (axis 0) index, in all three channels."""
    index = np.arange(width if axis == 1 else height, dtype=np.uint8)
    plane = np.broadcast_to(index[None, :] if axis == 1 else index[:, None], (height, width))
    return np.repeat(plane[:, :, None], 3, axis=2).copy()


def tf_to_uint8(value):
    """tf.image.convert_image_dtype(float in [0, 1] -> uint8): x * 255.5, truncated."""
    return np.floor(np.clip(np.asarray(value) / 255.0, 0, 1) * 255.5).astype(int)


# --- images -----------------------------------------------------------------------------------------
def test_squash_resize_maps_each_axis_on_its_own_without_letterbox():
    # A 256 x 128 (W x H) horizontal ramp squashed to 224 x 224: column j samples source x = (j + 0.5)
    # 256/224 - 0.5, and a normalised symmetric Lanczos kernel reproduces a ramp exactly away from the
    # borders. A letterbox would leave rows of black and change the mapping.
    out = images.squash_resize(ramp(128, 256, axis=1), 224, 224)
    assert out.shape == (224, 224, 3)
    columns = np.arange(8, 216)
    expected = (columns + 0.5) * 256 / 224 - 0.5
    assert np.abs(out[112, columns, 0] - expected).max() <= 0.51
    assert (out[:, columns, 0] == out[112, columns, 0]).all()  # every row alike: no padding band
    tall = images.squash_resize(ramp(128, 256, axis=0), 224, 224)  # rows: 128 -> 224, stretched
    rows = np.arange(8, 216)
    assert np.abs(tall[rows, 100, 1] - ((rows + 0.5) * 128 / 224 - 0.5)).max() <= 0.51


def test_center_crop_samples_tf_crop_and_resize_positions():
    # OpenVLA's 0.9-area crop of a 224 ramp: side sqrt(0.9) of the image, TF's sample positions
    # x_j = x1 (W - 1) + j (x2 - x1) (W - 1) / (w - 1); bilinear is exact on a ramp.
    out = images.center_crop_resize(ramp(224, 224, axis=1), 0.9, 224, 224)
    side = np.sqrt(np.float32(0.9))
    x = (1 - side) / 2 * 223 + np.arange(224) * side * 223 / 223
    assert out[0, 0, 0] == 5 and out[0, 223, 0] == 217
    np.testing.assert_array_equal(out[100, :, 2], tf_to_uint8(x))
    np.testing.assert_array_equal(out[:, 50, 0], np.full(224, out[0, 50, 0]))


def test_center_crop_of_a_small_image_by_hand():
    # 4 x 4 image, value 20 y + 10 x; a quarter-area crop (half the side) to 2 x 2 samples
    # y, x in {0.75, 2.25}: 20 y + 10 x = 22.5, 37.5 / 52.5, 67.5 -> uint8 through 255.5/255, truncated.
    y, x = np.mgrid[0:4, 0:4]
    image = np.repeat((20 * y + 10 * x).astype(np.uint8)[:, :, None], 3, axis=2)
    out = images.center_crop_resize(image, 0.25, 2, 2)
    np.testing.assert_array_equal(out[:, :, 0], [[22, 37], [52, 67]])


def test_openvla_image_is_jpeg_then_squash_then_crop():
    rng = np.random.Generator(np.random.PCG64(3))
    frame = rng.integers(0, 256, (120, 160, 3), dtype=np.uint8)
    plain, cropped = openvla_image(frame, False), openvla_image(frame, True)
    assert plain.shape == cropped.shape == (224, 224, 3) and plain.dtype == np.uint8
    np.testing.assert_array_equal(plain, images.squash_resize(images.jpeg_roundtrip(frame), 224, 224))
    np.testing.assert_array_equal(cropped, images.center_crop_resize(plain, 0.9, 224, 224))
    assert np.abs(plain.astype(int) - images.squash_resize(frame, 224, 224)).max() > 10  # noise does not survive JPEG
    np.testing.assert_array_equal(openvla_image(frame, False, jpeg=False), images.squash_resize(frame, 224, 224))


def test_jpeg_roundtrip_keeps_flat_blocks_and_blurs_noise():
    flat = np.full((16, 16, 3), (200, 100, 50), dtype=np.uint8)
    assert np.abs(images.jpeg_roundtrip(flat).astype(int) - flat).max() <= 1
    noise = np.random.Generator(np.random.PCG64(4)).integers(0, 256, (16, 16, 3), dtype=np.uint8)
    assert np.abs(images.jpeg_roundtrip(noise).astype(int) - noise).mean() > 2  # 4:2:0 chroma, quantisation


def test_resize_with_pad_matches_openpi_client():
    from openpi_client import image_tools
    rng = np.random.Generator(np.random.PCG64(5))
    for shape in ((120, 160, 3), (200, 90, 3), (224, 224, 3)):
        frame = rng.integers(0, 256, shape, dtype=np.uint8)
        np.testing.assert_array_equal(images.resize_with_pad(frame, 224, 224),
                                      image_tools.resize_with_pad(frame, 224, 224))


def test_rdt_pads_square_with_the_encoder_mean_centred():
    frame = np.full((50, 100, 3), 255, dtype=np.uint8)  # wide: padded above and below
    out = images.pad_square_resize(frame, 100)
    assert out.shape == (100, 100, 3)
    assert (out[:25] == 127).all() and (out[75:] == 127).all() and (out[25:75] == 255).all()
    assert images.pad_square_resize(frame, 384).shape == (384, 384, 3)


# --- text ---------------------------------------------------------------------------------------------
def test_openvla_prompt_is_upstream_text():
    assert openvla_prompt("Cut the Cucumber in HALF") == \
        "In: What action should the robot take to cut the cucumber in half?\nOut:"
    assert openvla_prompt("Slice it", v01=True).endswith("USER: What action should the robot take to slice it? ASSISTANT:")


# --- normalisation ------------------------------------------------------------------------------------
@pytest.fixture
def delta_stats(tmp_path):
    return statistics.load_statistics(policy_support.write_statistics(tmp_path), policy_support.DELTA_KEY,
                                      policy="test")


def test_unnormalize_q99_by_hand(delta_stats):
    # dim 0: q01 -0.004, q99 0.006: 0.5 (n + 1) 0.010 - 0.004; the gripper (mask false) passes through.
    normalized = np.array([-1.0, 0.0, 1.0, 0.5, 0.0, 0.0, 0.7])
    out = statistics.unnormalize_bounds_q99(normalized, delta_stats.action)
    np.testing.assert_allclose(out, [-0.004, 0.0, 0.004, 0.01, 0.005, -0.005, 0.7], atol=1e-12)


def test_unnormalize_normal_drops_extra_model_dims(delta_stats):
    out = statistics.unnormalize_normal(np.array([1.0, -1, 0, 0, 0, 0, 0.3, 9.0]), delta_stats.action)
    np.testing.assert_allclose(out[:2], [0.001 + 0.0025, 0.0 - 0.0025])
    assert out.shape == (7,) and out[6] == 0.3


def test_normalize_q99_clips_and_bounds_roundtrip(delta_stats, tmp_path):
    out = statistics.normalize_bounds_q99(np.array([0.9, 0.0, 5.0, 0, 0, 0, 0.04, 0.04]), delta_stats.proprio)
    np.testing.assert_allclose(out[:3], [1.0, 0.0, 1.0], atol=1e-6)
    np.testing.assert_allclose(out[6:], [0.04, 0.04])  # masked out: as given
    rdt = statistics.load_statistics(tmp_path / "dataset_statistics.json", policy_support.RDT_KEY, policy="t")
    values = np.linspace(-0.5, 0.5, 16)
    back = statistics.unnormalize_bounds(statistics.normalize_bounds(values, rdt.proprio), rdt.action)
    np.testing.assert_allclose(back, values, atol=1e-12)


def test_statistics_are_required_and_errors_name_the_option(tmp_path):
    with pytest.raises(statistics.StatisticsError, match="needs option statistics=PATH"):
        statistics.load_statistics(None, None, policy="openvla")
    path = policy_support.write_statistics(tmp_path)
    with pytest.raises(statistics.StatisticsError, match="unnorm_key='bridge_orig' is not in .*culinarycut_delta"):
        statistics.load_statistics(path, "bridge_orig", policy="openvla")
    with pytest.raises(statistics.StatisticsError, match="has 2 datasets; choose one with option unnorm_key"):
        statistics.load_statistics(path, None, policy="openvla")
    broken = tmp_path / "broken.json"
    broken.write_text(json.dumps({"k": {"action": {"mean": [0, 0], "std": [1, 1]}}}))
    with pytest.raises(statistics.StatisticsError, match="lacks min, max, q01, q99"):
        statistics.load_statistics(broken, "k", policy="octo")


# --- rotation -----------------------------------------------------------------------------------------
def test_ortho6d_is_first_two_columns_and_round_trips():
    rng = np.random.Generator(np.random.PCG64(11))
    for _ in range(50):
        quaternion = rng.normal(size=4)
        matrix = rotation.quat_wxyz_to_matrix(quaternion)
        six = rotation.matrix_to_ortho6d(matrix)
        np.testing.assert_allclose(six, np.concatenate([matrix[:, 0], matrix[:, 1]]))
        np.testing.assert_allclose(rotation.ortho6d_to_matrix(six), matrix, atol=1e-12)
        back = rotation.matrix_to_quat_wxyz(matrix)
        q = quaternion / np.linalg.norm(quaternion)
        np.testing.assert_allclose(back, q if q[0] >= 0 else -q, atol=1e-12)
    # A model's noisy 6-D output becomes the nearest proper rotation with the first column kept.
    noisy = np.array([2.0, 0.0, 0.0, 0.3, 1.0, 0.0])
    np.testing.assert_allclose(rotation.ortho6d_to_matrix(noisy), np.eye(3), atol=1e-12)


# --- actions and chunks -------------------------------------------------------------------------------
def test_delta_action_in_control_units_and_gripper_dropped():
    mode, values = actions.delta_to_ee_delta_pose([0.01, -0.02, 0.0, 0.05, 0.0, -0.1, 1.0], "metres_radians")
    assert mode == "pd_ee_delta_pose"
    np.testing.assert_allclose(values, [0.1, -0.2, 0.0, 0.5, 0.0, -1.0])


@pytest.mark.parametrize("units, action, expected", [
    # pd_ee_delta_pose's own units (ManiSkill): 1 = 0.1 m / 0.1 rad already, passed through unchanged
    ("maniskill_normalised", [0.3, -0.5, 0.0, 0.2, 0.0, -1.0, 1.0], [0.3, -0.5, 0.0, 0.2, 0.0, -1.0]),
    # robosuite OSC_POSE (LIBERO): 1 = 0.05 m -> 0.5 of ours, 1 = 0.5 rad -> 5 of ours; input clipped to [-1, 1]
    ("robosuite_osc", [0.2, -0.4, 1.0, 0.02, -0.1, 0.0, -1.0], [0.1, -0.2, 0.5, 0.1, -0.5, 0.0]),
    ("robosuite_osc", [3.0, -2.0, 0.0, 0.0, 0.0, 7.0], [0.5, -0.5, 0.0, 0.0, 0.0, 5.0]),
    ("metres_radians", [0.005, 0.0, -0.01, 0.0, 0.02, 0.0], [0.05, 0.0, -0.1, 0.0, 0.2, 0.0]),
])
def test_delta_action_units_golden(units, action, expected):
    mode, values = actions.delta_to_ee_delta_pose(action, units)
    assert mode == "pd_ee_delta_pose"
    np.testing.assert_allclose(values, expected, atol=1e-12)


def test_action_units_come_from_the_statistics_or_the_option(tmp_path):
    policy_support.write_statistics(tmp_path)
    path = tmp_path / "dataset_statistics.json"
    stats, units = actions.load_delta_ee_statistics(path, policy_support.DELTA_KEY, None, policy="t", proprio=True)
    assert units == "metres_radians" and stats.key == policy_support.DELTA_KEY
    with pytest.raises(statistics.StatisticsError, match="option action_units='robosuite_osc' contradicts"):
        actions.load_delta_ee_statistics(path, policy_support.DELTA_KEY, "robosuite_osc", policy="t", proprio=False)
    with pytest.raises(ValueError, match="option action_units='inches'; choose one of metres_radians"):
        actions.load_delta_ee_statistics(path, policy_support.DELTA_KEY, "inches", policy="t", proprio=False)
    # the RDT key is in another layout: refused, naming both
    with pytest.raises(statistics.StatisticsError, match="has action_layout 'rdt_unified_16', but this adapter "
                                                         "reads 'delta_ee_xyz_euler_xyz_gripper'"):
        actions.load_delta_ee_statistics(path, policy_support.RDT_KEY, None, policy="t", proprio=False)
    # without unnorm_key the one key in the adapter's layout is chosen
    chosen, _ = actions.load_delta_ee_statistics(path, None, None, policy="t", proprio=False)
    assert chosen.key == policy_support.DELTA_KEY
    # a file that does not say its units (upstream's own statistics) needs the option
    document = json.loads(path.read_text())
    for field in ("action_units", "action_layout", "proprio_layout"):
        del document[policy_support.DELTA_KEY][field]
    bare = tmp_path / "upstream.json"
    bare.write_text(json.dumps({"bridge_orig": document[policy_support.DELTA_KEY]}))
    with pytest.raises(statistics.StatisticsError, match="does not say its action_units; set option action_units="):
        actions.load_delta_ee_statistics(bare, None, None, policy="t", proprio=False)
    _, units = actions.load_delta_ee_statistics(bare, None, "robosuite_osc", policy="t", proprio=False)
    assert units == "robosuite_osc"
    mode, values = actions.pose_to_ee_pose_quat([0.5, 0, 0.2], np.diag([1.0, -1.0, -1.0]))
    assert mode == "pd_ee_pose_quat"
    np.testing.assert_allclose(values, [0.5, 0, 0.2, 0, 1, 0, 0], atol=1e-12)


def test_open_loop_executes_in_order_then_requeries():
    runner = chunking.OpenLoopChunks(3)
    executed = []
    queries = 0
    for _ in range(7):
        if runner.needs_chunk:
            runner.add(np.arange(8)[:, None] + 100 * queries)
            queries += 1
        executed.append(int(runner.next()[0]))
    assert executed == [0, 1, 2, 100, 101, 102, 200] and queries == 3


def test_temporal_ensemble_averages_the_predictions_for_this_step():
    # Chunk t predicts 10 t + k for step t + k. At step 2 the kept chunks 0, 1, 2 give 2, 11, 20.
    ensemble = chunking.TemporalEnsemble(4)
    out = []
    for t in range(6):
        ensemble.add((10 * t + np.arange(4))[:, None].astype(float))
        out.append(float(ensemble.next()[0]))
    # From step 4 only the last 4 chunks count: (13 + 22 + 31 + 40) / 4 and (23 + 32 + 41 + 50) / 4.
    assert out == [0.0, 5.5, 11.0, 16.5, 26.5, 36.5]
    weighted = chunking.TemporalEnsemble(4, exp_weight=0.5)
    np.testing.assert_allclose(weighted.weights(3), np.exp([0, -0.5, -1.0]) / np.exp([0, -0.5, -1.0]).sum())
    for t in range(3):
        weighted.add((10 * t + np.arange(4))[:, None].astype(float))
    # Octo: the oldest chunk's prediction gets the largest weight.
    np.testing.assert_allclose(weighted.next()[0], weighted.weights(3) @ np.array([2.0, 11.0, 20.0]))


def test_octo_history_pads_the_first_step():
    history = OctoHistory()
    first = history.add({"image_primary": np.zeros((2, 2, 3), np.uint8)})
    second = history.add({"image_primary": np.ones((2, 2, 3), np.uint8)})
    assert first["timestep_pad_mask"].tolist() == [False, True]
    assert second["timestep_pad_mask"].tolist() == [True, True]
    assert second["image_primary"].shape == (2, 2, 2, 3)
    assert second["image_primary"][0].max() == 0 and second["image_primary"][1].min() == 1  # oldest first


# --- wire encoding ------------------------------------------------------------------------------------
def test_msgpack_numpy_matches_openpi_client_both_ways():
    from openpi_client import msgpack_numpy as upstream
    value = {"observation/image": np.arange(24, dtype=np.uint8).reshape(2, 4, 3), "state": np.float32(1.5),
             "prompt": "cut", "nested": {"a": np.eye(2)}}
    for pack, unpack in ((msgpack_numpy.packb, upstream.unpackb), (upstream.packb, msgpack_numpy.unpackb)):
        back = unpack(pack(value))
        np.testing.assert_array_equal(back["observation/image"], value["observation/image"])
        assert back["state"] == np.float32(1.5) and back["state"].dtype == np.float32
        np.testing.assert_array_equal(back["nested"]["a"], np.eye(2))
    assert msgpack_numpy.packb(value) == upstream.packb(value)
    with pytest.raises(ValueError, match="object"):
        msgpack_numpy.packb({"x": np.array([object()])})
    hostile = upstream.Packer().pack({b"__ndarray__": True, b"data": b"", b"dtype": "|O", b"shape": [0]})
    with pytest.raises(ValueError, match="refusing numpy dtype object"):
        msgpack_numpy.unpackb(hostile)


# --- RDT language embeddings -----------------------------------------------------------------------------
def test_rdt_embeddings_from_encode_lang_pt_files_or_npz(tmp_path):
    from culinarycut_policies import rdt_language
    npz = tmp_path / "instructions.npz"
    np.savez(npz, **{"cut the cucumber": np.full((1, 3, 4096), 0.5, np.float32)})
    loaded = rdt_language.load_embeddings(str(npz))
    assert list(loaded) == ["cut the cucumber"] and loaded["cut the cucumber"].shape == (3, 4096)
    np.savez(tmp_path / "bad.npz", x=np.zeros((3, 512), np.float32))
    with pytest.raises(ValueError, match=r"bad.npz\['x'\]: expected embeddings \(1, L, 4096\)"):
        rdt_language.load_embeddings(str(tmp_path / "bad.npz"))
    try:
        import torch
    except ImportError:
        torch = None
    pt = tmp_path / "cut.pt"
    if torch is None:  # the message says what to do
        pt.write_bytes(b"not read")
        with pytest.raises(ValueError, match="needs torch, which is not importable here"):
            rdt_language.load_embeddings(str(pt))
        return
    # encode_lang.py's file: {"name", "instruction", "embeddings" (1, L, 4096)}
    torch.save({"name": "cut", "instruction": "cut the apple", "embeddings": torch.full((1, 4, 4096), 0.25)}, pt)
    loaded = rdt_language.load_embeddings(str(tmp_path))  # a folder of .pt files
    assert list(loaded) == ["cut the apple"] and loaded["cut the apple"].shape == (4, 4096)
    assert rdt_language.main([str(tmp_path / "out.npz"), str(pt)]) == 0
    np.testing.assert_array_equal(np.load(tmp_path / "out.npz")["cut the apple"], loaded["cut the apple"])

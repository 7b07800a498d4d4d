"""A small generated dataset (two planner episodes and one replay of a demonstration on a randomised
object type), read back by readers that are not the writers: h5py for the HDF5 layouts, DuckDB for the
LeRobot Parquet files (pyarrow writes them) with every column compared with the recorded episode, OpenCV's
decoder for the videos; the LeRobot metadata checked against upstream LeRobot v2.1; verify's replay and its
detection of a truncated file; the same seed gives the same episode bytes, however long a process holds
the writer's HDF5 handles."""
from __future__ import annotations

import dataclasses
import io
import json
import shutil
from pathlib import Path

import cv2
import duckdb
import h5py
import numpy as np
import gymnasium
import pytest
from PIL import Image

import rdt_reader
from culinarycut import Client
from culinarycut.datasets.adapter_layouts import RDT_UNIFIED_SLOTS, delta_ee_actions, rdt_states
from culinarycut.datasets.demo import load_demonstration
from culinarycut.datasets.demo_from_oracle import record_oracle_demonstration
from culinarycut.datasets.episode_file import read_episode, write_episode
from culinarycut.datasets.episodes import iter_episodes
from culinarycut.datasets.export import export
from culinarycut.datasets.export_libero import export_libero
from culinarycut.datasets.export_rdt import export_rdt
from culinarycut.datasets.generate import generate, run_job
from culinarycut.datasets.jobs import DatasetConfig, Randomisation, draw_variation, job_scene, make_jobs
from culinarycut.datasets.rotation_vector import quat_xyzw_to_axis_angle
from culinarycut.datasets.store import GenerationStore
from culinarycut.datasets.verify import verify

SIZE = 32  # pixels: tiny cameras keep the test within a few minutes on 2 cores
RATIO_SPEC = {"style": "normal", "state": "ratio", "ratio": 0.3, "reference": "left", "target_object": "cucumber"}
MIDDLE_SPEC = {"style": "bias", "state": "middle", "target_object": "cucumber"}
CAMERAS = ("front", "left", "right")


@pytest.fixture(scope="module")
def dataset(address, tmp_path_factory):
    root = tmp_path_factory.mktemp("datasets")
    base = DatasetConfig(name="t", seed=3, tasks=(), episodes_per_task=1, image_size=SIZE)
    with Client(address, timeout_s=600) as client:
        scene = job_scene(base, draw_variation(base, RATIO_SPEC, 11), 11)
        scene["task"] = {"instruction": "cut the cucumber at 0.3 ratio from the left"}
        record_oracle_demonstration(client, scene, RATIO_SPEC, 11, root / "demo.json")
    config = DatasetConfig(name="t", seed=3, tasks=(RATIO_SPEC, MIDDLE_SPEC), episodes_per_task=1,
                           demos=(str(root / "demo.json"),), image_size=SIZE,
                           randomisation=Randomisation(foods=("cucumber", "banana")))
    summary = generate(config, root / "data", [address], progress=False)
    exported = export(root / "data", root / "export")
    return {"root": root / "data", "config": config, "summary": summary, "export": exported, "address": address}


def test_every_job_kept_with_its_variation(dataset):
    summary = dataset["summary"]
    assert (summary.jobs, summary.ran, summary.kept) == (3, 3, 3)
    with GenerationStore(dataset["root"]) as store:
        rows = store.rows()
    assert [r["reason"] for r in rows] == ["success"] * 3
    assert sum(r["key"].startswith("demo-") for r in rows) == 1
    meta, steps = read_episode(dataset["root"] / rows[0]["file"])
    assert len(meta["instructions"]) >= 5 and len(set(meta["instructions"])) == len(meta["instructions"])
    assert set(meta["variation"]) == {"position_m", "yaw_deg", "scale", "food", "cut_height_m", "cut_speed_m_s",
                                      "scene"}
    assert meta["resolved_scene"]["objects"][0]["scale"] == pytest.approx(meta["variation"]["scale"])
    # Both of the paper's scenes by default, each episode on the one it drew (rows and files agree).
    assert {r["scene"] for r in rows} == {"table", "kitchen"}
    for row in rows:
        meta = read_episode(dataset["root"] / row["file"])[0]
        assert meta["resolved_scene"].get("scene", "table") == meta["variation"]["scene"] == row["scene"]
    assert steps["obs/front_rgb"].shape[1:] == (SIZE, SIZE, 3)
    assert steps["knife_contact"].any(), "the knife never touched the food"
    assert np.abs(steps["obs/wrist_wrench"][:, :3]).max() > 0.1  # N: force was measured during the cut


def test_demonstration_is_object_relative(dataset):
    demo = load_demonstration(dataset["root"].parent / "demo.json")
    relative = np.asarray(demo.relative_pose)
    assert np.asarray(demo.knife_contact).any()
    # in half extents of the object: the cut ends below its bottom (z -1), at the 0.3 mark of its long
    # axis (x: 0.3 from one end is 0.4 half lengths from the centre), across its middle (y ~ 0)
    lowest = relative[np.argmin(relative[:, 2])]
    assert lowest[2] < -0.9
    assert abs(abs(lowest[0]) - 0.4) < 0.05 and abs(lowest[1]) < 0.2
    assert demo.cut_speed_m_s > 0.005


def test_demonstration_episode_phases_follow_the_knife(dataset):
    """A replayed demonstration's contact phase comes from the knife's state against the food."""
    with GenerationStore(dataset["root"]) as store:
        row = next(r for r in store.rows() if r["key"].startswith("demo-"))
    _, steps = read_episode(dataset["root"] / row["file"])
    phases, contact = list(steps["phase"]), steps["knife_contact"].astype(bool)
    assert all(phase == "cut" for phase, touching in zip(phases, contact) if touching)
    first = {phase: phases.index(phase) for phase in dict.fromkeys(phases)}
    assert first["approach"] == 0 and first["approach"] < first["descend"] < first["cut"] < first["retreat"], phases
    assert first["cut"] < int(np.argmax(contact)), "the cut starts above the food, at the drawn height"
    assert phases[-1] == "retreat" and "cut" not in phases[phases.index("retreat"):], phases


def test_robomimic_hdf5_read_back(dataset):
    with h5py.File(dataset["export"]["robomimic"], "r") as file:
        data = file["data"]
        demos = sorted(data.keys())
        assert demos == ["demo_0", "demo_1", "demo_2"]
        assert data.attrs["total"] == sum(data[d].attrs["num_samples"] for d in demos)
        env_meta = json.loads(data.attrs["env_args"])
        # robomimic/envs/env_base.py EnvType: ROBOSUITE_TYPE 1, GYM_TYPE 2, IG_MOMART_TYPE 3; env_utils
        # get_env_class raises for any other. GYM_TYPE's EnvGym calls make(env_name, **env_kwargs).
        assert env_meta["type"] == 2 and set(env_meta["env_kwargs"]) == {"control_mode"}
        with gymnasium.make(env_meta["env_name"], address=dataset["address"], **env_meta["env_kwargs"]) as env:
            assert env.unwrapped.control_mode == "pd_ee_pose_quat"
        assert json.loads(data.attrs["contact_phases"])[0] == "approach"
        for name in demos:
            demo = data[name]
            n = demo.attrs["num_samples"]
            for key in ("actions", "rewards", "dones", "states"):
                assert demo[key].shape[0] == n, key
            assert demo["dones"][-1] == 1 and demo["dones"][:-1].sum() == 0
            for camera in CAMERAS:
                assert demo[f"obs/{camera}_image"].shape == (n, SIZE, SIZE, 3)
                assert demo[f"obs/{camera}_image"].dtype == np.uint8
            for key in ("ee_states", "joint_states", "wrist_wrench", "contact_phase"):
                assert demo[f"obs/{key}"].shape[0] == n and demo[f"next_obs/{key}"].shape[0] == n
            np.testing.assert_array_equal(demo["next_obs/ee_states"][:-1], demo["obs/ee_states"][1:])
            assert len(json.loads(demo.attrs["instructions"])) >= 5
            assert json.loads(demo.attrs["model_file"])["objects"]
            assert demo.attrs["scene"] in ("table", "kitchen") and demo.attrs["topology"]
        masks = {k: sorted(v.decode() for v in file[f"mask/{k}"][()]) for k in ("train", "valid")}
        assert sorted(masks["train"] + masks["valid"]) == demos and not set(masks["train"]) & set(masks["valid"])


def test_libero_export_read_as_libero_loads_it(dataset, tmp_path):
    out = export_libero(dataset["root"], tmp_path / "libero")
    files = sorted(out.glob("*_demo.hdf5"))
    recorded = {json.dumps(meta["instructions"]): steps for _, meta, steps in iter_episodes(dataset["root"])}
    demos_read = 0
    for path in files:
        with h5py.File(path, "r") as f:
            # libero/libero/utils/dataset_utils.py get_dataset_info: demos in episode order, the language
            demos = sorted(f["data"].keys())
            demos = [demos[i] for i in np.argsort([int(elem[5:]) for elem in demos])]
            language = "".join(json.loads(f["data"].attrs["problem_info"])["language_instruction"])
            assert path.name == language.lower().replace(" ", "_") + "_demo.hdf5"
            assert json.loads(f["data"].attrs["env_args"])["type"] == 2
            assert f["data"].attrs["num_demos"] == len(demos)
            # robomimic's get_shape_metadata_from_dataset (LIBERO's get_dataset): the first demo's shapes
            first = f["data"][list(f["data"].keys())[0]]
            assert first["actions"].ndim == 2 and first["actions"].shape[1] == 7
            shapes = {k: first[f"obs/{k}"].shape[1:] for k in ("agentview_rgb", "gripper_states", "joint_states",
                                                                 "ee_states", "ee_pos", "ee_ori")}
            assert shapes == {"agentview_rgb": (SIZE, SIZE, 3), "gripper_states": (2,), "joint_states": (7,),
                              "ee_states": (6,), "ee_pos": (3,), "ee_ori": (3,)}
            # SequenceDataset.load_demo_info: each demo's num_samples; data's total is their sum
            assert f["data"].attrs["total"] == sum(f[f"data/{d}"].attrs["num_samples"] for d in demos)
            for name in demos:
                demo = f[f"data/{name}"]
                steps = recorded[demo.attrs["instructions"]]
                n = demo.attrs["num_samples"]
                assert all(demo[k].shape[0] == n for k in ("actions", "states", "robot_states", "rewards", "dones"))
                np.testing.assert_array_equal(demo["obs/agentview_rgb"][()], steps["obs/front_rgb"])
                # scripts/create_dataset.py: ee_states = [eef pos, quat2axisangle(eef quat)], ee_pos, ee_ori its parts
                quats = steps["obs/tcp_pose"][:, 3:7]
                expected = [quat_xyzw_to_axis_angle(np.r_[q[1:], q[0]] * (1 if q[1] >= 0 else -1)) for q in quats]
                np.testing.assert_allclose(demo["obs/ee_ori"][()], expected, atol=1e-6)
                np.testing.assert_array_equal(demo["obs/ee_states"][()],
                                              np.concatenate([demo["obs/ee_pos"][()], demo["obs/ee_ori"][()]], axis=1))
                assert np.abs(np.diff(demo["obs/ee_ori"][()], axis=0)).max() < 0.5  # no flip at edge down
                # OSC_POSE actions: delta / (0.05 m, 0.5 rad) in [-1, 1], gripper -1 (open)
                actions = demo["actions"][()]
                assert (np.abs(actions) <= 1.0).all() and (actions[:, 6] == -1.0).all()
                delta = delta_ee_actions(steps, "pd_ee_pose_quat")
                unclipped = (np.abs(delta[:, :3]) < 0.05).all(axis=1)
                np.testing.assert_allclose(actions[unclipped, :3] * 0.05, delta[unclipped, :3], atol=1e-9)
                # get_robot_state_vector: gripper qpos, eef pos, eef quaternion in robosuite's x, y, z, w
                np.testing.assert_allclose(demo["robot_states"][:, 5:], np.roll(quats, -1, axis=1), atol=1e-9)
                demos_read += 1
    assert demos_read == 3


def _jsonl(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines()]


def _recorded_episodes(dataset) -> list[tuple[dict, dict]]:
    """(meta, steps) of the kept episodes, read from the episode files in the store's order."""
    with GenerationStore(dataset["root"]) as store:
        return [read_episode(dataset["root"] / row["file"]) for row in store.rows(kept_only=True)]


# Upstream LeRobot v2.1 as openpi reads it: huggingface/lerobot at commit 0cf864870cf2 (openpi's pin),
# files under lerobot/common/datasets/; each check below names the upstream file and constant or function.
def test_lerobot_v21_metadata_matches_upstream(dataset):
    root = dataset["export"]["lerobot"]
    # utils.py INFO_PATH, EPISODES_PATH, TASKS_PATH, EPISODES_STATS_PATH: the four metadata files
    for name in ("meta/info.json", "meta/episodes.jsonl", "meta/tasks.jsonl", "meta/episodes_stats.jsonl"):
        assert (root / name).is_file(), name
    info = json.loads((root / "meta" / "info.json").read_text())
    episodes, tasks = _jsonl(root / "meta" / "episodes.jsonl"), _jsonl(root / "meta" / "tasks.jsonl")
    stats = _jsonl(root / "meta" / "episodes_stats.jsonl")
    # lerobot_dataset.py CODEBASE_VERSION
    assert info["codebase_version"] == "v2.1"
    # utils.py create_empty_dataset_info: the keys of every info.json (ours adds contact_phases)
    assert set(info) - {"contact_phases"} == {"codebase_version", "robot_type", "total_episodes", "total_frames",
                                              "total_tasks", "total_videos", "total_chunks", "chunks_size", "fps",
                                              "splits", "data_path", "video_path", "features"}
    # utils.py DEFAULT_CHUNK_SIZE
    assert info["chunks_size"] == 1000
    # utils.py DEFAULT_PARQUET_PATH
    assert info["data_path"] == "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet"
    # utils.py DEFAULT_VIDEO_PATH
    assert info["video_path"] == "videos/chunk-{episode_chunk:03d}/{video_key}/episode_{episode_index:06d}.mp4"
    # utils.py create_empty_dataset_info (fps: int; LeRobotDatasetMetadata.fps -> int)
    assert type(info["fps"]) is int and info["fps"] == 20
    assert isinstance(info["robot_type"], str)
    features = info["features"]
    video_keys = [k for k, f in features.items() if f["dtype"] == "video"]
    # lerobot_dataset.py LeRobotDatasetMetadata.save_episode: the counters, splits and chunks it keeps
    assert info["total_episodes"] == len(episodes) == 3 and info["total_frames"] == sum(e["length"] for e in episodes)
    assert info["total_tasks"] == len(tasks) and info["total_videos"] == len(episodes) * len(video_keys)
    assert info["splits"] == {"train": f"0:{len(episodes)}"} and info["total_chunks"] == 1
    # utils.py DEFAULT_FEATURES: the five per-frame index features, exactly
    for name, dtype in (("timestamp", "float32"), ("frame_index", "int64"), ("episode_index", "int64"),
                        ("index", "int64"), ("task_index", "int64")):
        assert features[name] == {"dtype": dtype, "shape": [1], "names": None}, name
    # utils.py get_hf_features_from_features: a numpy dtype name and a 1-D shape for every non-video feature
    for name, spec in features.items():
        if spec["dtype"] == "video":
            continue
        assert set(spec) == {"dtype", "shape", "names"} and np.dtype(spec["dtype"]).name == spec["dtype"], name
        assert len(spec["shape"]) == 1 and spec["shape"][0] >= 1, name
        assert spec["names"] is None or len(spec["names"]) == spec["shape"][0], name  # one name per element
    # utils.py dataset_to_policy_features: video shape (h, w, c) with names height, width, channels
    assert sorted(video_keys) == [f"observation.images.{c}" for c in sorted(CAMERAS)]
    for key in video_keys:
        spec = features[key]
        assert spec["shape"] == [SIZE, SIZE, 3] and spec["names"] == ["height", "width", "channels"], key
        # video_utils.py get_video_info and get_audio_info: the keys of a video's info, fps an int
        assert set(spec["info"]) == {"video.height", "video.width", "video.codec", "video.pix_fmt",
                                     "video.is_depth_map", "video.fps", "video.channels", "has_audio"}, key
        assert (spec["info"]["video.height"], spec["info"]["video.width"], spec["info"]["video.channels"]) == (
            SIZE, SIZE, 3)
        assert type(spec["info"]["video.fps"]) is int and spec["info"]["video.fps"] == info["fps"]
        assert spec["info"]["video.is_depth_map"] is False and spec["info"]["has_audio"] is False
    # lerobot_dataset.py LeRobotDatasetMetadata.save_episode: an episode row is episode_index, tasks, length
    # (ours adds cut_spec, seed, source); utils.py load_episodes sorts them by episode_index
    assert [e["episode_index"] for e in episodes] == list(range(len(episodes)))
    for episode in episodes:
        assert {"episode_index", "tasks", "length"} <= set(episode)
        assert type(episode["length"]) is int and episode["length"] > 0
        assert episode["tasks"] and all(isinstance(t, str) for t in episode["tasks"])
    # utils.py write_task / load_tasks: {task_index, task}, indices 0..n-1, each task once (add_task)
    assert all(set(t) == {"task_index", "task"} for t in tasks)
    assert sorted(t["task_index"] for t in tasks) == list(range(len(tasks)))
    assert len({t["task"] for t in tasks}) == len(tasks) == len({t for e in episodes for t in e["tasks"]})
    # utils.py write_episode_stats: {episode_index, stats}, one row per episode
    assert [s["episode_index"] for s in stats] == [e["episode_index"] for e in episodes]
    assert all(set(s) == {"episode_index", "stats"} for s in stats)
    for (meta, steps), episode, row in zip(_recorded_episodes(dataset), episodes, stats):
        # compute_stats.py compute_episode_stats: stats of every feature
        assert set(row["stats"]) == set(features)
        for name, stat in row["stats"].items():
            # compute_stats.py get_feature_stats: min, max, mean, std and count, count of shape (1,)
            assert set(stat) == {"min", "max", "mean", "std", "count"}, name
            assert len(stat["count"]) == 1 and stat["count"][0] >= 1, name
            shapes = {k: np.asarray(v).shape for k, v in stat.items() if k != "count"}
            if name in video_keys:
                # compute_stats.py compute_episode_stats and _assert_type_and_shape: per channel (3, 1, 1) in [0, 1]
                assert set(shapes.values()) == {(3, 1, 1)}, name
                assert 0.0 <= np.min(stat["min"]) and np.max(stat["max"]) <= 1.0, name
            else:
                # compute_stats.py compute_episode_stats: over the frames, the feature's shape (keepdims for 1-D)
                assert set(shapes.values()) == {tuple(features[name]["shape"])}, name
                assert stat["count"] == [episode["length"]], name
        actions = steps["actions"].astype(np.float32).astype(np.float64)
        np.testing.assert_allclose(row["stats"]["action"]["mean"], actions.mean(0), rtol=1e-6, atol=1e-9)
        np.testing.assert_allclose(row["stats"]["action"]["min"], actions.min(0))
        np.testing.assert_allclose(row["stats"]["action"]["std"], actions.std(0), rtol=1e-6, atol=1e-9)
        assert episode["tasks"] == list(meta["instructions"]) and episode["length"] == len(steps["actions"])


def _duckdb_columns(path: Path) -> tuple[dict[str, list], dict[str, str], dict[bytes, bytes], int]:
    """The Parquet file through DuckDB's own reader: values by column, column types, key-value metadata, rows."""
    with duckdb.connect() as con:
        relation = con.read_parquet(str(path))
        names, types = relation.columns, [str(t) for t in relation.types]
        rows = relation.fetchall()
        metadata = dict(con.execute("SELECT key, value FROM parquet_kv_metadata(?)", [str(path)]).fetchall())
        num_rows = con.execute("SELECT num_rows FROM parquet_file_metadata(?)", [str(path)]).fetchone()[0]
    return {n: [row[i] for row in rows] for i, n in enumerate(names)}, dict(zip(names, types)), metadata, num_rows


def test_lerobot_v21_read_back(dataset):
    """Every Parquet column read back with DuckDB (not pyarrow, the writer) equals what the episode
    recorded; every video decodes (OpenCV) to one frame per row."""
    root = dataset["export"]["lerobot"]
    info = json.loads((root / "meta" / "info.json").read_text())
    episodes, tasks = _jsonl(root / "meta" / "episodes.jsonl"), _jsonl(root / "meta" / "tasks.jsonl")
    features = info["features"]
    video_keys = [k for k, f in features.items() if f["dtype"] == "video"]
    task_index = {t["task"]: t["task_index"] for t in tasks}
    duckdb_type = {"float32": "FLOAT", "int64": "BIGINT", "bool": "BOOLEAN"}
    index_start, referenced = 0, set()
    recorded = _recorded_episodes(dataset)
    assert len(recorded) == len(episodes)
    for episode, (meta, steps) in zip(episodes, recorded):
        n, chunk = episode["length"], episode["episode_index"] // info["chunks_size"]
        assert episode["seed"] == meta["seed"] and episode["tasks"] == list(meta["instructions"])
        assert episode["scene"] == meta["variation"]["scene"] and episode["topology"] is True
        path = root / info["data_path"].format(episode_chunk=chunk, episode_index=episode["episode_index"])
        columns, types, metadata, num_rows = _duckdb_columns(path)
        assert num_rows == n == len(steps["actions"])
        assert set(columns) == {k for k in features if k not in video_keys}
        # The `datasets` description LeRobot loads the columns with (utils.py get_hf_features_from_features):
        # a Value for shape (1,), a fixed-length Sequence otherwise.
        described = json.loads(metadata[b"huggingface"])["info"]["features"]
        for name, values in columns.items():
            spec = features[name]
            assert len(values) == n, name
            if spec["shape"] == [1]:
                assert types[name] == duckdb_type[spec["dtype"]], (name, types[name])
                assert described[name] == {"dtype": spec["dtype"], "_type": "Value"}, name
            else:
                assert types[name] == f"{duckdb_type[spec['dtype']]}[]", (name, types[name])  # a Parquet LIST
                assert all(len(v) == spec["shape"][0] for v in values), name
                assert described[name] == {"feature": {"dtype": spec["dtype"], "_type": "Value"},
                                           "length": spec["shape"][0], "_type": "Sequence"}, name
        expected = {
            "observation.state": np.concatenate([steps["obs/qpos"], steps["obs/tcp_pose"]], axis=1),
            "observation.tcp_pose": steps["obs/tcp_pose"],
            "observation.wrist_wrench": steps["obs/wrist_wrench"],
            "action": steps["actions"],
            "contact_phase": np.array([info["contact_phases"].index(p) for p in steps["phase"]]),
            "knife_contact": steps["knife_contact"].astype(bool),
            "next.reward": steps["rewards"],
            "next.done": steps["dones"].astype(bool),
            "timestamp": np.arange(n) / info["fps"],
            "frame_index": np.arange(n),
            "episode_index": np.full(n, episode["episode_index"]),
            "index": np.arange(index_start, index_start + n),
            # frame i prompts with instruction i mod the number of instructions
            "task_index": np.array([task_index[meta["instructions"][f % len(meta["instructions"])]] for f in range(n)]),
        }
        assert set(expected) == set(columns), "a column is not compared"
        for name, values in columns.items():
            dtype = np.dtype(features[name]["dtype"])
            got = np.array([list(v) for v in values] if features[name]["shape"] != [1] else values)
            want = np.asarray(expected[name]).reshape(got.shape)
            if dtype.kind == "f":  # float32 in the file: the recorded value rounded to float32, exactly
                np.testing.assert_array_equal(got.astype(np.float32), want.astype(np.float32), err_msg=name)
            else:
                assert got.dtype.kind == ("b" if dtype.kind == "b" else "i"), name
                np.testing.assert_array_equal(got, want, err_msg=name)
        assert steps["dones"][-1] and columns["next.done"][-1] and not any(columns["next.done"][:-1])
        referenced.update(tasks[i]["task"] for i in columns["task_index"])
        index_start += n
        for key in video_keys:
            video = root / info["video_path"].format(episode_chunk=chunk, video_key=key,
                                                     episode_index=episode["episode_index"])
            capture = cv2.VideoCapture(str(video))
            frames = 0
            while True:
                ok, frame = capture.read()
                if not ok:
                    break
                assert frame.shape == (SIZE, SIZE, 3)
                frames += 1
            assert frames == n, key
    assert index_start == info["total_frames"]
    # every instruction of every episode is a task, and frames prompt with each of them
    assert referenced == {t["task"] for t in tasks} == {t for e in episodes for t in e["tasks"]}


def test_rdt_export_read_by_rdts_hdf5_reader(dataset, tmp_path):
    episodes = list(iter_episodes(dataset["root"]))
    longest = max(len(steps["actions"]) for _, _, steps in episodes)
    # the default export, and one whose minimum makes every episode padded
    for out, min_steps in ((Path(dataset["export"]["rdt"]), 128), (tmp_path / "rdt", longest + 5)):
        if min_steps != 128:
            export_rdt(dataset["root"], out, min_steps=min_steps)
        folders = sorted(out.iterdir())
        assert len(folders) == 3
        for folder, (_, _, steps) in zip(folders, episodes):
            check_rdt_episode(folder / f"{folder.name}.hdf5", steps, min_steps)


def check_rdt_episode(path: Path, steps: dict, min_steps: int) -> None:
    recorded = len(steps["actions"])
    valid, trajectory = rdt_reader.parse_state_only(path)
    assert valid  # not dropped as too short
    states = rdt_states(steps)  # the RDT adapter's robot_state of each observation
    with h5py.File(path, "r") as file:
        assert file.attrs["recorded_steps"] == recorded and len(file["action"]) == max(recorded, min_steps)
        np.testing.assert_array_equal(file["recorded_actions"][:recorded], steps["actions"])
        assert file.attrs["control_frequency_hz"] == 20.0
        assert file.attrs["scene"] in ("table", "kitchen") and file.attrs["topology"]
        # Our cameras, and upstream's names linked to them (front is RDT's cam_high).
        assert set(file["observations/images"].keys()) - {"cam_high", "cam_right_wrist"} == set(CAMERAS)
        first = rdt_reader.first_moving_step(file["observations/qpos"][:])
    instructions = json.loads((path.parent / "expanded_instruction_gpt-4-turbo.json").read_text())
    assert instructions["instruction"] and len(instructions["expanded_instruction"]) >= 5
    # the trajectory the reader keeps: from the step before the first move, raw values in the adapter's slots
    kept = trajectory["state"][:, RDT_UNIFIED_SLOTS]
    np.testing.assert_allclose(kept[:recorded - first + 1], states[first - 1:], atol=1e-6)
    assert (np.delete(trajectory["state"], RDT_UNIFIED_SLOTS, axis=1) == 0).all()
    for step_id in (first, recorded - 2):
        valid, sample = rdt_reader.parse_step(path, step_id)
        # the state and the action chunk in the adapter's unified slots: each action is the next step's
        # state; past the recording the knife holds its last state (our padding, then the reader's own)
        np.testing.assert_allclose(sample["state"][0, RDT_UNIFIED_SLOTS], states[step_id], atol=1e-6)
        ahead = states[step_id + 1:step_id + 1 + rdt_reader.CHUNK_SIZE]
        ahead = np.concatenate([ahead, np.repeat(states[-1:], rdt_reader.CHUNK_SIZE - len(ahead), axis=0)])
        np.testing.assert_allclose(sample["actions"][:, RDT_UNIFIED_SLOTS], ahead, atol=1e-6)
        assert np.flatnonzero(sample["state_indicator"]).tolist() == RDT_UNIFIED_SLOTS
        # standard RGB JPEGs: OpenCV's decode is BGR (converted as RDT's ALOHA converter does), PIL's RGB
        bgr = sample["cam_high"][-1]
        rgb = cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)
        assert np.abs(rgb.astype(int) - steps["obs/front_rgb"][step_id].astype(int)).mean() < 6.0  # quality 95
        with h5py.File(path, "r") as file:
            pil = np.asarray(Image.open(io.BytesIO(file["observations/images/front"][step_id])).convert("RGB"))
        assert np.abs(pil.astype(int) - rgb.astype(int)).max() <= 2
        assert sample["cam_right_wrist"].shape == (2, 0, 0, 0)  # no wrist camera in this dataset


def test_export_statistics(dataset):
    statistics = json.loads(Path(dataset["export"]["statistics"]).read_text())
    entry = statistics["culinarycut"]
    assert entry["num_trajectories"] == 3
    with h5py.File(dataset["export"]["robomimic"], "r") as file:
        actions = np.concatenate([file[f"data/{d}/actions"][()] for d in file["data"]])
    assert entry["num_transitions"] == len(actions)
    np.testing.assert_allclose(entry["action"]["mean"], actions.mean(0), rtol=1e-5, atol=1e-6)
    for key in ("action", "proprio"):
        assert set(entry[key]) == {"mean", "std", "min", "max", "q01", "q99", "mask"}
        assert np.all(np.asarray(entry[key]["q01"]) <= np.asarray(entry[key]["q99"]))


def test_verify_replays_and_finds_a_truncated_file(dataset, tmp_path):
    report = verify(dataset["root"], dataset["address"], replay_count=1)
    assert report.ok, report.problems
    assert report.replayed == 1
    broken = tmp_path / "broken"
    shutil.copytree(dataset["root"], broken)
    victim = sorted((broken / "episodes").glob("*.h5"))[0]
    victim.write_bytes(victim.read_bytes()[: victim.stat().st_size // 2])
    report = verify(broken, None, replay_count=0)
    assert not report.ok and any(victim.name in p for p in report.problems), report.problems


def test_same_seed_same_episode_bytes(dataset, tmp_path):
    job = make_jobs(dataset["config"])[0]
    run_job(job, dataset["config"], tmp_path, dataset["address"])
    with GenerationStore(dataset["root"]) as store:
        original = dataset["root"] / next(r["file"] for r in store.rows() if r["key"] == job.key)
    again = tmp_path / original.relative_to(dataset["root"])
    assert again.read_bytes() == original.read_bytes()


def test_episode_bytes_do_not_depend_on_when_dataset_handles_are_released(dataset, tmp_path, monkeypatch):
    """A Dask worker's profiler can keep a writer's frame, and so its h5py handles, alive: same bytes."""
    with GenerationStore(dataset["root"]) as store:
        original = dataset["root"] / next(r["file"] for r in store.rows() if r["file"])
    meta, steps = read_episode(original)
    write_episode(tmp_path / "released.h5", meta, steps)
    held = []
    create = h5py.Group.create_dataset
    monkeypatch.setattr(h5py.Group, "create_dataset", lambda *a, **k: held.append(create(*a, **k)) or held[-1])
    write_episode(tmp_path / "held.h5", meta, steps)
    assert held, "the writer did not go through h5py.Group.create_dataset"
    assert (tmp_path / "held.h5").read_bytes() == (tmp_path / "released.h5").read_bytes()


def test_dataset_card(dataset, tmp_path):
    from culinarycut.datasets.card import write_card
    card = write_card(dataset["root"], tmp_path).read_text()
    assert "3 kept trajectories of 3 generated (100 % pass the success filter)" in card
    assert "| planner/normal-ratio-0.3-cucumber | 1 | 1 |" in card
    assert "## Scenes" in card and "| kitchen |" in card and "| table |" in card
    for picture in ("card_frames.png", "card_trajectories.png"):
        image = cv2.imread(str(tmp_path / picture))
        assert image is not None and image.shape[0] > 200, picture
        assert f"]({picture})" in card


def test_a_failed_episode_is_rejected_with_its_reason(dataset, tmp_path):
    """Too few steps to finish the cut: no episode file, the row says why."""
    config = DatasetConfig(name="short", seed=3, tasks=(RATIO_SPEC,), episodes_per_task=1, image_size=SIZE,
                           max_episode_steps=15)
    row = run_job(make_jobs(config)[0], config, tmp_path, dataset["address"])
    assert row["kept"] == 0 and row["file"] is None and row["steps"] == 15
    assert row["reason"].startswith("truncated"), row["reason"]
    assert not (tmp_path / "episodes").exists()
    assert json.loads((tmp_path / "rows" / (row["key"].replace("/", "__") + ".json")).read_text()) == row


def test_scenes_and_topology_are_dataset_options(tmp_path):
    """`--scenes` narrows the draw (the other draws stay as they were) and `--topology off` makes the topology
    ablation's data; a config without them (written before they existed) reads back as the table with topology."""
    both = DatasetConfig(name="t", seed=3, tasks=(RATIO_SPEC, MIDDLE_SPEC), episodes_per_task=4)
    table = dataclasses.replace(both, scenes=("table",), topology=False)
    for drawn, narrowed in zip(make_jobs(both), make_jobs(table)):
        assert {k: v for k, v in drawn.variation.items() if k != "scene"} == \
               {k: v for k, v in narrowed.variation.items() if k != "scene"}
        assert narrowed.scene["scene"] == "table" and narrowed.scene["effects"]["topology"] is False
        assert drawn.scene["scene"] == drawn.variation["scene"] and drawn.scene["effects"]["topology"] is True
    assert {job.variation["scene"] for job in make_jobs(both)} == {"table", "kitchen"}
    old = json.loads(both.to_json())
    del old["scenes"], old["topology"]
    assert DatasetConfig.from_json(json.dumps(old)).scenes == ("table",)
    with pytest.raises(ValueError, match="moon; choose from table, kitchen"):
        dataclasses.replace(both, scenes=("moon",))
    with GenerationStore(tmp_path) as store:  # resuming with other options names what differs
        store.claim_config(both.to_json(), {})
        with pytest.raises(RuntimeError, match=r"differs in scenes, topology\); give the same options"):
            store.claim_config(table.to_json(), {})


def test_ratio_states_from_either_end():
    """`--states ratio-0.3-right` asks for the cut measured from the right end (the unseen-language and
    continuous-ratio suites hold both ends); its jobs get their own keys, and a left cut keeps the key it had."""
    from culinarycut.cli_data import _states
    states = _states("middle,ratio-0.3,ratio-0.3-left,ratio-0.3-right")
    assert [s.get("reference") for s in states] == [None, "left", "left", "right"]
    config = DatasetConfig(name="t", seed=3, tasks=tuple({"style": "normal", **s, "target_object": "cucumber"}
                                                         for s in _states("ratio-0.3,ratio-0.3-right")),
                           episodes_per_task=1)
    keys = [job.key for job in make_jobs(config)]
    assert keys == ["planner/normal-ratio-0.3-cucumber/00000", "planner/normal-ratio-0.3-right-cucumber/00000"]
    for bad in ("ratio-0.3-up", "ratio-", "ratio-x-right"):
        with pytest.raises(ValueError, match=f"--states: '{bad}' is not middle, ratio-R"):
            _states(bad)

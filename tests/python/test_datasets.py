"""A small generated dataset (two planner episodes and one replay of a demonstration on a randomised
object type), read back by readers that are not the writers: h5py for the HDF5 layouts, pyarrow's
low-level ParquetFile against the LeRobot v2.1 spec, OpenCV's decoder for the videos; verify's replay
and its detection of a truncated file; the same seed gives the same episode bytes."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import cv2
import h5py
import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from culinarycut import Client
from culinarycut.datasets.demo import load_demonstration
from culinarycut.datasets.demo_from_oracle import record_oracle_demonstration
from culinarycut.datasets.episode_file import read_episode
from culinarycut.datasets.export import export
from culinarycut.datasets.generate import generate, run_job
from culinarycut.datasets.jobs import DatasetConfig, Randomisation, draw_variation, job_scene, make_jobs
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
    assert set(meta["variation"]) == {"position_m", "yaw_deg", "scale", "food", "cut_height_m", "cut_speed_m_s"}
    assert meta["resolved_scene"]["objects"][0]["scale"] == pytest.approx(meta["variation"]["scale"])
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
        assert json.loads(data.attrs["env_args"])["env_kwargs"]["control_mode"] == "pd_ee_pose_quat"
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
        masks = {k: sorted(v.decode() for v in file[f"mask/{k}"][()]) for k in ("train", "valid")}
        assert sorted(masks["train"] + masks["valid"]) == demos and not set(masks["train"]) & set(masks["valid"])


def test_lerobot_v21_read_back(dataset):
    root = dataset["export"]["lerobot"]
    info = json.loads((root / "meta" / "info.json").read_text())
    assert info["codebase_version"] == "v2.1" and info["total_episodes"] == 3 and info["fps"] == 20.0
    episodes = [json.loads(line) for line in (root / "meta" / "episodes.jsonl").read_text().splitlines()]
    tasks = [json.loads(line) for line in (root / "meta" / "tasks.jsonl").read_text().splitlines()]
    stats = [json.loads(line) for line in (root / "meta" / "episodes_stats.jsonl").read_text().splitlines()]
    assert [e["episode_index"] for e in episodes] == [0, 1, 2] and len(stats) == 3
    assert info["total_tasks"] == len(tasks) and sorted(t["task_index"] for t in tasks) == list(range(len(tasks)))
    assert sum(e["length"] for e in episodes) == info["total_frames"]
    features = info["features"]
    video_keys = [k for k, f in features.items() if f["dtype"] == "video"]
    assert sorted(video_keys) == [f"observation.images.{c}" for c in sorted(CAMERAS)]
    for name, spec in features.items():  # LeRobot: one name per element
        if spec["dtype"] != "video":
            assert spec["names"] is None or len(spec["names"]) == spec["shape"][0], name
    assert info["contact_phases"][:3] == ["approach", "descend", "cut"]
    index_start, referenced, task_by_index = 0, set(), {t["task_index"]: t["task"] for t in tasks}
    for episode in episodes:
        chunk = episode["episode_index"] // info["chunks_size"]
        path = root / info["data_path"].format(episode_chunk=chunk, episode_index=episode["episode_index"])
        parquet = pq.ParquetFile(path)  # the low-level reader, column by column
        schema = parquet.schema_arrow
        assert parquet.metadata.num_rows == episode["length"]
        assert set(schema.names) == {k for k in features if k not in video_keys}
        for name in schema.names:
            field, spec = schema.field(name), features[name]
            if spec["shape"] == [1]:
                assert not pa.types.is_list(field.type) and not pa.types.is_fixed_size_list(field.type), name
            else:
                assert pa.types.is_fixed_size_list(field.type) and field.type.list_size == spec["shape"][0], name
                assert str(field.type.value_type) == {"float32": "float"}.get(spec["dtype"], spec["dtype"])
        assert b"huggingface" in schema.metadata
        table = parquet.read_row_group(0) if parquet.num_row_groups == 1 else parquet.read()
        assert table.column("episode_index").to_pylist() == [episode["episode_index"]] * episode["length"]
        assert table.column("frame_index").to_pylist() == list(range(episode["length"]))
        assert table.column("index").to_pylist() == list(range(index_start, index_start + episode["length"]))
        frame_tasks = [task_by_index[i] for i in table.column("task_index").to_pylist()]
        assert frame_tasks == [episode["tasks"][f % len(episode["tasks"])] for f in range(episode["length"])]
        referenced.update(frame_tasks)
        index_start += episode["length"]
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
            assert frames == episode["length"], key
        stat = stats[episode["episode_index"]]["stats"]
        assert np.asarray(stat["observation.images.front"]["mean"]).shape == (3, 1, 1)
        assert len(stat["action"]["mean"]) == features["action"]["shape"][0]
    # every instruction of every episode is a task, and frames prompt with each of them
    assert referenced == {t["task"] for t in tasks} == {t for e in episodes for t in e["tasks"]}


def test_rdt_hdf5_and_statistics(dataset):
    folders = sorted(Path(dataset["export"]["rdt"]).iterdir())
    assert len(folders) == 3
    for folder in folders:
        with h5py.File(folder / f"{folder.name}.hdf5", "r") as file:
            n = file["action"].shape[0]
            assert file["observations/qpos"].shape[0] == n
            # Our cameras, and upstream's names linked to them (front is RDT's cam_high).
            assert set(file["observations/images"].keys()) - {"cam_high", "cam_right_wrist"} == set(CAMERAS)
            assert "cam_high" in file["observations/images"]
            # RDT's reader decodes each frame's JPEG bytes with OpenCV: the recorded RGB comes back.
            jpeg = file["observations/images/cam_high"][0]
            decoded = cv2.imdecode(np.frombuffer(jpeg, np.uint8), cv2.IMREAD_COLOR)
            index = int(folder.name.split("_")[1])
            with h5py.File(dataset["export"]["robomimic"], "r") as robomimic:
                recorded = robomimic[f"data/demo_{index}/obs/front_image"][0]
            assert decoded.shape == recorded.shape
            assert np.abs(decoded.astype(int) - recorded.astype(int)).mean() < 6.0  # JPEG at quality 95
            assert file.attrs["control_frequency_hz"] == 20.0
        instructions = json.loads((folder / "expanded_instruction_gpt-4-turbo.json").read_text())
        assert instructions["instruction"] and len(instructions["expanded_instruction"]) >= 5
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


def test_dataset_card(dataset, tmp_path):
    from culinarycut.datasets.card import write_card
    card = write_card(dataset["root"], tmp_path).read_text()
    assert "3 kept trajectories of 3 generated (100 % pass the success filter)" in card
    assert "| planner/normal-ratio-0.3-cucumber | 1 | 1 |" in card
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

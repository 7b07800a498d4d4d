"""LeRobot v2.1 (the layout openpi reads through its pinned LeRobot): meta/info.json, episodes.jsonl,
tasks.jsonl, episodes_stats.jsonl; one Parquet file per episode under data/chunk-XXX/ and one MP4
per episode and camera under videos/chunk-XXX/observation.images.<camera>/.

Vectors are fixed-size float32 lists and scalars plain columns, as Hugging Face `datasets` writes
them (its feature description goes into the Parquet schema metadata under b"huggingface").
Each episode lists all its instructions as tasks, and its frames take them in turn (frame i carries
instruction i mod n), so a policy trained on the frames (openpi reads the prompt from each frame's
task_index) sees every phrasing of every episode, all through the motion. contact_phase is one integer
per frame; info.json's "contact_phases" lists the names of its codes.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from culinarycut.datasets.episodes import (PHASES, action_names, camera_names, iter_episodes, phase_codes, proprio,
                                           proprio_names, scene_conditions)

CODEBASE_VERSION = "v2.1"
CHUNKS_SIZE = 1000
DATA_PATH = "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet"
VIDEO_PATH = "videos/chunk-{episode_chunk:03d}/{video_key}/episode_{episode_index:06d}.mp4"
VIDEO_CODEC = ("mp4v", "mpeg4")  # OpenCV's fourcc, and the codec name ffprobe reports


def _write_video(path: Path, frames: np.ndarray, fps: float) -> None:
    import cv2
    path.parent.mkdir(parents=True, exist_ok=True)
    height, width = frames.shape[1:3]
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*VIDEO_CODEC[0]), fps, (width, height))
    if not writer.isOpened():
        raise RuntimeError(f"OpenCV cannot write {path} with codec {VIDEO_CODEC[0]}")
    for frame in frames:
        writer.write(np.ascontiguousarray(frame[:, :, ::-1]))
    writer.release()


def _json_fps(fps: float) -> int | float:
    """LeRobot's info.json and video info carry fps as an integer (its create_empty_dataset_info and
    get_video_info); a control rate that is not a whole number of hertz stays a float."""
    return int(fps) if float(fps).is_integer() else fps


def _vector_stats(values: np.ndarray) -> dict:
    values = values.reshape(len(values), -1).astype(np.float64)
    return {"min": values.min(0).tolist(), "max": values.max(0).tolist(), "mean": values.mean(0).tolist(),
            "std": values.std(0).tolist(), "count": [len(values)]}


def _image_stats(frames: np.ndarray) -> dict:
    """Per channel, in [0, 1], shaped (3, 1, 1) as LeRobot's compute_episode_stats gives them."""
    pixels = frames.reshape(-1, 3).astype(np.float64) / 255.0
    shape = lambda v: [[[float(x)]] for x in v]  # noqa: E731
    return {"min": shape(pixels.min(0)), "max": shape(pixels.max(0)), "mean": shape(pixels.mean(0)),
            "std": shape(pixels.std(0)), "count": [len(frames)]}


def _frame_columns(steps: dict, episode_index: int, first_index: int, task_indices: list[int], fps: float) -> dict:
    length = len(steps["actions"])
    return {
        "observation.state": proprio(steps),
        "observation.tcp_pose": steps["obs/tcp_pose"].astype(np.float32),
        "observation.wrist_wrench": steps["obs/wrist_wrench"].astype(np.float32),
        "action": steps["actions"].astype(np.float32),
        "contact_phase": phase_codes(steps).astype(np.int64),
        "knife_contact": steps["knife_contact"].astype(bool),
        "next.reward": steps["rewards"].astype(np.float32),
        "next.done": steps["dones"].astype(bool),
        "timestamp": (np.arange(length) / fps).astype(np.float32),
        "frame_index": np.arange(length, dtype=np.int64),
        "episode_index": np.full(length, episode_index, dtype=np.int64),
        "index": np.arange(first_index, first_index + length, dtype=np.int64),
        "task_index": np.resize(np.asarray(task_indices, dtype=np.int64), length),  # in turn, frame by frame
    }


def _features(columns: dict, steps: dict, control_mode: str, image_size: tuple, fps: float) -> dict:
    features = {}
    for name, values in columns.items():
        dtype = "bool" if values.dtype == bool else str(values.dtype)
        shape = list(values.shape[1:]) or [1]
        features[name] = {"dtype": dtype, "shape": shape, "names": None}
    features["observation.state"]["names"] = proprio_names(steps)
    features["observation.tcp_pose"]["names"] = ["x_m", "y_m", "z_m", "qw", "qx", "qy", "qz"]
    features["observation.wrist_wrench"]["names"] = ["fx_n", "fy_n", "fz_n", "tx_nm", "ty_nm", "tz_nm"]
    features["action"]["names"] = action_names(control_mode, columns["action"].shape[1])
    features["contact_phase"]["names"] = ["contact_phase"]  # one code per frame; info["contact_phases"] names them
    height, width = image_size
    for camera in camera_names(steps):
        features[f"observation.images.{camera}"] = {
            "dtype": "video", "shape": [height, width, 3], "names": ["height", "width", "channels"],
            "info": {"video.fps": _json_fps(fps), "video.height": height, "video.width": width, "video.channels": 3,
                     "video.codec": VIDEO_CODEC[1], "video.pix_fmt": "yuv420p", "video.is_depth_map": False,
                     "has_audio": False}}
    return features


def _hf_features(columns: dict) -> dict:
    """The `datasets` library's description of the Parquet columns."""
    described = {}
    for name, values in columns.items():
        value = {"dtype": "bool" if values.dtype == bool else str(values.dtype), "_type": "Value"}
        described[name] = value if values.ndim == 1 else {"feature": value, "length": int(values.shape[1]),
                                                          "_type": "Sequence"}
    return described


def _write_parquet(path: Path, columns: dict) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq
    arrays, fields = [], []
    for name, values in columns.items():
        if values.ndim == 1:
            array = pa.array(values)
        else:
            array = pa.FixedSizeListArray.from_arrays(pa.array(values.reshape(-1)), values.shape[1])
        arrays.append(array)
        fields.append(pa.field(name, array.type))
    metadata = {b"huggingface": json.dumps({"info": {"features": _hf_features(columns)}}).encode()}
    table = pa.Table.from_arrays(arrays, schema=pa.schema(fields, metadata=metadata))
    path.parent.mkdir(parents=True, exist_ok=True)
    pq.write_table(table, path)


def export_lerobot(root: Path, out: Path, robot_type: str = "panda") -> Path:
    out.mkdir(parents=True, exist_ok=True)
    (out / "meta").mkdir(exist_ok=True)
    tasks: dict[str, int] = {}
    episodes, stats, total_frames, info_features, fps = [], [], 0, None, None
    for index, meta, steps in iter_episodes(root):
        fps = float(meta["resolved_scene"]["robot"]["control_frequency_hz"])
        for instruction in meta["instructions"]:
            tasks.setdefault(instruction, len(tasks))
        columns = _frame_columns(steps, index, total_frames, [tasks[t] for t in meta["instructions"]], fps)
        chunk = index // CHUNKS_SIZE
        _write_parquet(out / DATA_PATH.format(episode_chunk=chunk, episode_index=index), columns)
        episode_stats = {name: _vector_stats(values) for name, values in columns.items()}
        for camera in camera_names(steps):
            frames = steps[f"obs/{camera}_rgb"]
            key = f"observation.images.{camera}"
            _write_video(out / VIDEO_PATH.format(episode_chunk=chunk, video_key=key, episode_index=index), frames, fps)
            episode_stats[key] = _image_stats(frames)
        if info_features is None:
            first_camera = camera_names(steps)[0]
            size = steps[f"obs/{first_camera}_rgb"].shape[1:3]
            info_features = _features(columns, steps, meta["control_mode"], size, fps)
        length = len(columns["index"])
        episodes.append({"episode_index": index, "tasks": list(meta["instructions"]), "length": length,
                         "cut_spec": meta["cut_spec"], "seed": meta["seed"], "source": meta["source"],
                         **scene_conditions(meta)})
        stats.append({"episode_index": index, "stats": episode_stats})
        total_frames += length
    if not episodes:
        raise ValueError(f"{root}: no kept episodes to export")
    cameras = sum(1 for f in info_features.values() if f["dtype"] == "video")
    info = {"codebase_version": CODEBASE_VERSION, "robot_type": robot_type, "total_episodes": len(episodes),
            "total_frames": total_frames, "total_tasks": len(tasks), "total_videos": len(episodes) * cameras,
            "total_chunks": (len(episodes) - 1) // CHUNKS_SIZE + 1, "chunks_size": CHUNKS_SIZE,
            "fps": _json_fps(fps),
            "splits": {"train": f"0:{len(episodes)}"}, "data_path": DATA_PATH, "video_path": VIDEO_PATH,
            "features": info_features, "contact_phases": list(PHASES)}
    (out / "meta" / "info.json").write_text(json.dumps(info, indent=4))
    _write_jsonl(out / "meta" / "episodes.jsonl", episodes)
    _write_jsonl(out / "meta" / "tasks.jsonl", [{"task_index": i, "task": t} for t, i in tasks.items()])
    _write_jsonl(out / "meta" / "episodes_stats.jsonl", stats)
    return out


def _write_jsonl(path: Path, rows: list[dict]) -> None:
    path.write_text("".join(json.dumps(row) + "\n" for row in rows))

"""The HDF5 layout RDT fine-tunes from with its generic reader (data/hdf5_vla_dataset.py, HDF5VLADataset):
one file per episode, its instructions beside it in the file that reader opens (instruction,
simplified_instruction, expanded_instruction), the control frequency in the file's attrs.

- `observations/qpos` and `action` are in one layout, as the reader fills both into RDT's unified vector
  with one index list: the RDT adapter's 16 values (adapter_layouts.py: 7 joints (rad), TCP xyz (m), 6-D
  rotation), their unified indices in the file's attr `unified_indices`, names in `state_names`. `action`
  is the state after each step (what RDT predicts; the adapter executes it). Raw SI values: the reader
  normalises nothing, nor does the adapter by default.
- The reader drops episodes shorter than 128 steps; shorter ones are padded to 128 by repeating their
  last step (the robot holding still), and attr `recorded_steps` says how many steps were recorded.
- Images: one standard (RGB) JPEG per frame in a fixed-length byte-string dataset, under our camera
  names, with upstream's names linked to them (`cam_high` the front camera, `cam_right_wrist` the wrist:
  a single arm takes the right arm's slots). The reader's cv2.imdecode returns them as BGR (see
  docs/datasets.md for the conversion).
- Also kept: the recorded control-mode actions (`recorded_actions`), the robot's own joint state
  (`observations/joint_qpos`, `observations/qvel`), TCP pose, wrist wrench, contact phase.
"""
from __future__ import annotations

import json
from pathlib import Path

import cv2
import h5py
import numpy as np

from culinarycut.datasets.adapter_layouts import RDT_STATE_NAMES, RDT_UNIFIED_SLOTS, rdt_actions, rdt_states
from culinarycut.datasets.episodes import camera_names, iter_episodes, phase_codes, scene_conditions

INSTRUCTION_FILE = "expanded_instruction_gpt-4-turbo.json"
UPSTREAM_CAMERA_NAMES = {"front": "cam_high", "wrist": "cam_right_wrist"}
JPEG_QUALITY = 95
MIN_STEPS = 128  # data/hdf5_vla_dataset.py: `if num_steps < 128: return False, None`


def jpeg_frames(frames: np.ndarray) -> np.ndarray:
    """(T, H, W, 3) RGB uint8 -> T standard JPEGs as fixed-length byte strings (zero-padded, which decoders
    ignore); OpenCV encodes BGR, so the channels are swapped first."""
    encoded = []
    for frame in frames:
        ok, data = cv2.imencode(".jpg", cv2.cvtColor(np.ascontiguousarray(frame), cv2.COLOR_RGB2BGR),
                                [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
        if not ok:
            raise RuntimeError("OpenCV could not JPEG-encode a camera frame")
        encoded.append(data.tobytes())
    width = max(len(data) for data in encoded)
    return np.array(encoded, dtype=f"S{width}")


def pad_steps(values: np.ndarray, steps: int) -> np.ndarray:
    """`values` (T, ...) with its last row repeated up to `steps` rows."""
    missing = steps - len(values)
    return values if missing <= 0 else np.concatenate([values, np.repeat(values[-1:], missing, axis=0)])


def export_rdt(root: Path, out: Path, min_steps: int = MIN_STEPS) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    count = 0
    for index, meta, steps in iter_episodes(root):
        folder = out / f"episode_{index:06d}"
        folder.mkdir(exist_ok=True)
        recorded = len(steps["actions"])
        per_step = {"action": rdt_actions(steps), "observations/qpos": rdt_states(steps),
                    "recorded_actions": steps["actions"], "observations/joint_qpos": steps["obs/qpos"],
                    "observations/qvel": steps["obs/qvel"], "observations/eef_pose": steps["obs/tcp_pose"],
                    "observations/wrist_wrench": steps["obs/wrist_wrench"],
                    "observations/contact_phase": phase_codes(steps)}
        with h5py.File(folder / f"episode_{index:06d}.hdf5", "w") as file:
            for name, values in per_step.items():
                file.create_dataset(name, data=pad_steps(np.asarray(values), min_steps))
            for camera in camera_names(steps):
                frames = jpeg_frames(steps[f"obs/{camera}_rgb"])
                file.create_dataset(f"observations/images/{camera}", data=pad_steps(frames, min_steps))
                if camera in UPSTREAM_CAMERA_NAMES:
                    file[f"observations/images/{UPSTREAM_CAMERA_NAMES[camera]}"] = h5py.SoftLink(
                        f"/observations/images/{camera}")
            file.attrs["unified_indices"] = RDT_UNIFIED_SLOTS
            file.attrs["state_names"] = RDT_STATE_NAMES
            file.attrs["recorded_steps"] = recorded
            file.attrs["control_mode"] = meta["control_mode"]
            file.attrs["control_frequency_hz"] = meta["resolved_scene"]["robot"]["control_frequency_hz"]
            file.attrs["cut_spec"] = json.dumps(meta["cut_spec"], sort_keys=True)
            file.attrs["seed"] = meta["seed"]
            conditions = scene_conditions(meta)
            file.attrs["scene"] = conditions["scene"]
            file.attrs["topology"] = conditions["topology"]
        instructions = meta["instructions"]
        (folder / INSTRUCTION_FILE).write_text(json.dumps(
            {"instruction": instructions[0], "simplified_instruction": instructions[1:2],
             "expanded_instruction": instructions}, indent=2))
        count += 1
    if not count:
        raise ValueError(f"{root}: no kept episodes to export")
    return out

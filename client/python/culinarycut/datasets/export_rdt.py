"""The HDF5 layout RDT fine-tunes from (its ALOHA/agilex episodes): one file per episode with
`action`, `observations/qpos`, `observations/images/<camera>`, plus the TCP pose, wrist wrench and
contact phase; the episode's instructions beside it in the file RDT's HDF5VLADataset reads
(instruction, simplified_instruction, expanded_instruction) and the control frequency in the file's attrs.

Images are stored as RDT's reader decodes them: one JPEG per frame in a fixed-length byte-string dataset
(its HDF5VLADataset runs cv2.imdecode on each), under our camera names, with upstream's names as links to
them: `cam_high` the front camera and `cam_right_wrist` the wrist camera (a single arm takes the right arm's
slots, as the RDT adapter sends it). The bytes decode with OpenCV to the recorded RGB channel order."""
from __future__ import annotations

import json
from pathlib import Path

import cv2
import h5py
import numpy as np

from culinarycut.datasets.episodes import camera_names, iter_episodes, phase_codes, scene_conditions

INSTRUCTION_FILE = "expanded_instruction_gpt-4-turbo.json"
UPSTREAM_CAMERA_NAMES = {"front": "cam_high", "wrist": "cam_right_wrist"}
JPEG_QUALITY = 95


def jpeg_frames(frames: np.ndarray) -> np.ndarray:
    """(T, H, W, 3) uint8 -> T JPEGs as fixed-length byte strings (zero-padded, which decoders ignore)."""
    encoded = []
    for frame in frames:
        ok, data = cv2.imencode(".jpg", np.ascontiguousarray(frame), [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
        if not ok:
            raise RuntimeError("OpenCV could not JPEG-encode a camera frame")
        encoded.append(data.tobytes())
    width = max(len(data) for data in encoded)
    return np.array(encoded, dtype=f"S{width}")


def export_rdt(root: Path, out: Path) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    count = 0
    for index, meta, steps in iter_episodes(root):
        folder = out / f"episode_{index:06d}"
        folder.mkdir(exist_ok=True)
        with h5py.File(folder / f"episode_{index:06d}.hdf5", "w") as file:
            file.create_dataset("action", data=steps["actions"])
            file.create_dataset("observations/qpos", data=steps["obs/qpos"])
            file.create_dataset("observations/qvel", data=steps["obs/qvel"])
            file.create_dataset("observations/eef_pose", data=steps["obs/tcp_pose"])
            file.create_dataset("observations/wrist_wrench", data=steps["obs/wrist_wrench"])
            file.create_dataset("observations/contact_phase", data=phase_codes(steps))
            for camera in camera_names(steps):
                file.create_dataset(f"observations/images/{camera}", data=jpeg_frames(steps[f"obs/{camera}_rgb"]))
                if camera in UPSTREAM_CAMERA_NAMES:
                    file[f"observations/images/{UPSTREAM_CAMERA_NAMES[camera]}"] = h5py.SoftLink(
                        f"/observations/images/{camera}")
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

"""The HDF5 layout RDT fine-tunes from (its ALOHA/agilex episodes): one file per episode with
`action`, `observations/qpos`, `observations/images/<camera>`, plus the TCP pose, wrist wrench and
contact phase; the episode's instructions beside it in the file RDT's HDF5VLADataset reads
(instruction, simplified_instruction, expanded_instruction) and the control frequency in the file's attrs."""
from __future__ import annotations

import json
from pathlib import Path

import h5py

from culinarycut.datasets.episodes import camera_names, iter_episodes, phase_codes

INSTRUCTION_FILE = "expanded_instruction_gpt-4-turbo.json"


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
                file.create_dataset(f"observations/images/{camera}", data=steps[f"obs/{camera}_rgb"])
            file.attrs["control_mode"] = meta["control_mode"]
            file.attrs["control_frequency_hz"] = meta["resolved_scene"]["robot"]["control_frequency_hz"]
            file.attrs["cut_spec"] = json.dumps(meta["cut_spec"], sort_keys=True)
            file.attrs["seed"] = meta["seed"]
        instructions = meta["instructions"]
        (folder / INSTRUCTION_FILE).write_text(json.dumps(
            {"instruction": instructions[0], "simplified_instruction": instructions[1:2],
             "expanded_instruction": instructions}, indent=2))
        count += 1
    if not count:
        raise ValueError(f"{root}: no kept episodes to export")
    return out

"""RDT's generic HDF5 fine-tuning reader, reproduced from data/hdf5_vla_dataset.py (HDF5VLADataset) of
thu-ml/RoboticsDiffusionTransformer so the tests read our export as RDT would. Its [Modify] points take our
values: the unified indices from the file's attr (its UNI_STATE_INDICES), no ALOHA gripper rescale, a
camera the robot lacks as (IMG_HISTORY_SIZE, 0, 0, 0) as its comments ask, and the step given instead of
drawn at random."""
from __future__ import annotations

from pathlib import Path

import cv2
import h5py
import numpy as np

STATE_DIM = 128        # configs/base.yaml common.state_dim
CHUNK_SIZE = 64        # common.action_chunk_size
IMG_HISTORY_SIZE = 2   # common.img_history_size
MIN_STEPS = 128        # "We drop too-short episode"
EPS = 1e-2             # "We skip the first few still steps"


def fill_in_state(values: np.ndarray, indices: list[int]) -> np.ndarray:
    unified = np.zeros(values.shape[:-1] + (STATE_DIM,))
    unified[..., indices] = values
    return unified


def first_moving_step(qpos: np.ndarray) -> int:
    moving = np.where(np.any(np.abs(qpos - qpos[0:1]) > EPS, axis=1))[0]
    if len(moving) == 0:
        raise ValueError("Found no qpos that exceeds the threshold.")
    return int(moving[0])


def parse_state_only(path: Path):
    """parse_hdf5_file_state_only: (valid, {"state", "action"} from the step before the first move)."""
    with h5py.File(path, "r") as f:
        qpos = f["observations"]["qpos"][:]
        if qpos.shape[0] < MIN_STEPS:
            return False, None
        first = first_moving_step(qpos)
        indices = list(f.attrs["unified_indices"])
        return True, {"state": fill_in_state(qpos[first - 1:], indices),
                      "action": fill_in_state(f["action"][first - 1:], indices)}


def parse_step(path: Path, step_id: int):
    """parse_hdf5_file at `step_id`: the state, the action chunk (padded with its last), the camera history
    decoded with cv2.imdecode as the reader does (first image repeated before the episode starts)."""
    with h5py.File(path, "r") as f:
        qpos = f["observations"]["qpos"][:]
        if qpos.shape[0] < MIN_STEPS:
            return False, None
        indices = list(f.attrs["unified_indices"])
        actions = f["action"][step_id:step_id + CHUNK_SIZE]
        if actions.shape[0] < CHUNK_SIZE:
            actions = np.concatenate([actions, np.tile(actions[-1:], (CHUNK_SIZE - actions.shape[0], 1))])

        def parse_img(key):
            if key not in f["observations"]["images"]:
                return np.zeros((IMG_HISTORY_SIZE, 0, 0, 0))
            imgs = [cv2.imdecode(np.frombuffer(f["observations"]["images"][key][i], np.uint8), cv2.IMREAD_COLOR)
                    for i in range(max(step_id - IMG_HISTORY_SIZE + 1, 0), step_id + 1)]
            imgs = np.stack(imgs)
            if imgs.shape[0] < IMG_HISTORY_SIZE:
                imgs = np.concatenate([np.tile(imgs[:1], (IMG_HISTORY_SIZE - imgs.shape[0], 1, 1, 1)), imgs])
            return imgs

        return True, {"state": fill_in_state(qpos[step_id:step_id + 1], indices),
                      "actions": fill_in_state(actions, indices),
                      "state_indicator": fill_in_state(np.ones(qpos.shape[1]), indices),
                      "cam_high": parse_img("cam_high"), "cam_left_wrist": parse_img("cam_left_wrist"),
                      "cam_right_wrist": parse_img("cam_right_wrist")}

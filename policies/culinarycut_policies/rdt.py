"""RDT-1B through an openpi-protocol server (policies/servers/serve_rdt.py).

Sent per query: six images in RDT's order [ext_{t-1}, right_wrist_{t-1}, left_wrist_{t-1}, ext_t,
right_wrist_t, left_wrist_t] (None where a camera is missing, and for t-1 at the first step, as
scripts/agilex_inference.py starts its window), each padded square and resized to 384; the state in
the 128-D unified vector (configs/state_vec.py; the single arm in the right-arm slots) with its mask,
normalised with the statistics' proprio min/max as scripts/maniskill_model.py does; the control
frequency; the language as precomputed T5-XXL embeddings (1, L, 4096), or the instruction text when no
embeddings file is given (the server must then encode it). The answer is (1, 64, 128): 64 future absolute
states, un-normalised with the action min/max; their end-effector pose is executed as pd_ee_pose_quat,
open loop, before the next query.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from culinarycut_policies.actions import pose_to_ee_pose_quat, tcp_pose
from culinarycut_policies.chunking import OpenLoopChunks
from culinarycut_policies.images import camera_rgb, pad_square_resize
from culinarycut_policies.remote_policy import DEFAULT_CAMERA_SIZE, RemotePolicy
from culinarycut_policies.rotation import matrix_to_ortho6d, ortho6d_to_matrix, quat_wxyz_to_matrix
from culinarycut_policies.statistics import StatisticsError, load_statistics, normalize_bounds, unnormalize_bounds
from culinarycut_policies.transports.faults import PolicyServerError
from culinarycut_policies.transports.openpi_websocket import OpenPIWebsocketClient

UNIFIED_DIM = 128
IMAGE_SIZE = 384
CHUNK_STEPS = 64
CONTROL_FREQUENCY_HZ = 25.0  # RDT's own robot; CulinaryCut's rate comes from the episode
# Our 16 values in the unified vector: Panda joints 0-6 (right_arm_joint_i_pos), the TCP position
# (right_eef_pos_x..z, 30-32) and its 6-D rotation (right_eef_angle_0..5, 33-38). Slot 10 (right gripper)
# stays out of the mask: the knife has none.
JOINT_SLOTS = list(range(7))
EEF_POSITION_SLOTS = [30, 31, 32]
EEF_ROTATION_SLOTS = list(range(33, 39))
STATE_SLOTS = JOINT_SLOTS + EEF_POSITION_SLOTS + EEF_ROTATION_SLOTS


def robot_state(observation: dict) -> np.ndarray:
    """The 16 values of STATE_SLOTS in SI units: joints (rad), TCP position (m), 6-D rotation."""
    position, quaternion = tcp_pose(observation)
    joints = np.asarray(observation["agent"]["qpos"], dtype=np.float64)[:7]
    return np.concatenate([joints, position, matrix_to_ortho6d(quat_wxyz_to_matrix(quaternion))])


def to_unified(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(state (1, 1, 128), state_elem_mask (1, 128)) as _format_joint_to_state builds them."""
    state = np.zeros((1, 1, UNIFIED_DIM), dtype=np.float32)
    state[0, 0, STATE_SLOTS] = values
    mask = np.zeros((1, UNIFIED_DIM), dtype=np.float32)
    mask[0, STATE_SLOTS] = 1.0
    return state, mask


def load_embeddings(path: str | None) -> dict[str, np.ndarray]:
    """instruction -> (L, 4096) float from an .npz (scripts/encode_lang.py's output, one array per text)."""
    if not path:
        return {}
    try:
        with np.load(Path(path), allow_pickle=False) as archive:
            return {key: archive[key] for key in archive.files}
    except (OSError, ValueError) as err:
        raise ValueError(f"policy rdt: option language_embeddings={path}: {err}") from None


class RDTPolicy(RemotePolicy):
    name = "rdt"
    model_family = "rdt"
    version = "1"
    control_mode = "pd_ee_pose_quat"

    def __init__(self, url: str = "ws://127.0.0.1:8000", statistics: str | None = None,
                 unnorm_key: str | None = None, camera: str = "front", wrist_camera: str | None = "wrist",
                 camera_size: int = DEFAULT_CAMERA_SIZE, execute_steps: int = CHUNK_STEPS,
                 control_frequency: float | None = None, language_embeddings: str | None = None,
                 api_key: str | None = None, **transport):
        super().__init__(url=url, **transport)
        self.stats = load_statistics(statistics, unnorm_key, policy=self.name)
        if self.stats.proprio is None:
            raise StatisticsError(f"policy rdt: the statistics of {self.stats.key!r} have no 'proprio'")
        for what, entry in (("proprio", self.stats.proprio), ("action", self.stats.action)):
            if entry.dim != len(STATE_SLOTS):
                raise StatisticsError(f"policy rdt: {what} statistics of {self.stats.key!r} have {entry.dim} values; "
                                      f"RDT's layout here has {len(STATE_SLOTS)} (7 joints, TCP xyz, 6-D rotation)")
        self.use_cameras(camera, wrist_camera, camera_size)
        self.chunks = OpenLoopChunks(int(execute_steps))
        self.fixed_frequency = None if control_frequency is None else float(control_frequency)
        self.control_frequency = self.fixed_frequency or CONTROL_FREQUENCY_HZ
        self.embeddings = load_embeddings(language_embeddings)
        self.previous_images: list = [None, None, None]
        self.transport = OpenPIWebsocketClient(self.url, self.timeouts, api_key=api_key)

    def reset(self, instruction, info):
        if self.embeddings and instruction not in self.embeddings:
            raise KeyError(f"policy rdt: no language embedding for {instruction!r} in option language_embeddings "
                           f"({len(self.embeddings)} instructions); encode it with scripts/encode_lang.py")
        self.chunks.reset()
        self.previous_images = [None, None, None]
        if self.fixed_frequency is None and info.get("control_frequency_hz"):
            self.control_frequency = float(info["control_frequency_hz"])
        super().reset(instruction, info)

    def images(self, observation: dict) -> list:
        current = [pad_square_resize(camera_rgb(observation, self.camera), IMAGE_SIZE),
                   pad_square_resize(camera_rgb(observation, self.wrist_camera), IMAGE_SIZE)
                   if self.wrist_camera else None,
                   None]  # left wrist: a single arm has none
        six = self.previous_images + current
        self.previous_images = current
        return six

    def request(self, observation: dict) -> dict:
        state, mask = to_unified(normalize_bounds(robot_state(observation), self.stats.proprio))
        request = {"images": self.images(observation), "state": state, "state_elem_mask": mask,
                   "ctrl_freq": np.float32(self.control_frequency)}
        if self.embeddings:
            request["text_embeds"] = self.embeddings[self.instruction].astype(np.float32)[None]
        else:
            request["instruction"] = self.instruction
        return request

    def act(self, observation):
        if self.chunks.needs_chunk:
            reply = self.transport.infer(self.request(observation))
            actions = np.asarray(reply.get("actions"))
            if actions.shape[:1] != (1,) or actions.ndim != 3 or actions.shape[2] != UNIFIED_DIM:
                raise PolicyServerError(f"policy rdt: expected actions (1, H, {UNIFIED_DIM}) from {self.url}, "
                                        f"got {actions.shape}")
            self.chunks.add(unnormalize_bounds(actions[0][:, STATE_SLOTS], self.stats.action))
        else:
            self.images(observation)  # keeps the t-1 images current while the chunk runs
        target = self.chunks.next()
        position = target[len(JOINT_SLOTS):len(JOINT_SLOTS) + 3]
        rotation = ortho6d_to_matrix(target[len(JOINT_SLOTS) + 3:])
        return pose_to_ee_pose_quat(position, rotation)

"""RDT-1B through an openpi-protocol server (policies/servers/serve_rdt.py).

Sent per query: six images in RDT's order [ext_{t-1}, right_wrist_{t-1}, left_wrist_{t-1}, ext_t,
right_wrist_t, left_wrist_t] (None where a camera is missing, and for t-1 at the first step, as
scripts/agilex_inference.py starts its window), each JPEG round-tripped as that script's jpeg_mapping
does, then padded square and resized to 384 (the raw frames are kept between queries and processed
only when a query is made); the state in
the 128-D unified vector (configs/state_vec.py; the single arm in the right-arm slots) with its mask,
in raw SI values as RDT's HDF5 fine-tune trains on them, or min/max-scaled as its ManiSkill fine-tune
(option normalization: rdt_normalization.py); the control frequency; the language as precomputed T5-XXL embeddings (1, L, 4096) (rdt_language.py reads
scripts/encode_lang.py's .pt files), or the instruction text when no embeddings are given (the server
must then encode it). The answer is (1, 64, 128): 64 future absolute states (un-normalised with the
action min/max under normalization=bounds); their end-effector pose is executed as pd_ee_pose_quat, open
loop, before the next query.
"""
from __future__ import annotations

import numpy as np
from culinarycut.datasets.adapter_layouts import RDT_UNIFIED_SLOTS

from culinarycut_policies.actions import pose_to_ee_pose_quat, tcp_pose
from culinarycut_policies.chunking import OpenLoopChunks
from culinarycut_policies.images import camera_rgb, jpeg_roundtrip, pad_square_resize
from culinarycut_policies.rdt_language import load_embeddings
from culinarycut_policies.rdt_normalization import RDTNormalization
from culinarycut_policies.remote_policy import DEFAULT_CAMERA_SIZE, RemotePolicy
from culinarycut_policies.rotation import matrix_to_ortho6d, ortho6d_to_matrix, quat_wxyz_to_matrix
from culinarycut_policies.transports.faults import PolicyServerError
from culinarycut_policies.transports.openpi_websocket import OpenPIWebsocketClient

UNIFIED_DIM = 128
IMAGE_SIZE = 384
CHUNK_STEPS = 64
CONTROL_FREQUENCY_HZ = 25.0  # RDT's own robot; CulinaryCut's rate comes from the episode
# Our 16 values in the unified vector (the export's layout): Panda joints, TCP position, 6-D rotation.
STATE_SLOTS = RDT_UNIFIED_SLOTS
JOINTS = 7


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


def rdt_image(rgb: np.ndarray | None) -> np.ndarray | None:
    """One camera frame as RDT saw it: agilex_inference.py's jpeg_mapping (its training frames were JPEG),
    then agilex_model.py's expand2square and SigLIP's resize to 384."""
    return None if rgb is None else pad_square_resize(jpeg_roundtrip(rgb), IMAGE_SIZE)


class RDTPolicy(RemotePolicy):
    name = "rdt"
    model_family = "rdt"
    version = "1"
    control_mode = "pd_ee_pose_quat"

    def __init__(self, url: str = "ws://127.0.0.1:8000", statistics: str | None = None,
                 unnorm_key: str | None = None, camera: str = "front", wrist_camera: str | None = "wrist",
                 camera_size: int = DEFAULT_CAMERA_SIZE, execute_steps: int = CHUNK_STEPS,
                 control_frequency: float | None = None, language_embeddings: str | None = None,
                 normalization: str = "none", api_key: str | None = None, **transport):
        super().__init__(url=url, **transport)
        self.normalization = RDTNormalization(normalization, statistics, unnorm_key)
        self.use_cameras(camera, wrist_camera, camera_size)
        self.chunks = OpenLoopChunks(int(execute_steps))
        self.fixed_frequency = None if control_frequency is None else float(control_frequency)
        self.control_frequency = self.fixed_frequency or CONTROL_FREQUENCY_HZ
        self.embeddings = load_embeddings(language_embeddings)
        self.previous_frames: list = [None, None, None]  # raw RGB of t-1, processed only when a query is made
        self.transport = OpenPIWebsocketClient(self.url, self.timeouts, api_key=api_key)

    def reset(self, instruction, info):
        if self.embeddings and instruction not in self.embeddings:
            raise KeyError(f"policy rdt: no language embedding for {instruction!r} in option language_embeddings "
                           f"({len(self.embeddings)} instructions); encode it with RDT's scripts/encode_lang.py")
        self.chunks.reset()
        self.previous_frames = [None, None, None]
        if self.fixed_frequency is None and info.get("control_frequency_hz"):
            self.control_frequency = float(info["control_frequency_hz"])
        super().reset(instruction, info)

    def check_metadata(self, metadata: dict) -> None:
        """The server's chunk must hold the steps executed from it (serve_rdt.py: action_chunk_size)."""
        horizon = metadata.get("action_horizon")
        if horizon is not None and self.chunks.execute_steps > int(horizon):
            raise PolicyServerError(f"policy rdt: option execute_steps={self.chunks.execute_steps} exceeds the "
                                    f"action_horizon {horizon} of the model at {self.url}; set execute_steps<={horizon}")

    def frames(self, observation: dict) -> list:
        """This step's raw frames [ext, right wrist, left wrist (a single arm has none)]."""
        return [camera_rgb(observation, self.camera),
                camera_rgb(observation, self.wrist_camera) if self.wrist_camera else None, None]

    def images(self, observation: dict) -> list:
        """The six processed images of a query; this step's frames become the next query's t-1."""
        current = self.frames(observation)
        six = [rdt_image(frame) for frame in self.previous_frames + current]
        self.previous_frames = current
        return six

    def request(self, observation: dict) -> dict:
        state, mask = to_unified(self.normalization.state(robot_state(observation)))
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
            self.chunks.add(self.normalization.action(actions[0][:, STATE_SLOTS]))
        else:
            self.previous_frames = self.frames(observation)  # the t-1 frames of the next query
        target = self.chunks.next()
        position = target[JOINTS:JOINTS + 3]
        rotation = ortho6d_to_matrix(target[JOINTS + 3:])
        return pose_to_ee_pose_quat(position, rotation)

"""OpenVLA-OFT through its REST server (openvla-oft vla-scripts/deploy.py): `full_image` and `wrist_image`
JPEG round-tripped and resized to 224 x 224 as its LIBERO client does (resize_image_for_policy; the
server centre-crops when it was trained with crops), `state` (the knife's position and rotation
vector, gripper slots 0: see actions.py) and `instruction`; the server normalises the state and
un-normalises the answer with its `unnorm_key`, and answers a chunk of actions (8 for LIBERO) that is
executed open loop before the next query."""
from __future__ import annotations

import numpy as np

from culinarycut_policies.actions import (delta_to_ee_delta_pose, load_delta_ee_statistics, pad_state,
                                          resolve_rotation_delta, tcp_position_axis_angle)
from culinarycut_policies.chunking import OpenLoopChunks
from culinarycut_policies.control_rate import ModelRate
from culinarycut_policies.images import camera_rgb
from culinarycut_policies.openvla import openvla_image
from culinarycut_policies.remote_policy import DEFAULT_CAMERA_SIZE, RemotePolicy
from culinarycut_policies.statistics import StatisticsError
from culinarycut_policies.transports.faults import PolicyServerError
from culinarycut_policies.transports.json_numpy_rest import JsonNumpyRestClient

CHUNK_STEPS = 8  # prismatic/vla/constants.py NUM_ACTIONS_CHUNK for LIBERO; num_open_loop_steps in its eval


class OpenVLAOFTPolicy(RemotePolicy):
    name = "openvla-oft"
    version = "1"
    control_mode = "pd_ee_delta_pose"

    def __init__(self, url: str = "http://127.0.0.1:8777", statistics: str | None = None,
                 unnorm_key: str | None = None, camera: str = "front", wrist_camera: str | None = "wrist",
                 camera_size: int = DEFAULT_CAMERA_SIZE, execute_steps: int = CHUNK_STEPS,
                 action_units: str | None = None, model_rate_hz: float | None = None,
                 rotation_delta: str | None = None, **transport):
        super().__init__(url=url, **transport)
        self.stats, self.action_units = load_delta_ee_statistics(statistics, unnorm_key, action_units,
                                                                 policy=self.name, proprio=True)
        self.rotation_delta = resolve_rotation_delta(rotation_delta, self.action_units, self.name)
        if self.stats.proprio is None:
            raise StatisticsError(f"policy {self.name!r}: the statistics of {self.stats.key!r} have no 'proprio'; "
                                  "OpenVLA-OFT normalises its `state` with them")
        self.rate = ModelRate(model_rate_hz, self.stats.key, self.name)
        self.use_cameras(camera, wrist_camera, camera_size)
        self.chunks = OpenLoopChunks(execute_steps)
        self.transport = JsonNumpyRestClient(self.url, self.timeouts)

    def reset(self, instruction, info):
        self.chunks.reset()
        self.rate.reset(info)
        super().reset(instruction, info)

    def request(self, observation: dict) -> dict:
        """run_libero_eval's observation: images already 224 x 224, the raw (un-normalised) state."""
        payload = {"full_image": openvla_image(camera_rgb(observation, self.camera), center_crop=False)}
        if self.wrist_camera:
            payload["wrist_image"] = openvla_image(camera_rgb(observation, self.wrist_camera), center_crop=False)
        payload["state"] = pad_state(tcp_position_axis_angle(observation), self.stats.proprio.dim)
        payload["instruction"] = self.instruction
        return payload

    def act(self, observation):
        return self.rate.execute(self.model_action, observation)

    def model_action(self, observation):
        if self.chunks.needs_chunk:
            reply = self.transport.query(self.request(observation))
            chunk = np.asarray(reply, dtype=np.float64)
            if chunk.ndim != 2 or chunk.shape[1] != self.stats.action.dim:
                raise PolicyServerError(f"OpenVLA-OFT server answered shape {chunk.shape}; expected a list of "
                                        f"{self.stats.action.dim}-D actions (the statistics of {self.stats.key!r})")
            self.chunks.add(chunk)
        return delta_to_ee_delta_pose(self.chunks.next(), self.action_units, self.rotation_delta)

"""Any openpi policy server (pi0, pi0-FAST, pi0.5: scripts/serve_policy.py) in the layout of openpi's
LIBERO example (examples/libero/main.py): `observation/image` and `observation/wrist_image` resized with
pad to 224, `observation/state`, `prompt`; the answer's `actions` (H, D) is executed `replan_steps` at a
time (5 in the example). openpi servers normalise and un-normalise with the statistics stored in their
own checkpoint, so this adapter takes none; the actions are delta end-effector actions in option
`action_units`: by default robosuite's OSC units (1 = 0.05 m / 0.5 rad), what LIBERO-trained checkpoints
(pi0_libero, pi05_libero) answer; `metres_radians` for a model trained on CulinaryCut's delta layout
(gripper: see actions.py)."""
from __future__ import annotations

import numpy as np

from culinarycut_policies.actions import (delta_to_ee_delta_pose, pad_state, resolve_action_units,
                                          resolve_rotation_delta, tcp_position_axis_angle)
from culinarycut_policies.chunking import OpenLoopChunks
from culinarycut_policies.control_rate import ModelRate
from culinarycut_policies.images import camera_rgb, resize_with_pad
from culinarycut_policies.remote_policy import DEFAULT_CAMERA_SIZE, RemotePolicy
from culinarycut_policies.transports.faults import PolicyServerError
from culinarycut_policies.transports.openpi_websocket import OpenPIWebsocketClient

IMAGE_SIZE = 224
REPLAN_STEPS = 5
STATE_DIM = 8  # LIBERO: eef position, rotation vector, two gripper joints
LIBERO_UNITS = "robosuite_osc"


class OpenPIPolicy(RemotePolicy):
    name = "openpi"
    version = "1"
    control_mode = "pd_ee_delta_pose"

    def __init__(self, url: str = "ws://127.0.0.1:8000", camera: str = "front", wrist_camera: str | None = "wrist",
                 camera_size: int = DEFAULT_CAMERA_SIZE, replan_steps: int = REPLAN_STEPS,
                 state_dim: int = STATE_DIM, action_units: str = LIBERO_UNITS, model_rate_hz: float | None = None,
                 rotation_delta: str | None = None, api_key: str | None = None, **transport):
        super().__init__(url=url, **transport)
        self.action_units = resolve_action_units(None, action_units, self.name)
        self.rotation_delta = resolve_rotation_delta(rotation_delta, self.action_units, self.name)
        self.use_cameras(camera, wrist_camera, camera_size)
        self.chunks = OpenLoopChunks(int(replan_steps))
        self.rate = ModelRate(model_rate_hz, None, self.name)
        self.state_dim = int(state_dim)
        self.transport = OpenPIWebsocketClient(self.url, self.timeouts, api_key=api_key)

    def reset(self, instruction, info):
        self.chunks.reset()
        self.rate.reset(info)
        super().reset(instruction, info)

    def request(self, observation: dict) -> dict:
        request = {"observation/image": resize_with_pad(camera_rgb(observation, self.camera), IMAGE_SIZE, IMAGE_SIZE)}
        if self.wrist_camera:
            request["observation/wrist_image"] = resize_with_pad(camera_rgb(observation, self.wrist_camera),
                                                                 IMAGE_SIZE, IMAGE_SIZE)
        request["observation/state"] = pad_state(tcp_position_axis_angle(observation), self.state_dim)
        request["prompt"] = self.instruction
        return request

    def act(self, observation):
        return self.rate.execute(self.model_action, observation)

    def model_action(self, observation):
        if self.chunks.needs_chunk:
            reply = self.transport.infer(self.request(observation))
            actions = np.asarray(reply.get("actions"))
            if actions.ndim != 2:
                raise PolicyServerError(f"policy openpi: expected `actions` (H, D) from {self.url}, got {actions.shape}")
            self.chunks.add(actions)
        return delta_to_ee_delta_pose(self.chunks.next(), self.action_units, self.rotation_delta)

"""OpenVLA through its REST server (vla-scripts/deploy.py): one front image JPEG round-tripped and squashed
to 224 x 224 as its evaluation does (and the 0.9-area centre crop for models fine-tuned with image
augmentation), the instruction and `unnorm_key`;
the server builds the prompt, un-normalises with the key's q01/q99 and mask, and answers one 7-D delta
end-effector action per query, executed as pd_ee_delta_pose (gripper: see actions.py)."""
from __future__ import annotations

import numpy as np

from culinarycut_policies.actions import delta_to_ee_delta_pose, load_delta_ee_statistics, resolve_rotation_delta
from culinarycut_policies.control_rate import ModelRate
from culinarycut_policies.images import camera_rgb, center_crop_resize, jpeg_roundtrip, squash_resize
from culinarycut_policies.remote_policy import DEFAULT_CAMERA_SIZE, RemotePolicy
from culinarycut_policies.transports.faults import PolicyServerError
from culinarycut_policies.transports.json_numpy_rest import JsonNumpyRestClient

IMAGE_SIZE = 224           # experiments/robot/robot_utils.py, get_image_resize_size
CROP_AREA = 0.9            # experiments/robot/openvla_utils.py, get_vla_action(center_crop=True)
SYSTEM_PROMPT = ("A chat between a curious user and an artificial intelligence assistant. "
                 "The assistant gives helpful, detailed, and polite answers to the user's questions.")


def openvla_prompt(instruction: str, v01: bool = False) -> str:
    """deploy.py's get_openvla_prompt: the instruction lower-cased into OpenVLA's question."""
    if v01:
        return f"{SYSTEM_PROMPT} USER: What action should the robot take to {instruction.lower()}? ASSISTANT:"
    return f"In: What action should the robot take to {instruction.lower()}?\nOut:"


def openvla_image(rgb: np.ndarray, center_crop: bool, jpeg: bool = True) -> np.ndarray:
    """The 224 x 224 image OpenVLA sees: JPEG round trip (its training frames were JPEG in RLDS), squashed
    (no letterbox), then optionally centre-cropped to 0.9 of its area and resized back."""
    image = squash_resize(jpeg_roundtrip(rgb) if jpeg else rgb, IMAGE_SIZE, IMAGE_SIZE)
    if center_crop:
        image = center_crop_resize(image, CROP_AREA, IMAGE_SIZE, IMAGE_SIZE)
    return image


def check_in_bounds(action: np.ndarray, low: np.ndarray, high: np.ndarray, mask: np.ndarray, where: str) -> None:
    """OpenVLA decodes one of 256 bins in [-1, 1], so a masked dimension lands in [q01, q99] and an
    unmasked one in [-1, 1]; anything else means other statistics (or none) were applied."""
    lower = np.where(mask, np.minimum(low, high), -1.0)
    upper = np.where(mask, np.maximum(low, high), 1.0)
    slack = 1e-6 * np.maximum(1.0, np.abs(upper - lower))
    outside = (action < lower - slack) | (action > upper + slack)
    if outside.any():
        dims = np.flatnonzero(outside).tolist()
        raise PolicyServerError(f"{where}: action dimensions {dims} ({action[dims]}) lie outside what the "
                                f"statistics allow ({lower[dims]} .. {upper[dims]}): the server un-normalised "
                                "with other statistics, or not at all (option check_bounds=false to skip)")


class OpenVLAPolicy(RemotePolicy):
    name = "openvla"
    version = "1"
    control_mode = "pd_ee_delta_pose"

    def __init__(self, url: str = "http://127.0.0.1:8000", statistics: str | None = None,
                 unnorm_key: str | None = None, camera: str = "front", camera_size: int = DEFAULT_CAMERA_SIZE,
                 center_crop: bool = False, jpeg: bool = True, check_bounds: bool = True,
                 action_units: str | None = None, model_rate_hz: float | None = None,
                 rotation_delta: str | None = None, **transport):
        super().__init__(url=url, **transport)
        self.stats, self.action_units = load_delta_ee_statistics(statistics, unnorm_key, action_units,
                                                                 policy=self.name, proprio=False)
        self.rotation_delta = resolve_rotation_delta(rotation_delta, self.action_units, self.name)
        self.rate = ModelRate(model_rate_hz, self.stats.key, self.name)
        self.use_cameras(camera, None, camera_size)
        self.center_crop = bool(center_crop)
        self.jpeg = bool(jpeg)
        self.check_bounds = bool(check_bounds)
        self.transport = JsonNumpyRestClient(self.url, self.timeouts)

    def request(self, observation: dict) -> dict:
        """deploy.py's payload: {"image": 224x224x3 uint8, "instruction": str, "unnorm_key": str}."""
        image = openvla_image(camera_rgb(observation, self.camera), self.center_crop, self.jpeg)
        return {"image": image, "instruction": self.instruction, "unnorm_key": self.stats.key}

    def reset(self, instruction, info):
        self.rate.reset(info)
        super().reset(instruction, info)

    def act(self, observation):
        return self.rate.execute(self.model_action, observation)

    def model_action(self, observation):
        action = np.asarray(self.transport.query(self.request(observation)), dtype=np.float64).reshape(-1)
        stats = self.stats.action
        if action.shape != (stats.dim,):
            raise PolicyServerError(f"OpenVLA server answered {action.shape[0]} action values; the statistics of "
                                    f"{self.stats.key!r} have {stats.dim}")
        if self.check_bounds:
            check_in_bounds(action, stats.q01, stats.q99, stats.mask, f"OpenVLA server {self.transport.url}")
        return delta_to_ee_delta_pose(action, self.action_units, self.rotation_delta)

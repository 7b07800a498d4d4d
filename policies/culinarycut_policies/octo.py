"""Octo through an openpi-protocol server (policies/servers/serve_octo.py): `image_primary` 256 x 256 and
`image_wrist` 128 x 128 (Lanczos squash, as Octo's ResizeImageWrapper, which also centre-crops
`image_primary` to 0.9 of its area and resizes it back: option crop_primary), a history window of 2 with
`timestep_pad_mask` (octo/utils/gym_wrappers.py HistoryWrapper), batch dimension first. The server
answers normalised action chunks (1, 4, 7) (sample_actions without statistics; a server whose metadata
says `normalized_actions` false is refused); they are un-normalised
here with the dataset's mean/std and mask, as sample_actions would, and executed by temporal ensembling
or receding horizon control."""
from __future__ import annotations

from collections import deque

import numpy as np

from culinarycut_policies.actions import delta_to_ee_delta_pose, load_delta_ee_statistics, resolve_rotation_delta
from culinarycut_policies.chunking import OpenLoopChunks, TemporalEnsemble
from culinarycut_policies.control_rate import ModelRate
from culinarycut_policies.images import camera_rgb, octo_center_crop, squash_resize
from culinarycut_policies.remote_policy import DEFAULT_CAMERA_SIZE, RemotePolicy
from culinarycut_policies.statistics import unnormalize_normal
from culinarycut_policies.transports.faults import PolicyServerError
from culinarycut_policies.transports.openpi_websocket import OpenPIWebsocketClient

PRIMARY_SIZE = 256
WRIST_SIZE = 128
WINDOW = 2          # octo-base-1.5's window size (option window)
PRED_HORIZON = 4    # its action head's chunk (option action_horizon)
CROP_AREA = 0.9     # octo/utils/gym_wrappers.py ResizeImageWrapper avg_scale, on image_primary
EXECUTIONS = ("ensemble", "receding")


class OctoHistory:
    """HistoryWrapper: the first observation fills the window and is the only one not padding."""

    def __init__(self, window: int = WINDOW):
        self.window = window
        self.frames: deque = deque(maxlen=window)
        self.seen = 0

    def reset(self) -> None:
        self.frames.clear()
        self.seen = 0

    def add(self, frame: dict) -> dict:
        """The stacked window (window, ...) per key plus `timestep_pad_mask` (window,), False = padding."""
        if not self.frames:
            self.frames.extend([frame] * self.window)
            self.seen = 1
        else:
            self.frames.append(frame)
            self.seen += 1
        stacked = {k: np.stack([f[k] for f in self.frames]) for k in frame}
        mask = np.ones(self.window, dtype=bool)
        mask[: self.window - min(self.seen, self.window)] = False
        stacked["timestep_pad_mask"] = mask
        return stacked


class OctoPolicy(RemotePolicy):
    name = "octo"
    model_family = "octo"
    version = "1"
    control_mode = "pd_ee_delta_pose"

    def __init__(self, url: str = "ws://127.0.0.1:8000", statistics: str | None = None,
                 unnorm_key: str | None = None, camera: str = "front", wrist_camera: str | None = None,
                 camera_size: int = DEFAULT_CAMERA_SIZE, execution: str = "ensemble", exec_horizon: int = 1,
                 exp_weight: float = 0.0, window: int = WINDOW, action_horizon: int = PRED_HORIZON,
                 action_units: str | None = None, crop_primary: bool = True, model_rate_hz: float | None = None,
                 rotation_delta: str | None = None, api_key: str | None = None, **transport):
        super().__init__(url=url, **transport)
        self.stats, self.action_units = load_delta_ee_statistics(statistics, unnorm_key, action_units,
                                                                 policy=self.name, proprio=False)
        self.rotation_delta = resolve_rotation_delta(rotation_delta, self.action_units, self.name)
        self.window, self.action_horizon = int(window), int(action_horizon)
        if execution not in EXECUTIONS:
            raise ValueError(f"policy octo: option execution must be one of {EXECUTIONS}, got {execution!r}")
        if not 1 <= int(exec_horizon) <= self.action_horizon:
            raise ValueError(f"policy octo: option exec_horizon must be in 1..{self.action_horizon} (action_horizon), "
                             f"got {exec_horizon}")
        self.executor = (TemporalEnsemble(self.action_horizon, exp_weight) if execution == "ensemble"
                         else OpenLoopChunks(int(exec_horizon)))
        self.use_cameras(camera, wrist_camera, camera_size)
        self.crop_primary = bool(crop_primary)
        self.rate = ModelRate(model_rate_hz, self.stats.key, self.name)
        self.history = OctoHistory(self.window)
        self.transport = OpenPIWebsocketClient(self.url, self.timeouts, api_key=api_key)

    def reset(self, instruction, info):
        self.history.reset()
        self.executor.reset()
        self.rate.reset(info)
        super().reset(instruction, info)

    def check_metadata(self, metadata: dict) -> None:
        """The server's metadata must agree with the options (serve_octo.py reads them from the model)."""
        if "normalized_actions" in metadata and not metadata["normalized_actions"]:
            raise PolicyServerError(f"policy octo: the model at {self.url} answers un-normalised actions "
                                    "(normalized_actions false: it was given statistics); this adapter un-normalises "
                                    "with option statistics, so they would be un-normalised twice: serve the model "
                                    "without statistics")
        for option in ("window", "action_horizon"):
            if option in metadata and int(metadata[option]) != getattr(self, option):
                raise PolicyServerError(f"policy octo: the model at {self.url} has {option} {metadata[option]}; "
                                        f"set option {option}={metadata[option]}")

    def frame(self, observation: dict) -> dict:
        primary = squash_resize(camera_rgb(observation, self.camera), PRIMARY_SIZE, PRIMARY_SIZE)
        frame = {"image_primary": octo_center_crop(primary, CROP_AREA) if self.crop_primary else primary}
        if self.wrist_camera:
            frame["image_wrist"] = squash_resize(camera_rgb(observation, self.wrist_camera), WRIST_SIZE, WRIST_SIZE)
        return frame

    def request(self, observation: dict) -> dict:
        """{"observation": {key: (1, 2, ...)}, "prompt": instruction}: batch first, as sample_actions takes it."""
        window = self.history.add(self.frame(observation))
        return {"observation": {k: v[None] for k, v in window.items()}, "prompt": self.instruction}

    def act(self, observation):
        return self.rate.execute(self.model_action, observation)

    def model_action(self, observation):
        request = self.request(observation)  # every model step: its history window moves with it
        if self.executor.needs_chunk:
            reply = self.transport.infer(request)
            actions = np.asarray(reply.get("actions"))
            if actions.ndim != 3 or actions.shape[0] != 1 or actions.shape[1] < self.action_horizon:
                raise PolicyServerError(f"policy octo: expected actions (1, >={self.action_horizon}, D) from "
                                        f"{self.url}, got {actions.shape}")
            self.executor.add(unnormalize_normal(actions[0], self.stats.action))
        return delta_to_ee_delta_pose(self.executor.next(), self.action_units, self.rotation_delta)

"""The trained policy behind openpi's websocket protocol, in openpi's LIBERO layout: what the `openpi`
adapter sends by default (`culinarycut bench run SUITE --policy openpi --policy-url ws://HOST:PORT`), so
the trained model runs through the same path as a remote VLA. The protocol server is the one the
stand-ins and the real-model scripts use (culinarycut_policies.standins.websocket_server).

Each request: `observation/image` and `observation/wrist_image` (224 x 224 x 3 uint8), `observation/state`
(8: TCP position, rotation vector, two gripper slots), `prompt`, and `observation/wrist_wrench` (6), which
the metadata's `extra_observations` asks the adapter for. The answer: `actions` (chunk, 7), OSC_POSE
deltas and LIBERO's gripper column, what the adapter executes with its defaults (features.py).

The model sees a short history. The adapter queries once per `replan_steps` control steps (5) and opens
one connection per episode, so each connection keeps its own frames, one per query: the history is
`history_stride` control steps apart exactly when the adapter's replan_steps equals it (5 by default on
both sides; the metadata says `history_stride`). An episode's first query repeats its frame back in time,
as training does at an episode's start."""
from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np
import torch

from culinarycut_learning.checkpoint import checkpoint_path, load_checkpoint, policy_from_checkpoint
from culinarycut_learning.features import (ADAPTER_IMAGE_SIZE, compress_wrench, model_image, served_actions,
                                           state_from_request)
from culinarycut_learning.train import prompt_arrays, resolve_device

IMAGE_KEYS = ("observation/image", "observation/wrist_image")   # front, wrist: data.CAMERAS
WRENCH_KEY = "observation/wrist_wrench"
REQUIRED_KEYS = (*IMAGE_KEYS, "observation/state", "prompt", WRENCH_KEY)
MODEL_FAMILY = "culinarycut-act"


class ServedPolicy:
    """The checkpoint's model; `connection()` makes the model of one connection (one episode)."""

    def __init__(self, checkpoint: Path, device: str = "cpu", threads: int = 1):
        torch.set_num_threads(threads)
        self.device = resolve_device(device)
        payload = load_checkpoint(checkpoint)
        self.model, self.tokenizer, self.config = policy_from_checkpoint(payload)
        self.model.to(self.device)
        self.prompts: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        model = self.config.model
        self.metadata = {
            "model_family": MODEL_FAMILY, "layout": "libero", "action_horizon": model.chunk,
            "extra_observations": [WRENCH_KEY], "action_units": "robosuite_osc", "rotation_delta": "axis_angle",
            "history": model.history, "history_stride": model.history_stride, "image_size": model.image_size,
            "checkpoint": str(checkpoint_path(checkpoint)), "step": int(payload["step"]),
            "data_sha256": payload["data"]["sha256"],
        }

    def connection(self) -> Callable[[dict], dict]:
        frames: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []

        def answer(request: dict) -> dict:
            frames.append(self.frame(request))
            del frames[: -self.config.model.history]
            return {"actions": self.infer(frames, str(request["prompt"]))}
        return answer

    def frame(self, request: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        missing = [key for key in REQUIRED_KEYS if key not in request]
        if missing:
            hint = (" (the server's metadata asks for it in `extra_observations`: an openpi adapter that sends "
                    "it is needed, culinarycut-policies of this checkout)") if WRENCH_KEY in missing else ""
            raise ValueError(f"this policy reads openpi's LIBERO layout and the wrist force ({', '.join(REQUIRED_KEYS)}); "
                             f"the request lacks {', '.join(missing)}{hint}; it has {', '.join(sorted(request))}")
        images = []
        for key in IMAGE_KEYS:
            image = request[key]
            if not isinstance(image, np.ndarray) or image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
                raise ValueError(f"{key}: expected an HxWx3 uint8 image ({ADAPTER_IMAGE_SIZE} x {ADAPTER_IMAGE_SIZE} "
                                 f"from the adapter), got {getattr(image, 'shape', type(image))} "
                                 f"{getattr(image, 'dtype', '')}")
            images.append(model_image(image, self.config.model.image_size))
        wrench = np.asarray(request[WRENCH_KEY], dtype=np.float64).reshape(-1)
        if wrench.size != 6 or not np.all(np.isfinite(wrench)):
            raise ValueError(f"{WRENCH_KEY}: expected 6 finite values [N x3, N m x3], got {wrench}")
        return np.stack(images), state_from_request(request["observation/state"]), compress_wrench(wrench)

    def infer(self, frames: list, prompt: str) -> np.ndarray:
        """(chunk, 7) actions from this connection's frames (the last is now) and the prompt."""
        history = self.config.model.history
        picked = [frames[max(0, len(frames) - history + k)] for k in range(history)]   # oldest first
        if prompt not in self.prompts:
            self.prompts[prompt] = prompt_arrays(self.tokenizer, [prompt])
        ids, numbers = self.prompts[prompt]
        inputs = {"images": torch.from_numpy(np.stack([f[0] for f in picked])[None]),
                  "state": torch.from_numpy(np.stack([f[1] for f in picked])[None]),
                  "wrench": torch.from_numpy(np.stack([f[2] for f in picked])[None]),
                  "word_ids": torch.from_numpy(ids), "word_numbers": torch.from_numpy(numbers)}
        with torch.no_grad():
            normalised = self.model(**{k: v.to(self.device) for k, v in inputs.items()})
            actions = self.model.actions(normalised)[0].cpu().numpy()
        return served_actions(actions)


def make_server(checkpoint: Path, host: str = "127.0.0.1", port: int = 0, device: str = "cpu", threads: int = 1,
                api_key: str | None = None):
    """(server, policy): the websocket server, not yet started."""
    from culinarycut_policies.standins.websocket_server import WebsocketPolicyServer
    policy = ServedPolicy(checkpoint, device=device, threads=threads)
    server = WebsocketPolicyServer(None, policy.metadata, host, port, api_key=api_key,
                                   connection_model=policy.connection)
    return server, policy

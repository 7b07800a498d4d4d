"""Deterministic fake models: they check their inputs as the real model's code path would (shapes, dtypes,
keys) and answer in the real model's output format, from the inputs alone (no RNG), so a test can say
exactly what an adapter must execute. Each keeps the last request it saw for the tests to inspect.
`mode="zero"` answers as cheaply as possible (the overhead benchmark's model doing nothing)."""
from __future__ import annotations

import hashlib

import numpy as np

from culinarycut_policies.images import center_crop_resize, squash_resize
from culinarycut_policies.openvla import CROP_AREA, IMAGE_SIZE, openvla_prompt
from culinarycut_policies.statistics import (DatasetStatistics, normalize_bounds_q99, unnormalize_bounds_q99)

# OpenVLA's action tokenizer (prismatic/vla/action_tokenizer.py): 256 bins on [-1, 1], 255 centres.
_BINS = np.linspace(-1.0, 1.0, 256)
BIN_CENTERS = (_BINS[:-1] + _BINS[1:]) / 2.0


def _digest(*parts) -> np.ndarray:
    """32 bytes that depend on every input."""
    hasher = hashlib.sha256()
    for part in parts:
        hasher.update(part.tobytes() if isinstance(part, np.ndarray) else str(part).encode())
    return np.frombuffer(hasher.digest(), dtype=np.uint8)


def _image(value, key: str, shape: tuple | None = None) -> np.ndarray:
    if not isinstance(value, np.ndarray) or value.dtype != np.uint8 or value.ndim < 3 or value.shape[-1] != 3:
        raise ValueError(f"{key}: expected uint8 ...xHxWx3, got {getattr(value, 'shape', type(value))} "
                         f"{getattr(value, 'dtype', '')}")
    if shape is not None and value.shape != shape:
        raise ValueError(f"{key}: expected shape {shape}, got {value.shape}")
    return value


class FakeOpenVLA:
    """deploy.py's predict_action: prompt from the instruction, one of 255 bin centres per dimension
    (chosen by a hash of prompt and image), un-normalised with the request's unnorm_key (q01/q99, mask)."""

    def __init__(self, statistics: dict[str, DatasetStatistics], mode: str = "hash"):
        self.statistics = statistics
        self.mode = mode
        self.last_request: dict | None = None
        self.last_prompt = ""

    def normalized(self, prompt: str, image: np.ndarray, dim: int) -> np.ndarray:
        if self.mode == "zero":
            return np.full(dim, BIN_CENTERS[127])
        return BIN_CENTERS[_digest(prompt, image)[:dim] % len(BIN_CENTERS)]

    def __call__(self, payload: dict) -> np.ndarray:
        self.last_request = payload
        image = _image(payload["image"], "image")
        key = payload.get("unnorm_key")
        if key is None and len(self.statistics) == 1:
            key = next(iter(self.statistics))
        stats = self.statistics[key]  # KeyError -> "error", as predict_action's assert fails upstream
        self.last_prompt = openvla_prompt(payload["instruction"])
        return unnormalize_bounds_q99(self.normalized(self.last_prompt, image, stats.action.dim), stats.action)


class FakeOpenVLAOFT:
    """openvla-oft's get_vla_action: images resized to 224 if needed and centre-cropped, the state normalised
    with the proprio q01/q99, a chunk of `chunk` continuous actions in [-1, 1] un-normalised, as a list."""

    def __init__(self, statistics: DatasetStatistics, chunk: int = 8, center_crop: bool = True, mode: str = "hash"):
        self.stats = statistics
        self.chunk = chunk
        self.center_crop = center_crop
        self.mode = mode
        self.last_request: dict | None = None
        self.last_images: list = []
        self.last_state: np.ndarray | None = None

    def __call__(self, payload: dict) -> list:
        self.last_request = payload
        images = [payload["full_image"]] + [payload[k] for k in payload if "wrist" in k]
        if self.mode == "zero":  # the overhead benchmark's model that does nothing
            return [np.zeros(self.stats.action.dim) for _ in range(self.chunk)]
        prepared = []
        for image in images:
            image = _image(image, "image")
            if image.shape != (IMAGE_SIZE, IMAGE_SIZE, 3):
                image = squash_resize(image, IMAGE_SIZE, IMAGE_SIZE)
            if self.center_crop:
                image = center_crop_resize(image, CROP_AREA, IMAGE_SIZE, IMAGE_SIZE)
            prepared.append(image)
        self.last_images = prepared
        self.last_state = normalize_bounds_q99(payload["state"], self.stats.proprio)
        seed = _digest(openvla_prompt(payload["instruction"]), *prepared, self.last_state)
        normalized = np.tanh(np.resize(seed.astype(np.float64) / 64.0 - 2.0, (self.chunk, self.stats.action.dim)))
        return [unnormalize_bounds_q99(row, self.stats.action) for row in normalized]


class FakeOcto:
    """sample_actions without unnormalization statistics: (1, 4, 7) normalised actions from the window.
    Chunk element k, dimension d is 0.01 (k + 1) (d + 1) times the sign of the pad mask's sum, plus a
    hash-of-images term that `mode="zero"` leaves out; chunks differ from query to query with the images."""

    metadata = {"model_family": "octo", "window": 2, "action_horizon": 4, "action_dim": 7,
                "normalized_actions": True}

    def __init__(self, mode: str = "hash"):
        self.mode = mode
        self.last_request: dict | None = None

    def __call__(self, request: dict) -> dict:
        self.last_request = request
        observation = request["observation"]
        _image(observation["image_primary"], "image_primary", (1, 2, 256, 256, 3))
        if "image_wrist" in observation:
            _image(observation["image_wrist"], "image_wrist", (1, 2, 128, 128, 3))
        mask = np.asarray(observation["timestep_pad_mask"])
        if mask.shape != (1, 2) or mask.dtype != bool:
            raise ValueError(f"timestep_pad_mask: expected (1, 2) bool, got {mask.shape} {mask.dtype}")
        if not isinstance(request.get("prompt"), str):
            raise ValueError("prompt: expected the instruction text")
        k, d = np.meshgrid(np.arange(4), np.arange(7), indexing="ij")
        actions = 0.01 * (k + 1) * (d + 1) * float(mask.sum())
        if self.mode != "zero":
            actions = actions + (_digest(observation["image_primary"])[:7] / 255.0 - 0.5) * 0.1
        return {"actions": actions[None].astype(np.float32)}


class FakeRDT:
    """RDT's predict_action on the unified vectors: 64 future states that all equal the current state
    (a model that holds still), so what the robot does shows the adapter's round trip; the images and
    the language are checked and hashed into `last_digest`."""

    metadata = {"model_family": "rdt", "action_horizon": 64, "state_dim": 128, "image_size": 384}

    def __init__(self, mode: str = "hash"):
        self.mode = mode
        self.last_request: dict | None = None

    def __call__(self, request: dict) -> dict:
        self.last_request = request
        images = request["images"]
        if not isinstance(images, list) or len(images) != 6:
            raise ValueError(f"images: expected a list of 6 (None for missing), got {type(images).__name__}")
        for i, image in enumerate(images):
            if image is not None:
                _image(image, f"images[{i}]", (384, 384, 3))
        state = np.asarray(request["state"], dtype=np.float32)
        mask = np.asarray(request["state_elem_mask"])
        if state.shape != (1, 1, 128) or mask.shape != (1, 128):
            raise ValueError(f"state (1, 1, 128) and state_elem_mask (1, 128) expected, got {state.shape}, {mask.shape}")
        if "text_embeds" in request:
            embeds = np.asarray(request["text_embeds"])
            if embeds.ndim != 3 or embeds.shape[0] != 1 or embeds.shape[2] != 4096:
                raise ValueError(f"text_embeds: expected (1, L, 4096), got {embeds.shape}")
        elif not isinstance(request.get("instruction"), str):
            raise ValueError("text_embeds or instruction required")
        float(request["ctrl_freq"])
        return {"actions": np.repeat(state * mask[:, None, :], 64, axis=1)}


class FakeOpenPI:
    """An openpi policy answering `actions` (10, 7): a slow drift along x whose size follows the state."""

    metadata = {"model_family": "openpi-fake", "action_horizon": 10}

    def __init__(self, mode: str = "hash"):
        self.mode = mode
        self.last_request: dict | None = None

    def __call__(self, request: dict) -> dict:
        self.last_request = request
        _image(request["observation/image"], "observation/image", (224, 224, 3))
        state = np.asarray(request["observation/state"], dtype=np.float64)
        actions = np.zeros((10, 7))
        if self.mode != "zero":
            actions[:, 0] = 0.001 * np.tanh(state[0])
        return {"actions": actions}

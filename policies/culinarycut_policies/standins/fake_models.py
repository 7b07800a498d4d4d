"""Deterministic fake models: they check their inputs as the real model's code path would (shapes, dtypes,
keys) and answer in the real model's output format, from the inputs alone (no RNG), so a test can say
exactly what an adapter must execute. Each keeps the last request it saw for the tests to inspect.
`mode="zero"` answers as cheaply as possible (the overhead benchmark's model doing nothing)."""
from __future__ import annotations

import hashlib
import time

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


# What an openpi server of each layout reads (src/openpi/policies/*_policy.py, its make_*_example) and
# answers: (horizon, action dim) of a checkpoint of that layout (pi0_fast_libero, pi0_fast_droid: 10;
# pi0_aloha: pi0's 50) and the example that builds the request. The prompt is required, as by a server
# whose config has no default_prompt.
OPENPI_LAYOUTS = {
    "libero": {"example": "examples/libero/main.py", "actions": (10, 7),
               "keys": ("observation/image", "observation/wrist_image", "observation/state", "prompt")},
    "droid": {"example": "examples/droid/main.py", "actions": (10, 8),
              "keys": ("observation/exterior_image_1_left", "observation/wrist_image_left",
                       "observation/joint_position", "observation/gripper_position", "prompt")},
    "aloha": {"example": "examples/aloha_real/env.py", "actions": (50, 14), "keys": ("state", "images", "prompt")},
}
ALOHA_CAMERAS = ("cam_high", "cam_low", "cam_left_wrist", "cam_right_wrist")  # AlohaInputs.EXPECTED_CAMERAS
ALOHA_RESET_POSE = [0, -1.5, 1.5, 0, 0, 0]  # the policy_metadata of openpi's pi0_aloha configs


def _vector(value, key: str, size: int) -> np.ndarray:
    if not isinstance(value, np.ndarray) or value.shape != (size,) or not np.issubdtype(value.dtype, np.floating):
        raise ValueError(f"{key}: expected a float vector ({size},), got {getattr(value, 'shape', type(value))} "
                         f"{getattr(value, 'dtype', '')}")
    return value


class FakeOpenPI:
    """An openpi server of one `layout` (a real one's config decides it): checks the request as that
    layout's input transform and model would read it, and answers `actions` of the layout's shape.
    A request in another layout is refused naming both (a real server fails with a KeyError).
    libero: (10, 7) delta actions, a slow drift along x whose size follows the state.
    droid: (10, 8), joint 1 turning at velocity 0.05 (0.15 rad/s in DROID's units), the gripper column the
    gripper position it was sent.
    aloha: (50, 14), the state it was sent (the arms hold still) but for the left waist, which element k
    moves 0.002 (k + 1) rad from where it is."""

    def __init__(self, mode: str = "hash", layout: str = "libero"):
        if layout not in OPENPI_LAYOUTS:
            raise ValueError(f"unknown openpi layout {layout!r}; choose one of {', '.join(OPENPI_LAYOUTS)}")
        self.mode = mode
        self.layout = layout
        horizon = OPENPI_LAYOUTS[layout]["actions"][0]
        self.metadata = {"model_family": "openpi-fake", "layout": layout, "action_horizon": horizon}
        if layout == "aloha":
            self.metadata["reset_pose"] = list(ALOHA_RESET_POSE)
        self.last_request: dict | None = None

    def __call__(self, request: dict) -> dict:
        self.last_request = request
        started = time.monotonic()
        self._check_layout(request)
        actions = getattr(self, f"_{self.layout}")(request)
        return {"actions": actions, "policy_timing": {"infer_ms": (time.monotonic() - started) * 1000.0}}

    def _check_layout(self, request: dict) -> None:
        spec = OPENPI_LAYOUTS[self.layout]
        missing = [k for k in spec["keys"] if k not in request]
        if not missing:
            if not isinstance(request["prompt"], str):
                raise ValueError(f"prompt: expected the instruction text, got {type(request['prompt']).__name__}")
            return
        sent = [name for name, other in OPENPI_LAYOUTS.items()
                if name != self.layout and all(k in request for k in other["keys"] if k != "prompt")]
        raise ValueError(f"this openpi server reads the {self.layout} layout ({spec['example']}: "
                         f"{', '.join(spec['keys'])}); the request lacks {', '.join(missing)}"
                         + (f" and is in the {sent[0]} layout: its client must send layout {self.layout}" if sent
                            else f" (it has {', '.join(sorted(request)) or 'no keys'})"))

    def _libero(self, request: dict) -> np.ndarray:
        _image(request["observation/image"], "observation/image", (224, 224, 3))
        _image(request["observation/wrist_image"], "observation/wrist_image", (224, 224, 3))
        state = _vector(request["observation/state"], "observation/state", 8)
        actions = np.zeros((10, 7))
        if self.mode != "zero":
            actions[:, 0] = 0.001 * np.tanh(state[0])
        return actions

    def _droid(self, request: dict) -> np.ndarray:
        _image(request["observation/exterior_image_1_left"], "observation/exterior_image_1_left", (224, 224, 3))
        _image(request["observation/wrist_image_left"], "observation/wrist_image_left", (224, 224, 3))
        _vector(request["observation/joint_position"], "observation/joint_position", 7)
        gripper = _vector(np.atleast_1d(request["observation/gripper_position"]), "observation/gripper_position", 1)
        actions = np.zeros((10, 8))
        if self.mode != "zero":
            actions[:, 0] = 0.05
            actions[:, 7] = gripper[0]
        return actions

    def _aloha(self, request: dict) -> np.ndarray:
        state = _vector(request["state"], "state", 14)
        images = request["images"]
        if not isinstance(images, dict) or "cam_high" not in images or set(images) - set(ALOHA_CAMERAS):
            raise ValueError(f"images: expected a dict with cam_high of {', '.join(ALOHA_CAMERAS)}, got "
                             f"{sorted(images) if isinstance(images, dict) else type(images).__name__}")
        for name, image in images.items():
            if not isinstance(image, np.ndarray) or image.shape != (3, 224, 224) or image.dtype != np.uint8:
                raise ValueError(f"images/{name}: expected uint8 3x224x224 (channels first), got "
                                 f"{getattr(image, 'shape', type(image))} {getattr(image, 'dtype', '')}")
        actions = np.repeat(state[None], 50, axis=0)
        if self.mode != "zero":
            actions[:, 0] += 0.002 * np.arange(1, 51)
        return actions

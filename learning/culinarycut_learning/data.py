"""Training data from `culinarycut data export`'s robomimic HDF5 (robomimic/<name>.hdf5), read with h5py.

Why robomimic's file: it is one HDF5 file for the whole dataset, read with h5py (a dependency the
project already has: python3-h5py), and it holds everything the model needs in one place: both cameras'
frames as uint8 arrays (no video decoding, as LeRobot's MP4 files would need), the TCP pose, the wrist
wrench, the recorded actions with their control mode (env_args), every instruction of each episode and
the train/valid masks. LIBERO's export has the adapter's action units ready but no wrist wrench and one
file per task; the actions here are converted with the very function that export uses (features.py).

Episodes are held in memory, images already at the model's size (uint8): a sample is a window of
`history` frames `history_stride` steps apart ending at step t (clamped at the episode's start, as the
server's history is at an episode's first query) and the `chunk` actions from t on (masked past the end)."""
from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from culinarycut_learning.features import compress_wrench, model_image, osc_actions, state_from_tcp_poses

CAMERAS = ("front", "wrist")   # the openpi LIBERO layout's observation/image and observation/wrist_image
STD_FLOOR = 1e-3               # a feature that never changes is divided by this, not by 0


class DataError(ValueError):
    """The export cannot be trained on; the message says why and what to do."""


@dataclass
class Episode:
    name: str
    images: np.ndarray        # (T, cameras, S, S, 3) uint8
    state: np.ndarray         # (T, 6) float32
    wrench: np.ndarray        # (T, 6) float32, compressed
    actions: np.ndarray       # (T, 6) float32, OSC units
    instructions: list[str]

    def __len__(self) -> int:
        return len(self.actions)


def find_robomimic_file(path: Path) -> Path:
    """The robomimic HDF5 of an export folder (robomimic/*.hdf5), or the file itself."""
    path = Path(path)
    if path.is_file():
        return path
    files = sorted((path / "robomimic").glob("*.hdf5")) if path.is_dir() else []
    if len(files) != 1:
        found = f"found {len(files)}" if path.is_dir() else "no such folder"
        raise DataError(f"{path}: expected one robomimic/*.hdf5 in a `culinarycut data export` folder ({found}); "
                        "export with --format robomimic, or pass the .hdf5 file")
    return files[0]


def file_digest(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as file:
        for block in iter(lambda: file.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def load_episodes(path: Path, image_size: int, split: str = "train", styles: tuple = ()) -> list[Episode]:
    """The episodes of mask/<split> (every demo when the mask is missing or, for train, empty); with `styles`, only
    the demos whose cut spec has one of them."""
    path = find_robomimic_file(path)
    episodes = []
    with h5py.File(path, "r") as file:
        data = file["data"]
        control_mode = json.loads(data.attrs["env_args"])["env_kwargs"]["control_mode"]
        names = sorted(data.keys(), key=lambda n: int(n.split("_")[-1]))
        if f"mask/{split}" in file:
            masked = [n.decode() if isinstance(n, bytes) else str(n) for n in file[f"mask/{split}"][()]]
            names = masked if masked or split != "train" else names
        elif split != "train":
            names = []
        for name in names:
            demo = data[name]
            if styles and json.loads(demo.attrs.get("cut_spec", "{}")).get("style") not in styles:
                continue
            missing = [c for c in CAMERAS if f"obs/{c}_image" not in demo]
            if missing:
                cameras = sorted(k[: -len("_image")] for k in demo["obs"] if k.endswith("_image"))
                raise DataError(f"{path}: {name} has no {', '.join(missing)} camera (it has {', '.join(cameras)}); "
                                f"the policy sees {' and '.join(CAMERAS)}: generate with --cameras front,wrist")
            poses = demo["obs/ee_states"][()]
            try:
                actions = osc_actions(demo["actions"][()], poses, control_mode)
            except ValueError as err:
                raise DataError(f"{path}: {err}") from None
            images = np.stack([np.stack([model_image(frame, image_size) for frame in demo[f"obs/{camera}_image"][()]])
                               for camera in CAMERAS], axis=1)
            episodes.append(Episode(name=name, images=images, state=state_from_tcp_poses(poses),
                                    wrench=compress_wrench(demo["obs/wrist_wrench"][()]), actions=actions,
                                    instructions=list(json.loads(demo.attrs["instructions"]))))
    if split == "train" and not episodes:
        raise DataError(f"{path}: no episodes to train on" + (f" in the styles {', '.join(styles)}" if styles else ""))
    return episodes


def normalisation(episodes: list[Episode]) -> dict[str, dict[str, list[float]]]:
    """Mean and standard deviation (floored) of the state, the compressed wrench and the actions."""
    stats = {}
    for key in ("state", "wrench", "actions"):
        values = np.concatenate([getattr(e, key) for e in episodes]).astype(np.float64)
        stats[key] = {"mean": values.mean(0).tolist(), "std": np.maximum(values.std(0), STD_FLOOR).tolist()}
    return stats


class Windows:
    """Samples of `history` frames and `chunk` actions from in-memory episodes."""

    def __init__(self, episodes: list[Episode], history: int, stride: int, chunk: int):
        self.episodes = episodes
        self.history, self.stride, self.chunk = history, stride, chunk
        self.lengths = np.array([len(e) for e in episodes])
        self.offsets = np.concatenate([[0], np.cumsum(self.lengths)])

    @property
    def frames(self) -> int:
        return int(self.offsets[-1])

    def locate(self, flat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        episode = np.searchsorted(self.offsets, flat, side="right") - 1
        return episode, flat - self.offsets[episode]

    def batch(self, flat: np.ndarray, instruction_choice: np.ndarray) -> dict[str, np.ndarray]:
        """Arrays for the frames `flat` (indices over all frames): images (B, K, C, S, S, 3) uint8, state and
        wrench (B, K, 6), actions (B, H, 6), action_mask (B, H) (1 where the episode has that step), and the
        instruction text of each sample (its episode's instruction at `instruction_choice` mod count)."""
        episodes, steps = self.locate(np.asarray(flat))
        back = self.stride * np.arange(self.history - 1, -1, -1)        # oldest frame first
        images, state, wrench, actions, mask, texts = [], [], [], [], [], []
        for e, t, choice in zip(episodes, steps, instruction_choice):
            ep = self.episodes[e]
            frames = np.maximum(t - back, 0)
            images.append(ep.images[frames])
            state.append(ep.state[frames])
            wrench.append(ep.wrench[frames])
            ahead = np.arange(t, t + self.chunk)
            valid = ahead < len(ep)
            actions.append(ep.actions[np.minimum(ahead, len(ep) - 1)] * valid[:, None])
            mask.append(valid.astype(np.float32))
            texts.append(ep.instructions[int(choice) % len(ep.instructions)])
        return {"images": np.stack(images), "state": np.stack(state), "wrench": np.stack(wrench),
                "actions": np.stack(actions).astype(np.float32), "action_mask": np.stack(mask), "texts": texts}

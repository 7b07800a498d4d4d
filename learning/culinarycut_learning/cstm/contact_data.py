"""The contact classifier's data: every frame of one camera in a `culinarycut data export --format robomimic`
file, labelled with the simulator's knife-food contact at that frame (`obs/knife_contact`, uint8: the episode
recorder's `knife_contact`, taken from the same step's info as the image, before the action is applied).

Held out: the export's mask/valid demos (every 10th demo); an export with none (fewer than 10 demos) holds
out its last train demo when it has two or more, so a small run still reports an accuracy on unseen episodes."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from culinarycut_learning.data import DataError, find_robomimic_file
from culinarycut_learning.features import model_image

CONTACT_KEY = "obs/knife_contact"


@dataclass
class ContactFrames:
    images: np.ndarray      # (N, S, S, 3) uint8, at the classifier's image size
    labels: np.ndarray      # (N,) uint8: 1 while the knife touches the food
    demos: list[str]        # the demos they come from
    camera_size: int = 0    # pixels: the recorded frames' width (the policy wrapper renders its camera so)

    def __len__(self) -> int:
        return len(self.labels)


def _names(file: h5py.File, key: str) -> list[str]:
    if key not in file:
        return []
    return [n.decode() if isinstance(n, bytes) else str(n) for n in file[key][()]]


def split_demos(file: h5py.File) -> tuple[list[str], list[str], str]:
    """(train demos, held-out demos, how they were chosen)."""
    every = sorted(file["data"].keys(), key=lambda n: int(n.split("_")[-1]))
    valid = _names(file, "mask/valid")
    train = _names(file, "mask/train") or [n for n in every if n not in valid]
    if valid:
        return train, valid, "the export's mask/valid"
    if len(train) >= 2:
        return train[:-1], train[-1:], f"no mask/valid demos: the last demo ({train[-1]}) held out"
    return train, [], "no mask/valid demos and one demo: nothing held out"


def load_frames(path: Path, camera: str, image_size: int, demos: list[str]) -> ContactFrames:
    path = find_robomimic_file(Path(path))
    images, labels, width = [], [], 0
    with h5py.File(path, "r") as file:
        for name in demos:
            demo = file["data"][name]
            if CONTACT_KEY not in demo:
                raise DataError(f"{path}: {name} has no {CONTACT_KEY} (an export older than the knife-contact "
                                "record): export again with `culinarycut data export --format robomimic`")
            if f"obs/{camera}_image" not in demo:
                cameras = sorted(k[: -len("_image")] for k in demo["obs"] if k.endswith("_image"))
                raise DataError(f"{path}: {name} has no {camera} camera (it has {', '.join(cameras) or 'none'}); "
                                "choose one with --camera, or generate with --cameras including it")
            frames = demo[f"obs/{camera}_image"][()]
            width = int(frames.shape[2])
            images.append(np.stack([model_image(frame, image_size) for frame in frames]))
            labels.append((demo[CONTACT_KEY][()].reshape(-1) > 0).astype(np.uint8))
    if not images:
        return ContactFrames(np.zeros((0, image_size, image_size, 3), np.uint8), np.zeros(0, np.uint8), [])
    return ContactFrames(np.concatenate(images), np.concatenate(labels), list(demos), width)


def load_split(path: Path, camera: str, image_size: int) -> tuple[ContactFrames, ContactFrames, str]:
    """(train frames, held-out frames, how the held-out demos were chosen)."""
    path = find_robomimic_file(Path(path))
    with h5py.File(path, "r") as file:
        train, valid, how = split_demos(file)
    frames = load_frames(path, camera, image_size, train)
    if not len(frames):
        raise DataError(f"{path}: no frames to train on")
    counts = np.bincount(frames.labels, minlength=2)
    if counts.min() == 0:
        missing = "contact" if counts[1] == 0 else "no-contact"
        raise DataError(f"{path}: the training demos have no {missing} frames ({counts[0]} without contact, "
                        f"{counts[1]} with): the classifier needs both")
    return frames, load_frames(path, camera, image_size, valid), how

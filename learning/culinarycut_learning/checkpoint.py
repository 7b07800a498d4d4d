"""Checkpoints: the weights with everything needed to serve or resume them (the configuration, the
normalisation statistics, the tokenizer, the data's digest, and for resuming the optimiser's state and
the step). Written to a temporary file and renamed, so a kill at any moment leaves the previous
checkpoint whole."""
from __future__ import annotations

import os
from pathlib import Path

import torch

from culinarycut_learning.config import TrainConfig
from culinarycut_learning.language import Tokenizer
from culinarycut_learning.model import CuttingPolicy

FORMAT = "culinarycut-learning/1"
CHECKPOINT = "checkpoint.pt"


def checkpoint_path(run_or_file: Path) -> Path:
    """RUN/checkpoint.pt for a run folder, or the file itself."""
    path = Path(run_or_file)
    return path / CHECKPOINT if path.is_dir() else path


def save_checkpoint(path: Path, payload: dict) -> None:
    path = Path(path)
    temporary = path.with_name(path.name + ".tmp")
    torch.save({"format": FORMAT, **payload}, temporary)
    with open(temporary, "rb") as file:
        os.fsync(file.fileno())
    os.replace(temporary, path)


def load_checkpoint(run_or_file: Path, map_location: str = "cpu") -> dict:
    path = checkpoint_path(run_or_file)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no checkpoint (train first: python -m culinarycut_learning train "
                                "--data EXPORT --out RUN)")
    payload = torch.load(path, map_location=map_location)
    if not isinstance(payload, dict) or payload.get("format") != FORMAT:
        raise ValueError(f"{path}: not a culinarycut-learning checkpoint ({FORMAT})")
    return payload


def policy_from_checkpoint(payload: dict) -> tuple[CuttingPolicy, Tokenizer, TrainConfig]:
    """The model with its weights (eval mode, CPU), its tokenizer and configuration."""
    config = TrainConfig.from_dict(payload["config"])
    tokenizer = Tokenizer.from_dict(payload["tokenizer"])
    model = CuttingPolicy(config.model, len(tokenizer.vocabulary), payload["normalisation"])
    model.load_state_dict(payload["model"])
    model.eval()
    return model, tokenizer, config

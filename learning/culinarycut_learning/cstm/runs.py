"""Run folders and checkpoints of the two CSTM trainers, as the policy's trainer keeps them (train.py,
checkpoint.py): RUN/checkpoint.pt (weights, optimiser state, step, configuration, what the data was),
RUN/config.json and RUN/log.jsonl; a checkpoint written to a temporary file and renamed, so a kill at any
moment leaves the last one whole; the same command again resumes from it, and a folder holding a run of
other settings or other data is refused, naming each difference."""
from __future__ import annotations

import json
from pathlib import Path

import torch

from culinarycut_learning.checkpoint import CHECKPOINT, checkpoint_path, save_checkpoint
from culinarycut_learning.config import differences
from culinarycut_learning.train import RunError, _truncate_log

CLASSIFIER_FORMAT = "culinarycut-learning/cstm-classifier/1"
GENERATOR_FORMAT = "culinarycut-learning/cstm-generator/1"
WHAT = {CLASSIFIER_FORMAT: "CSTM contact classifier", GENERATOR_FORMAT: "CSTM style generator"}


def load(run_or_file: Path, fmt: str) -> dict:
    """The checkpoint of a run folder (RUN/checkpoint.pt) or file; FileNotFoundError / ValueError say which path."""
    if not Path(run_or_file).exists():
        raise FileNotFoundError(f"{run_or_file}: no such file or folder (a {WHAT[fmt]} run folder or its "
                                f"{CHECKPOINT} was expected)")
    path = checkpoint_path(Path(run_or_file))
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no {WHAT[fmt]} checkpoint (train one first)")
    payload = torch.load(path, map_location="cpu")
    if not isinstance(payload, dict) or payload.get("format") != fmt:
        found = payload.get("format") if isinstance(payload, dict) else type(payload).__name__
        raise ValueError(f"{path}: not a {WHAT[fmt]} checkpoint ({fmt}); it is {found!r}")
    return payload


def open_run(out: Path, fmt: str, identity: dict, data: dict, identity_of) -> dict | None:
    """The run folder's checkpoint when it holds one of these settings and data (None for a new run);
    RunError naming each difference otherwise. `identity_of(saved config dict)` gives a saved run's identity."""
    out = Path(out)
    if not (out / CHECKPOINT).is_file():
        return None
    saved = load(out, fmt)
    changed = differences(identity_of(saved["config"]), identity)
    if saved["data"]["sha256"] != data["sha256"]:
        changed.append(f"data: {saved['data']['source']} (sha256 {saved['data']['sha256'][:12]}) -> "
                       f"{data['source']} (sha256 {data['sha256'][:12]})")
    if changed:
        raise RunError(f"{out} holds a run with other settings; use another --out, or the same settings to "
                       f"resume it: {'; '.join(changed)}")
    return saved


def start_folder(out: Path, config: dict, data: dict, step: int) -> Path:
    """Writes config.json, cuts the log back to `step`; returns the log's path."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "config.json").write_text(json.dumps({**config, "data": data}, indent=2, sort_keys=True) + "\n")
    log_path = out / "log.jsonl"
    _truncate_log(log_path, step)
    return log_path


def save(out: Path, fmt: str, payload: dict) -> Path:
    path = Path(out) / CHECKPOINT
    path.parent.mkdir(parents=True, exist_ok=True)
    save_checkpoint(path, {**payload, "format": fmt, "torch": torch.__version__})
    return path


def append_log(path: Path, record: dict) -> None:
    with open(path, "a") as file:
        file.write(json.dumps(record) + "\n")

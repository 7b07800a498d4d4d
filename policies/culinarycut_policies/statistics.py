"""Normalisation statistics in OpenVLA/Octo's `dataset_statistics.json` layout, and the three ways the
upstream models map between normalised and dataset units.

Layout: {key: {"action": {"mean", "std", "min", "max", "q01", "q99", "mask"}, "proprio": {...},
"num_transitions", "num_trajectories"}} (Octo's own files name q01, q99 p01, p99: read alike); `mask`
(optional, default all true) marks the dimensions that are normalised at all (a gripper usually is not).
CulinaryCut's export also writes, per key, what the values are (`action_layout`, `proprio_layout`,
`action_units`; culinarycut/datasets/statistics.py): an adapter refuses a key whose layout is not the one it executes, and reads its units from there.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

FIELDS = ("mean", "std", "min", "max", "q01", "q99")
# Octo's get_dataset_statistics (octo/data/utils/data_utils.py) writes the same quantiles as p01, p99.
OCTO_QUANTILES = {"q01": "p01", "q99": "p99"}


class StatisticsError(ValueError):
    """The statistics file is missing, malformed, or lacks the key or field an adapter needs."""


@dataclass(frozen=True)
class Statistics:
    """One array (mean, std, min, max, q01, q99, mask) per field, all of one dimension."""

    mean: np.ndarray
    std: np.ndarray
    min: np.ndarray
    max: np.ndarray
    q01: np.ndarray
    q99: np.ndarray
    mask: np.ndarray

    @property
    def dim(self) -> int:
        return int(self.mean.shape[0])


def _quantiles_by_our_names(raw: dict, where: str) -> dict:
    """q01/q99 taken from Octo's p01/p99 where a file has only those; both names must then agree."""
    raw = dict(raw)
    for ours, octos in OCTO_QUANTILES.items():
        if octos not in raw:
            continue
        if ours in raw and not np.array_equal(np.asarray(raw[ours], dtype=np.float64),
                                              np.asarray(raw[octos], dtype=np.float64)):
            raise StatisticsError(f"{where} has both {ours} and {octos}, and they differ")
        raw.setdefault(ours, raw[octos])
    return raw


def _entry(raw: dict, where: str) -> Statistics:
    raw = _quantiles_by_our_names(raw, where)
    missing = [f for f in FIELDS if f not in raw]
    if missing:
        raise StatisticsError(f"{where} lacks {', '.join(missing)} (needs {', '.join(FIELDS)}, or Octo's p01, "
                              "p99 for q01, q99; optional mask)")
    values = {f: np.asarray(raw[f], dtype=np.float64) for f in FIELDS}
    dim = values["mean"].shape
    if len(dim) != 1 or any(v.shape != dim for v in values.values()):
        raise StatisticsError(f"{where}: mean, std, min, max, q01, q99 must be vectors of one length; got "
                              + ", ".join(f"{f} {v.shape}" for f, v in values.items()))
    mask = np.asarray(raw.get("mask", np.ones(dim, dtype=bool)), dtype=bool)
    if mask.shape != dim:
        raise StatisticsError(f"{where}.mask has shape {mask.shape}, the statistics {dim}")
    return Statistics(mask=mask, **values)


@dataclass(frozen=True)
class DatasetStatistics:
    """The statistics of one dataset key (OpenVLA's `unnorm_key`)."""

    key: str
    action: Statistics
    proprio: Statistics | None
    num_transitions: int
    num_trajectories: int
    where: str = ""                     # "PATH[key]", for messages
    action_layout: str | None = None    # None: a file that does not say (upstream's own statistics)
    proprio_layout: str | None = None
    action_units: str | None = None


def load_statistics(path: str | Path | None, key: str | None, *, policy: str,
                    action_layout: str | None = None) -> DatasetStatistics:
    """The statistics of `key` in the file at `path`. Without a path the adapter cannot un-normalise, so it
    refuses; without a key the file must hold exactly one (as OpenVLA's `_check_unnorm_key` requires), or
    exactly one whose `action_layout` is the adapter's."""
    if not path:
        raise StatisticsError(f"policy {policy!r} needs option statistics=PATH: the dataset_statistics.json of the "
                              "data the model was trained on (an adapter never guesses its action units)")
    file = Path(path)
    try:
        everything = json.loads(file.read_text())
    except OSError as err:
        raise StatisticsError(f"policy {policy!r}: option statistics={path}: {err.strerror}") from None
    except json.JSONDecodeError as err:
        raise StatisticsError(f"policy {policy!r}: option statistics={path} is not JSON: {err}") from None
    if not isinstance(everything, dict) or not everything:
        raise StatisticsError(f"policy {policy!r}: {path} holds no dataset keys")
    if key is None and action_layout is not None:
        fitting = [k for k, v in everything.items() if isinstance(v, dict) and v.get("action_layout") == action_layout]
        key = fitting[0] if len(fitting) == 1 else None
    if key is None:
        if len(everything) != 1:
            raise StatisticsError(f"policy {policy!r}: {path} has {len(everything)} datasets; choose one with "
                                  f"option unnorm_key= from: {', '.join(sorted(everything))}")
        key = next(iter(everything))
    if key not in everything:
        raise StatisticsError(f"policy {policy!r}: option unnorm_key={key!r} is not in {path}; it has: "
                              f"{', '.join(sorted(everything))}")
    raw = everything[key]
    if "action" not in raw:
        raise StatisticsError(f"policy {policy!r}: {path}[{key!r}] has no 'action' statistics")
    proprio = _entry(raw["proprio"], f"{path}[{key!r}].proprio") if "proprio" in raw else None
    return DatasetStatistics(key=key, action=_entry(raw["action"], f"{path}[{key!r}].action"), proprio=proprio,
                             num_transitions=int(raw.get("num_transitions", 0)),
                             num_trajectories=int(raw.get("num_trajectories", 0)), where=f"{path}[{key!r}]",
                             action_layout=raw.get("action_layout"), proprio_layout=raw.get("proprio_layout"),
                             action_units=raw.get("action_units"))


def require_layout(stats: DatasetStatistics, *, policy: str, action_layout: str,
                   proprio_layout: str | None = None, hint: str = "") -> None:
    """Refuses statistics that say they are in another layout than the adapter executes (a file that says
    nothing is taken on the user's word; its units must then come from option action_units)."""
    for field, declared, expected in (("action_layout", stats.action_layout, action_layout),
                                      ("proprio_layout", stats.proprio_layout, proprio_layout)):
        if expected is not None and declared is not None and declared != expected:
            raise StatisticsError(f"policy {policy!r}: {stats.where} has {field} {declared!r}, but this adapter "
                                  f"reads {expected!r}{hint}")


def _check_dim(values: np.ndarray, stats: Statistics, what: str) -> None:
    if values.shape[-1] != stats.dim:
        raise StatisticsError(f"{what} has {values.shape[-1]} dimensions, its statistics {stats.dim}")


# OpenVLA's BOUNDS_Q99 (prismatic/extern/hf/modeling_prismatic.py, predict_action): [-1, 1] -> [q01, q99].
def unnormalize_bounds_q99(normalized: np.ndarray, stats: Statistics) -> np.ndarray:
    normalized = np.asarray(normalized, dtype=np.float64)
    _check_dim(normalized, stats, "action")
    return np.where(stats.mask, 0.5 * (normalized + 1.0) * (stats.q99 - stats.q01) + stats.q01, normalized)


# OpenVLA-OFT's normalize_proprio, BOUNDS_Q99 (experiments/robot/openvla_utils.py): clipped to [-1, 1].
def normalize_bounds_q99(values: np.ndarray, stats: Statistics) -> np.ndarray:
    values = np.asarray(values, dtype=np.float64)
    _check_dim(values, stats, "proprio")
    scaled = 2.0 * (values - stats.q01) / (stats.q99 - stats.q01 + 1e-8) - 1.0
    return np.clip(np.where(stats.mask, scaled, values), -1.0, 1.0)


# Octo's NORMAL (octo/model/octo_model.py, sample_actions): x * std + mean, extra model dims dropped.
def unnormalize_normal(normalized: np.ndarray, stats: Statistics) -> np.ndarray:
    normalized = np.asarray(normalized, dtype=np.float64)[..., : stats.dim]
    _check_dim(normalized, stats, "action")
    return np.where(stats.mask, normalized * stats.std + stats.mean, normalized)


# Octo's NormalizeProprio (octo/utils/gym_wrappers.py): (x - mean) / (std + 1e-8).
def normalize_normal(values: np.ndarray, stats: Statistics) -> np.ndarray:
    values = np.asarray(values, dtype=np.float64)
    _check_dim(values, stats, "proprio")
    return np.where(stats.mask, (values - stats.mean) / (stats.std + 1e-8), values)


# RDT's ManiSkill fine-tune (scripts/maniskill_model.py): min/max <-> [-1, 1], both ways.
def normalize_bounds(values: np.ndarray, stats: Statistics) -> np.ndarray:
    values = np.asarray(values, dtype=np.float64)
    _check_dim(values, stats, "state")
    flat = stats.mask & (stats.max <= stats.min)
    if flat.any():
        raise StatisticsError(f"state dimensions {np.flatnonzero(flat).tolist()} have max <= min: mask them out")
    with np.errstate(divide="ignore", invalid="ignore"):
        scaled = (values - stats.min) / (stats.max - stats.min) * 2.0 - 1.0
    return np.where(stats.mask, scaled, values)


def unnormalize_bounds(normalized: np.ndarray, stats: Statistics) -> np.ndarray:
    normalized = np.asarray(normalized, dtype=np.float64)
    _check_dim(normalized, stats, "action")
    return np.where(stats.mask, (normalized + 1.0) / 2.0 * (stats.max - stats.min) + stats.min, normalized)

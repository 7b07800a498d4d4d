"""Repeated timing on a shared machine: settings interleaved round by round, so that the machine's drift touches
each alike, and each setting summed up by its fastest run (drift only ever slows a run down) and its median."""
from __future__ import annotations

from typing import Callable, Iterable, Mapping, TypeVar

import numpy as np

T = TypeVar("T")


def interleaved(settings: Mapping[str, Callable[[], T]], rounds: int,
                announce: Callable[[int, str], None] | None = None) -> dict[str, list[T]]:
    """Runs every setting once per round, in turn, for `rounds` rounds; each setting's results in run order.
    `announce(round, name)` is called before each run (progress)."""
    results: dict[str, list[T]] = {name: [] for name in settings}
    for index in range(rounds):
        for name, run in settings.items():
            if announce:
                announce(index, name)
            results[name].append(run())
    return results


def spread(values: Iterable[float]) -> dict:
    """The fastest (min), median and slowest of repeated measurements, and every one of them in run order."""
    runs = [float(v) for v in values]
    return {"min": min(runs), "median": float(np.median(runs)), "max": max(runs), "runs": runs}


def fastest(runs: list[dict], key: str = "wall_s") -> dict:
    """The run whose `key` is least: repeated runs of one setting summed up by the one the machine slowed least."""
    return min(runs, key=lambda run: run[key])


def percentiles(samples: Iterable[float], levels: Iterable[int] = (50, 90), unit: str = "ms") -> dict:
    """{"p50_ms": ..., "p90_ms": ...} of `samples` (in `unit`)."""
    values = np.asarray(list(samples), dtype=float)
    return {f"p{level}_{unit}": float(np.percentile(values, level)) for level in levels}

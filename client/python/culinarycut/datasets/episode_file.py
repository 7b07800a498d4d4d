"""One kept episode as an HDF5 file (episodes/<key>.h5): its per-step arrays and its metadata as JSON.

Written to a temporary name, flushed to disk and renamed, so a generator killed at any moment leaves
either the whole file or none. No timestamps are stored (track_times off) and chunks skip HDF5's chunk
cache, so the same seed gives the same bytes.
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import h5py
import numpy as np

FORMAT = "culinarycut-episode-1"


def episode_path(root: Path, key: str) -> Path:
    return root / "episodes" / (key.replace("/", "__") + ".h5")


def write_episode(path: Path, meta: dict, steps: dict[str, np.ndarray]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(path.name + ".tmp")
    # No chunk cache: cached chunks are placed in the file when their dataset handle is released, which
    # depends on Python's object lifetimes (a Dask worker's profiler holds frames); uncached, in write order.
    with h5py.File(temporary, "w", rdcc_nbytes=0) as file:
        file.attrs["format"] = FORMAT
        file.attrs["meta"] = json.dumps(meta, sort_keys=True)
        for name in sorted(steps):
            values = steps[name]
            if values.dtype.kind == "U":
                values = values.astype("S")
            file.create_dataset(name, data=values, track_times=False,
                                compression="gzip" if values.dtype == np.uint8 and values.ndim == 4 else None)
    with open(temporary, "rb+") as handle:
        os.fsync(handle.fileno())
    os.replace(temporary, path)


def read_episode(path: Path) -> tuple[dict, dict[str, np.ndarray]]:
    """(meta, steps); ValueError for a file that is not a whole episode."""
    try:
        with h5py.File(path, "r") as file:
            if file.attrs.get("format") != FORMAT:
                raise ValueError(f"{path}: not a {FORMAT} file")
            meta = json.loads(file.attrs["meta"])
            steps = {}
            file.visititems(lambda name, item: steps.__setitem__(name, item[()])
                            if isinstance(item, h5py.Dataset) else None)
    except OSError as err:
        raise ValueError(f"{path}: unreadable ({err})") from None
    if "phase" in steps:
        steps["phase"] = steps["phase"].astype(str)
    return meta, steps

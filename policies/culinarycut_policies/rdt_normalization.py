"""What the RDT adapter does to states and actions, as the model was fine-tuned:
- `none` (default): RDT's HDF5 fine-tune (data/hdf5_vla_dataset.py, HDF5VLADataset: the reader
  CulinaryCut's RDT export targets) and the pre-trained RDT-1B (scripts/agilex_model.py) put raw SI values
  into the unified vector; no statistics are read.
- `bounds`: RDT's ManiSkill fine-tune (scripts/maniskill_model.py): min/max <-> [-1, 1] with the
  statistics' proprio and action (the export's NAME_rdt key)."""
from __future__ import annotations

import numpy as np
from culinarycut.datasets.adapter_layouts import RDT_STATE, RDT_UNIFIED_SLOTS

from culinarycut_policies.statistics import (DatasetStatistics, StatisticsError, load_statistics, normalize_bounds,
                                             require_layout, unnormalize_bounds)

NORMALIZATIONS = ("none", "bounds")


def load_rdt_bounds(path: str | None, key: str | None) -> DatasetStatistics:
    """The min/max statistics in the adapter's 16-slot layout."""
    stats = load_statistics(path, key, policy="rdt", action_layout=RDT_STATE)
    require_layout(stats, policy="rdt", action_layout=RDT_STATE, proprio_layout=RDT_STATE,
                   hint=" (`culinarycut data export` writes it under the key NAME_rdt: option unnorm_key)")
    if stats.proprio is None:
        raise StatisticsError(f"policy rdt: the statistics of {stats.key!r} have no 'proprio'")
    for what, entry in (("proprio", stats.proprio), ("action", stats.action)):
        if entry.dim != len(RDT_UNIFIED_SLOTS):
            raise StatisticsError(f"policy rdt: {what} statistics of {stats.key!r} have {entry.dim} values; "
                                  f"RDT's layout here has {len(RDT_UNIFIED_SLOTS)} (7 joints, TCP xyz, 6-D rotation)")
    return stats


class RDTNormalization:
    def __init__(self, mode: str, statistics: str | None, unnorm_key: str | None):
        if mode not in NORMALIZATIONS:
            raise ValueError(f"policy rdt: option normalization must be one of {NORMALIZATIONS}, got {mode!r}")
        if mode == "none" and (statistics or unnorm_key):
            raise ValueError("policy rdt: options statistics and unnorm_key are read only with normalization=bounds "
                             "(RDT's ManiSkill fine-tune); RDT's HDF5 fine-tune and the pre-trained model take raw "
                             "values (normalization=none, the default)")
        self.mode = mode
        self.stats = load_rdt_bounds(statistics, unnorm_key) if mode == "bounds" else None

    def state(self, values: np.ndarray) -> np.ndarray:
        return normalize_bounds(values, self.stats.proprio) if self.stats else np.asarray(values, dtype=np.float64)

    def action(self, values: np.ndarray) -> np.ndarray:
        return unnormalize_bounds(values, self.stats.action) if self.stats else np.asarray(values, dtype=np.float64)

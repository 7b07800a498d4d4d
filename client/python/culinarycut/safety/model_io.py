"""From a force dataset on disk to the asset: the rows as model inputs, the fit, the provenance."""
from __future__ import annotations

import os
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from culinarycut.safety.asset import TARGET, build_asset
from culinarycut.safety.dataset import ROWS_FILE, dataset_sha256, read_header, read_rows
from culinarycut.safety.fit import FitResult, fit_force_model
from culinarycut.safety.posynomial import INPUTS


def usable_rows(rows: list[dict]) -> list[dict]:
    """Cuts that ran to the end: a run stopped by its time limit may have missed its peak."""
    return [r for r in rows if not r.get("hit_time_limit", False)]


def inputs_and_forces(rows: list[dict]) -> tuple[np.ndarray, np.ndarray]:
    """x in INPUTS order (the speed the knife actually had at the peak) and the windowed peak force (N)."""
    x = np.array([[r[name] for name in INPUTS] for r in rows], dtype=float)
    return x, np.array([r[TARGET] for r in rows], dtype=float)


def fit_dataset(directory: Path, seed: int = 0, held_out_fraction: float = 0.2) -> tuple[FitResult, np.ndarray, list[dict], dict]:
    header = read_header(directory)
    rows = usable_rows(read_rows(directory))
    x, y = inputs_and_forces(rows)
    return fit_force_model(x, y, seed=seed, held_out_fraction=held_out_fraction), x, rows, header


def asset_from_fit(result: FitResult, x: np.ndarray, header: dict, directory: Path, asset_path: Path) -> dict:
    ranges = {name: (float(x[:, j].min()), float(x[:, j].max())) for j, name in enumerate(INPUTS)}
    fit = {"r2_held_out": result.held_out["r2"], "max_abs_error_n": result.held_out["max_abs_error_n"],
           "rmse_n": result.held_out["rmse_n"], "samples": result.samples, "held_out": result.held_out_count,
           "monotonic_in_speed": result.monotonic_in_speed, "family": result.family,
           "cross_validated_rmse_n": result.cross_validation, "method": "scipy.optimize.nnls"}
    rows_path = Path(directory).resolve() / ROWS_FILE
    provenance = {"dataset": os.path.relpath(rows_path, Path(asset_path).resolve().parent),
                  "dataset_sha256": dataset_sha256(directory), "engine_build": ", ".join(header["engine_builds"]),
                  "quality": header["quality"], "dx_m": header.get("dx_m"),
                  "created": datetime.now(timezone.utc).isoformat(timespec="seconds")}
    return build_asset(result.model, ranges, fit, provenance)

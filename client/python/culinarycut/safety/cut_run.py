"""One sample: a cc-cut process on one thread, its summary.json and steps.csv read into one dataset row."""
from __future__ import annotations

import json
import shutil
import subprocess
import time
from pathlib import Path

import numpy as np

from culinarycut.safety.sweep import Sample, Sweep


class CutFailed(RuntimeError):
    """cc-cut refused the scene (exit 2) or the simulation failed (exit 1)."""


def _steps(path: Path, columns: tuple[str, ...]) -> dict[str, np.ndarray]:
    with open(path) as f:
        header = f.readline().strip().split(",")
    table = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2, usecols=[header.index(c) for c in columns])
    return {c: table[:, i] for i, c in enumerate(columns)}


def edge_length_m(summary: dict, resolved: dict) -> float:
    """The food's extent along the blade: the pieces' rest bounds (where their particles were sampled) projected
    on the horizontal direction across the food's long axis, which is the blade's (cc-cut's knife crosses it)."""
    axis = np.asarray(resolved["food"]["axis_direction"], dtype=float)
    blade = np.cross(axis, [0.0, 0.0, 1.0])
    blade /= np.linalg.norm(blade)
    lows = np.array([p["rest_bounds_min_m"] for p in summary["pieces"]])
    highs = np.array([p["rest_bounds_max_m"] for p in summary["pieces"]])
    # Project every corner of every box: exact for the default pose (blade along world x), an upper bound otherwise.
    corners = np.concatenate([np.where(np.array(mask)[None, :], highs, lows)
                              for mask in np.ndindex(2, 2, 2)]) @ blade
    return float(corners.max() - corners.min())


def run_sample(cc_cut: Path, sweep: Sweep, sample: Sample, workdir: Path) -> dict:
    """Run one cut in workdir (removed afterwards) and return its row (forces in N, lengths in m, times in s)."""
    workdir.mkdir(parents=True, exist_ok=True)
    try:
        scene_file = workdir / "scene.json"
        scene_file.write_text(json.dumps(sweep.scene(sample)))
        out = workdir / "out"
        started = time.perf_counter()
        proc = subprocess.run([str(cc_cut), str(scene_file), "--out", str(out), "--threads", "1", "--quiet"],
                              capture_output=True, text=True)
        wall_s = time.perf_counter() - started
        if proc.returncode != 0:
            raise CutFailed(f"cc-cut exited {proc.returncode} on {sample.key()}: {proc.stderr.strip()[-500:]}")
        report = json.loads((out / "summary.json").read_text())
        summary, resolved = report["summary"], report["resolved"]
        steps = _steps(out / "steps.csv", ("t_s", "dt_s", "knife_vz_m_s", "blade_fz_n", "edge_fz_n"))
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    descending = steps["knife_vz_m_s"] < 0
    touching = descending & (steps["blade_fz_n"] > 0)
    contact_s = float(np.sum(steps["dt_s"][touching]))
    # The knife's speed when the windowed force peaked (it is the prescribed one unless the run slowed it).
    at_peak = int(np.searchsorted(steps["t_s"], summary["peak_blade_force_time_s"]))
    at_peak = min(at_peak, len(steps["t_s"]) - 1)
    return {
        "key": sample.key(),
        "food": sample.food, "scale": sample.scale,
        "youngs_modulus_mpa": sample.youngs_modulus_mpa, "yield_stress_kpa": sample.yield_stress_kpa,
        "fracture_toughness_j_m2": sample.fracture_toughness_j_m2,
        "speed_requested_m_s": sample.speed_m_s,
        "speed_m_s": float(abs(steps["knife_vz_m_s"][at_peak])),
        "edge_length_m": edge_length_m(summary, resolved),
        "peak_blade_force_n": summary["peak_blade_force_n"],
        "peak_blade_force_time_s": summary["peak_blade_force_time_s"],
        "peak_substep_blade_force_n": summary["peak_substep_blade_force_n"],
        # Mean while the descending blade is pressed: its impulse over the contact time.
        "mean_blade_force_n": float(np.sum((steps["blade_fz_n"] * steps["dt_s"])[touching]) / contact_s)
        if contact_s > 0 else 0.0,
        "peak_substep_edge_force_n": float(steps["edge_fz_n"].max()),
        "contact_time_s": contact_s,
        "pieces": len(summary["pieces"]),
        "particles": resolved["particles"], "dx_m": resolved["dx_m"], "dt_s": resolved["dt_s"],
        "substeps": summary["substeps"], "sim_time_s": summary["sim_time_s"],
        "hit_time_limit": summary["hit_time_limit"],
        "wall_s": round(wall_s, 3),
    }

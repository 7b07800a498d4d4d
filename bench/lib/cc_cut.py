"""One cc-cut run and its windowed force, and the cut scenes the physics benchmarks give it.

Each run is one cc-cut process on one thread; the windowed force is the blade impulse over the last 5 ms
(cc-cut's accumulation window) divided by 5 ms, read against the depth of the edge in the food.
"""
from __future__ import annotations

import csv
import functools
import json
import math
import subprocess
import time
from pathlib import Path

import numpy as np

WINDOW_S = 0.005
SCALE = 0.6  # small foods keep the fine runs to seconds
# The world advances the food once per robot physics step (500 Hz) and slows the knife by the food's
# speed resistance summed over that step (sim/world/food_step.cc).
ROBOT_PHYSICS_STEP_S = 0.002
CUTTING = {"mpm": True, "plasticity": True, "damage": True, "friction": True, "force_sensing": True}


@functools.cache
def engine_presets(cc_cut: Path | None = None) -> dict:
    """The engine's quality presets and MPM bounds (`cc-cut --presets`, sim/world/quality_preset.cc their one
    source), read once per binary so the benchmarks keep no copy."""
    from culinarycut.safety.binary import cc_cut_presets
    from bench.harness.paths import cc_cut as built_cc_cut
    try:
        return cc_cut_presets(cc_cut or built_cc_cut())
    except ValueError as err:
        raise SystemExit(f"error: cannot read the engine's presets: {err}, or set $CULINARYCUT_BUILD") from None


def scene(food: str, dx_m: float, speed_m_s: float, overrides: dict | None = None) -> dict:
    """The validation cut: the 0.6-scale food cut in the middle at dx_m, 8 particles per cell, CFL 0.2."""
    obj = {"food": food, "scale": SCALE, "pose": {"position": [0.5, 0.0]}}
    if overrides:
        obj["material_overrides"] = overrides
    return {"description": f"physics validation: {food} at dx {dx_m * 1e3:g} mm",
            "scene": {"effects": dict(CUTTING), "objects": [obj], "quality": "standard",
                      "mpm": {"dx": dx_m, "particles_per_cell": 8, "cfl": 0.2}, "seed": 0},
            "solver": {"threads": 1},
            "knife": {"cut_fraction": 0.5, "start_above_top_m": 0.003, "end_below_bottom_m": 0.001,
                      "descent_speed_m_s": speed_m_s, "lift_speed_m_s": 1.0, "settle_s": 0.02,
                      "force_window_s": WINDOW_S}}


def _turned(degrees: float) -> list[float]:
    """The quaternion [w, x, y, z] of a turn about the vertical."""
    half = math.radians(degrees) / 2.0
    return [math.cos(half), 0.0, 0.0, math.sin(half)]


def preset_scene(food: str = "cucumber", yaw_deg: float = 0.0, overrides: dict | None = None, speed_m_s: float = 0.5,
                 knife: dict | None = None, quality: str = "standard") -> dict:
    """The 0.6-scale food cut at a quality preset (its own resolution); `knife` overrides the knife path (a value
    of None removes that key)."""
    obj = {"food": food, "scale": SCALE, "pose": {"position": [0.5, 0.0]}}
    if yaw_deg:
        obj["pose"]["quaternion"] = _turned(yaw_deg)
    if overrides:
        obj["material_overrides"] = overrides
    knife_path = {"cut_fraction": 0.5, "start_above_top_m": 0.003, "end_below_bottom_m": 0.001,
                  "descent_speed_m_s": speed_m_s, "lift_speed_m_s": 1.0, "settle_s": 0.02, "force_window_s": WINDOW_S,
                  "max_time_s": 20.0, **(knife or {})}
    return {"description": f"physics case: {food}",
            "scene": {"effects": dict(CUTTING), "objects": [obj], "quality": quality, "seed": 0},
            "solver": {"threads": 1},
            "knife": {key: value for key, value in knife_path.items() if value is not None}}


def knife_speed_factor(t_s: np.ndarray, speed_factor: np.ndarray, in_food: np.ndarray) -> float:
    """The world's knife speed over the commanded one, averaged over the robot physics steps the edge spends
    in the food: each step's factor is 1 / (1 + u sum(k2 c-hat dt)) over its substeps, and cc-cut's per-substep
    factor 1 / (1 + u k2 c-hat dt) gives each term u k2 c-hat dt = 1 / factor - 1."""
    step = np.floor(t_s / ROBOT_PHYSICS_STEP_S).astype(int)
    terms = 1.0 / speed_factor - 1.0
    steps = np.unique(step[in_food])
    if len(steps) == 0:
        return 1.0
    sums = np.bincount(step, weights=terms)[steps]
    return float(np.mean(1.0 / (1.0 + sums)))


def run(cc_cut: Path, spec: dict, workdir: Path, particles_npz: Path | None = None) -> dict:
    """One cc-cut run: the windowed blade and edge force against the edge's depth below the food's top. With
    `particles_npz`, every particle's rest and final position and piece are saved there (numpy, compressed)."""
    scene_file = workdir / "scene.json"
    scene_file.write_text(json.dumps(spec))
    out = workdir / "out"
    started = time.perf_counter()
    subprocess.run([str(cc_cut), str(scene_file), "--out", str(out), "--threads", "1", "--quiet",
                    *(["--particles"] if particles_npz else [])], check=True)
    wall_s = time.perf_counter() - started
    if particles_npz:
        table = np.loadtxt(out / "particles.csv", delimiter=",", skiprows=1, dtype=np.float64, ndmin=2)
        np.savez_compressed(particles_npz, rest_m=table[:, 0:3].astype(np.float32),
                            final_m=table[:, 3:6].astype(np.float32), piece=table[:, 6].astype(np.int32))
    written = json.loads((out / "summary.json").read_text())
    summary = written["summary"]
    with open(out / "steps.csv") as f:
        rows = list(csv.DictReader(f))
    col = {k: np.array([float(r[k]) for r in rows])
           for k in ("t_s", "dt_s", "knife_z_m", "knife_vz_m_s", "blade_fz_n", "edge_fz_n", "speed_factor")}
    blade = np.cumsum(col["blade_fz_n"] * col["dt_s"])
    edge = np.cumsum(col["edge_fz_n"] * col["dt_s"])
    t = col["t_s"]
    start = np.searchsorted(t, t - WINDOW_S)
    span = np.maximum(t - t[start], 1e-12)
    blade_w = (blade - blade[start]) / span
    edge_w = (edge - edge[start]) / span
    descending = np.arange(len(t)) <= int(np.argmin(col["knife_z_m"]))
    top_m = col["knife_z_m"][0] - spec["knife"]["start_above_top_m"]
    return {"depth_mm": ((top_m - col["knife_z_m"][descending]) * 1e3).tolist(),
            "blade_n": blade_w[descending].tolist(), "edge_n": edge_w[descending].tolist(),
            "peak_blade_n": float(blade_w.max()), "peak_edge_n": float(edge_w.max()),
            # Work of the edge on the food while the knife descends: force times the distance it moved.
            "edge_work_j": float(np.sum((col["edge_fz_n"] * -col["knife_vz_m_s"] * col["dt_s"])[descending])),
            "pieces": len(summary["pieces"]),
            "cut_fraction": summary["cut_fractions"][0] if summary["cut_fractions"] else None,
            "j_clamps": summary["j_clamps"], "speed_caps": summary["speed_caps"],
            "substeps": summary["substeps"], "particles": sum(p["particles"] for p in summary["pieces"]),
            "wall_s": wall_s, "sim_time_s": summary["sim_time_s"], "max_rss_mb": summary["peak_memory_mb"],
            # The solver's own time (no process start), in all and per stage.
            "solver_wall_s": summary["wall_time_ms"]["total"] / 1e3,
            "stage_s": {s: summary["wall_time_ms"][s] / 1e3 for s in ("setup", "p2g", "grid", "g2p")},
            "cut_fractions": summary["cut_fractions"], "food_length_m": written["resolved"]["food"]["length_m"],
            "piece_volumes_m3": sorted(p["volume_m3"] for p in summary["pieces"]),
            "kinetic_to_elastic_energy": summary.get("kinetic_to_elastic_energy"),
            "knife_speed_factor": knife_speed_factor(t, col["speed_factor"],
                                                     descending & (col["knife_z_m"] < top_m)),
            "active_particle_fraction": summary.get("active_particle_fraction", 1.0)}

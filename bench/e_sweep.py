#!/usr/bin/env python3
"""The paper's E-sweep as a reproducible study: the scripted oracle cuts a cucumber whose Young's
modulus runs from 0.1 to 0.9 MPa, through the robot (two-way coupled: the food's wrench acts on the
Panda), and we record the peak wrist force (averaged over each 50 ms control step, the world's
accumulation window) and the knife's speed just after impact, beside the paper's numbers.
Writes docs/benchmarks/e_sweep.{md,json} and docs/images/e_sweep.png.

    .venv/bin/python bench/e_sweep.py [--quality draft]
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from datetime import date
from pathlib import Path

import numpy as np
from culinarycut import Client
from culinarycut.launch import ServerProcess, server_binary
from culinarycut.policies import run_oracle_episode
from culinarycut.scenes import cut_cucumber_scene

sys.path.insert(0, str(Path(__file__).resolve().parent))
from step_latency import machine_info  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
YOUNGS_MPA = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]
# The paper's reported end points ("Force magnitudes", supplement): peak force and post-impact speed.
PAPER = {"force_n": {0.1: 69.96, 0.9: 77.34}, "speed_m_s": {0.1: 0.22, 0.9: 0.02}}
IMPACT_WINDOW_STEPS = 2  # post-impact speed: mean TCP speed over the 2 control steps after first contact


def episode(client: Client, youngs_mpa: float, quality: str) -> dict:
    scene = cut_cucumber_scene(quality=quality, cameras=(), real_material=True)
    scene["objects"][0]["material_overrides"] = {"youngs_modulus_pa": youngs_mpa * 1e6}
    started = time.perf_counter()
    trace = run_oracle_episode(client, scene, seed=0)
    forces = np.linalg.norm(np.asarray(trace["wrist_force_n"]), axis=1)
    first = trace["first_contact_step"]
    tcp_z = np.asarray(trace["tcp_z_m"])
    dt = trace["time_s"][1] - trace["time_s"][0]
    speed_after = None
    if first is not None and first + IMPACT_WINDOW_STEPS < len(tcp_z):
        speed_after = float(abs(tcp_z[first + IMPACT_WINDOW_STEPS] - tcp_z[first]) / (IMPACT_WINDOW_STEPS * dt))
    speed_before = float(abs(tcp_z[first - 1] - tcp_z[first - 3]) / (2 * dt)) if first and first >= 3 else None
    return {"youngs_mpa": youngs_mpa, "peak_force_n": float(forces.max()), "success": trace["success"],
            "pieces": trace["pieces"], "speed_before_impact_m_s": speed_before,
            "speed_after_impact_m_s": speed_after, "complete": trace["complete"],
            "wall_s": time.perf_counter() - started, "time_s": trace["time_s"], "force_n": forces.tolist()}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quality", default="draft", choices=["draft", "standard"])
    parser.add_argument("--out", default=str(ROOT / "docs" / "benchmarks"))
    args = parser.parse_args()
    results = []
    with ServerProcess(server_binary()) as server, Client(server.address, timeout_s=600) as client:
        for youngs_mpa in YOUNGS_MPA:
            results.append(episode(client, youngs_mpa, args.quality))
            r = results[-1]
            print(f"E {youngs_mpa:.1f} MPa: peak {r['peak_force_n']:.1f} N, speed {r['speed_before_impact_m_s']} -> "
                  f"{r['speed_after_impact_m_s']} m/s, success {r['success']}, {r['wall_s']:.0f} s", flush=True)
    machine = {**machine_info(), "date": date.today().isoformat()}
    out = Path(args.out)
    (out / "e_sweep.json").write_text(json.dumps({"machine": machine, "quality": args.quality, "results": results}))
    _plot(results, ROOT / "docs" / "images" / "e_sweep.png")
    (out / "e_sweep.md").write_text(_markdown(results, machine, args.quality))
    print(f"wrote {out / 'e_sweep.md'}")
    return 0


def _plot(results: list[dict], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, (force, speed) = plt.subplots(1, 2, figsize=(10, 3.4))
    e = [r["youngs_mpa"] for r in results]
    force.plot(e, [r["peak_force_n"] for r in results], "o-", label="CulinaryCut (this build)")
    force.plot(list(PAPER["force_n"]), list(PAPER["force_n"].values()), "s--", label="paper (end points)")
    force.set_xlabel("Young's modulus E (MPa)")
    force.set_ylabel("peak wrist force (N, 50 ms mean)")
    force.legend(fontsize=8)
    force.grid(alpha=0.3)
    speed.plot(e, [r["speed_after_impact_m_s"] or np.nan for r in results], "o-", label="CulinaryCut (this build)")
    speed.plot(list(PAPER["speed_m_s"]), list(PAPER["speed_m_s"].values()), "s--", label="paper (end points)")
    speed.set_xlabel("Young's modulus E (MPa)")
    speed.set_ylabel("knife speed after impact (m/s)")
    speed.legend(fontsize=8)
    speed.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=110)


def _markdown(results: list[dict], machine: dict, quality: str) -> str:
    lines = ["# The paper's E-sweep, reproduced through the robot", "",
             "Generated by `bench/e_sweep.py`: the scripted oracle cuts a full-size cucumber in the scene "
             f"\"cut the cucumber at 0.3 ratio from the left\" at the `{quality}` preset, E from 0.1 to 0.9 MPa (the "
             "cucumber preset's other values), seed 0, no cameras. Peak force: the largest wrist force, each "
             "averaged over its 50 ms control step. Speed: the knife's descent speed over the 2 control steps "
             "after first contact (and over 2 steps before it).", "",
             f"Machine: {machine['cpu_model']}, {machine['cores']} cores, {machine['platform']}; {machine['date']}.", "",
             "| E (MPa) | peak force (N) | paper (N) | speed before (m/s) | speed after (m/s) | paper (m/s) | cut | wall s |",
             "|---|---|---|---|---|---|---|---|"]
    for r in results:
        e = r["youngs_mpa"]
        fmt = lambda v: "-" if v is None else f"{v:.3f}"  # noqa: E731
        lines.append(f"| {e:.1f} | {r['peak_force_n']:.1f} | {PAPER['force_n'].get(e, '')} | "
                     f"{fmt(r['speed_before_impact_m_s'])} | {fmt(r['speed_after_impact_m_s'])} | "
                     f"{PAPER['speed_m_s'].get(e, '')} | {'yes' if r['success'] else 'no'} ({r['pieces']} pieces) | "
                     f"{r['wall_s']:.0f} |")
    lines += ["", "![E-sweep](../images/e_sweep.png)", "",
              "## How this differs from the paper, and why",
              "- The paper's knife strikes at up to several m/s (its policies' actions); the oracle descends at "
              "a few cm/s, so the impact is gentle and the speed after it is the servo's, not a collision's. "
              "The knife is slowed only by the food's measured wrench acting on the robot (joint torques J^T f), "
              "which the joint servo overcomes, and by the quadratic speed resistance u / (1 + k2 c-hat u dt) with "
              "k2 = 50 (E / 1 MPa) per (m/s) per s: at 5 cm/s and a 2 ms physics step that is under 0.1 % per step, "
              "so the speed after impact does not follow E as the paper's does. Making the resistance come from the "
              "measured force instead of a constant is part of the cutting-physics work still open.",
              "- Our peak force is the force it takes to push the knife through the food at this grid, which still "
              "depends on the grid spacing (docs/mpm.md, \"Blade thickness\"); until fracture answers to a toughness "
              "the numbers are not a calibrated prediction. The paper reports only the two end points, so the "
              "dashed lines join them straight."]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.exit(main())

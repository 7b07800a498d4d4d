#!/usr/bin/env python3
"""The paper's E-sweep as a reproducible study: the scripted oracle cuts a cucumber whose Young's
modulus runs from 0.1 to 0.9 MPa, through the robot (two-way coupled: the food's wrench acts on the
Panda), and we record the peak wrist force (averaged over each 50 ms control step, the world's
accumulation window) and the knife's speed just after impact, beside the paper's numbers.
Writes docs/benchmarks/e_sweep.{md,json} and docs/images/e_sweep.png.

    .venv/bin/python bench/e_sweep.py [--quality draft] [--render-only]
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from culinarycut import Client
from culinarycut.launch import ServerProcess, server_binary
from culinarycut.policies import run_oracle_episode
from culinarycut.scenes import cut_cucumber_scene

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import Docs, arguments, dated_machine_info, docs_for, pyplot, save_figure  # noqa: E402
from bench.lib import quick  # noqa: E402

PAGE, RESULTS = "benchmarks/e_sweep.md", "benchmarks/e_sweep.json"
YOUNGS_MPA = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]
# The paper's reported end points ("Force magnitudes", supplement): peak force and post-impact speed.
PAPER = {"force_n": {0.1: 69.96, 0.9: 77.34}, "speed_m_s": {0.1: 0.22, 0.9: 0.02}}
IMPACT_WINDOW_STEPS = 2  # post-impact speed: mean TCP speed over the 2 control steps after first contact


def episode(client: Client, youngs_mpa: float, quality: str, tiny: bool = False) -> dict:
    scene = cut_cucumber_scene(quality=quality, cameras=())
    scene = quick.food_scene(scene, coarse=True) if tiny else scene  # the smoke pass: a coarse strawberry
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
    parser = arguments(__doc__, render_only=True)
    parser.add_argument("--quality", default="draft", choices=["draft", "standard"])
    parser.add_argument("--out", type=Path, default=None, help="the folder of the page and JSON "
                                                               "(default docs/benchmarks)")
    args = parser.parse_args()
    docs = docs_for(args, args.out)
    if args.render_only:
        write_outputs(docs.stored(RESULTS), docs)
        return 0
    results = []
    with ServerProcess(server_binary()) as server, Client(server.address, timeout_s=600) as client:
        for youngs_mpa in YOUNGS_MPA[-1:] if args.quick else YOUNGS_MPA:
            results.append(episode(client, youngs_mpa, args.quality, args.quick))
            r = results[-1]
            print(f"E {youngs_mpa:.1f} MPa: peak {r['peak_force_n']:.1f} N, speed {r['speed_before_impact_m_s']} -> "
                  f"{r['speed_after_impact_m_s']} m/s, success {r['success']}, {r['wall_s']:.0f} s", flush=True)
    stored = {"machine": dated_machine_info(), "quality": args.quality, "results": results}
    docs.write_json(RESULTS, stored, __file__, indent=None)
    write_outputs(stored, docs)
    print(f"wrote {docs.path(PAGE)}")
    return 0


def write_outputs(stored: dict, docs: Docs) -> None:
    _plot(stored["results"], docs.image("e_sweep.png"))
    docs.write_page(PAGE, _markdown(stored["results"], stored["machine"], stored["quality"]), __file__, RESULTS, stored)


def _plot(results: list[dict], path: Path) -> None:
    figure, (force, speed) = pyplot().subplots(1, 2, figsize=(10, 3.4))
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
    save_figure(figure, path)


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
              "so the speed after impact does not follow E as the paper's does.",
              "- Our peak force is what it takes to push the knife through the food: the edge pushes with at most "
              "the food's edge toughness G_c times the length of edge in it (the cucumber's 488 J/m^2, calibrated "
              "against LS-DYNA references in docs/physics_validation.md, times its 4-5 cm width: about 20-24 N; "
              "docs/mpm.md), plus the faces' friction. E decides how far the food gives before the edge cuts, not "
              f"that force, so the peak stays at {min(r['peak_force_n'] for r in results):.1f}-"
              f"{max(r['peak_force_n'] for r in results):.1f} N across the sweep. The paper's "
              "70-77 N, rising about 10 % with E, comes from a knife striking at policy speeds with a contact model "
              "it does not calibrate; we do not reproduce its absolute values, and the paper reports only the two "
              "end points, so the dashed lines join them straight."]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.exit(main())

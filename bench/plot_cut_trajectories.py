#!/usr/bin/env python3
"""Planned and executed knife trajectories for every cut style, like the paper's supplement figure
"Trajectory visualization": the scripted oracle runs each task on a real server (robot only, with a
cucumber-sized box as the object) and the planned TCP path is drawn with the one the robot followed.

Writes docs/images/cut_trajectories.png and docs/benchmarks/oracle_tracking.{md,json} (how closely the
knife followed each plan, and how the resulting blade plane scores).

Usage: .venv/bin/python bench/plot_cut_trajectories.py [--control-mode pd_ee_pose_quat] [--seed 0]
Needs python3-matplotlib (Debian).
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from culinarycut import Client
from culinarycut.cli_tasks import DEFAULT_OBJECT
from culinarycut.geometry import quat_rotate
from culinarycut.launch import ServerProcess
from culinarycut.policies import ScriptedOracle

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import arguments, docs_for, machine_info, pyplot, save_figure, today  # noqa: E402

PAGE, RESULTS = "benchmarks/oracle_tracking.md", "benchmarks/oracle_tracking.json"
TASKS = [  # (panel title, instruction) in the order of the paper's figure, plus guillotine
    ("(A) Normal + Middle", "cut the cucumber at the middle"),
    ("(B) Normal + Split 3", "cut the cucumber into three equal pieces"),
    ("(C) Normal + Split 4", "cut the cucumber into four equal pieces"),
    ("(D) Normal + Split 5", "cut the cucumber into five equal pieces"),
    ("(E) Saw + Middle", "saw cut the cucumber at the middle"),
    ("(F) Bias + Middle", "bias cut the cucumber at the middle"),
    ("(G) Guillotine + Ratio 0.3 left", "guillotine cut the cucumber at 0.3 ratio from the left"),
    ("(H) Normal + Ratio 0.3 right", "cut the cucumber at 0.3 ratio from the right"),
]


def run_task(client: Client, instruction: str, control_mode: str, seed: int) -> dict:
    sid = client.create_session(None).session_id
    try:
        client.reset(sid, seed=seed)
        oracle = ScriptedOracle(client, sid)
        plan = oracle.reset(instruction, objects=[DEFAULT_OBJECT], control_mode=control_mode, seed=seed)
        fine = client.tasks.plan_cut(DEFAULT_OBJECT, np.asarray(client.observe(sid).observation.tcp_pose),
                                     instruction=instruction, seed=seed, sample_rate_hz=200)
        times, poses, phases = [], [], []
        while True:
            mode, values = oracle.act()
            if oracle.finished:
                break
            response = client.step(sid, mode, values)
            times.append(response.stamp.sim_time)
            poses.append(np.asarray(response.observation.tcp_pose))
            phases.append(oracle.phase)
    finally:
        client.close_session(sid)
    poses = np.asarray(poses)
    # Blade plane distance to each target while cutting, and the score of the deepest blade plane.
    worst_mm, cuts = 0.0, []
    for cut in plan["cuts"]:
        window = [(t > cut["start_time_s"] + 0.2) and (t < cut["end_time_s"]) for t in times]
        inside = poses[np.asarray(window)]
        for pose in inside:
            normal = quat_rotate(pose[3:], [0, 1, 0])
            worst_mm = max(worst_mm, abs(np.dot(cut["target_point_m"] - pose[:3], normal)) * 1e3)
        if len(inside):
            deepest = inside[np.argmin(inside[:, 2])]
            cuts.append({"object_name": DEFAULT_OBJECT["name"], "plane_point_m": deepest[:3],
                         "plane_normal": quat_rotate(deepest[3:], [0, 1, 0])})
    score = client.tasks.score_cuts(plan["spec"], DEFAULT_OBJECT, cuts)
    return {"plan": plan, "fine": fine, "times": np.asarray(times), "poses": poses, "worst_mm": worst_mm,
            "score": score, "lowest_mm": poses[:, 2].min() * 1e3}


def plot(results: list[tuple[str, str, dict]], path: Path) -> None:
    fig, axes = pyplot().subplots(2, 4, figsize=(16, 7.5), sharey=True, squeeze=False)
    for ax, (title, _, result) in zip(axes.ravel(), results):
        fine, poses = result["fine"], result["poses"]
        for k, (label, color) in enumerate([("x", "tab:red"), ("y", "tab:green"), ("z", "tab:blue")]):
            ax.plot(fine["time_s"], fine["tcp_pose"][:, k] * 1e3, color=color, lw=1.0, alpha=0.5,
                    label=f"planned {label}")
            ax.plot(result["times"], poses[:, k] * 1e3, color=color, lw=0, marker=".", ms=2.5,
                    label=f"executed {label}")
        for cut in result["plan"]["cuts"]:
            ax.axvspan(cut["start_time_s"], cut["end_time_s"], color="0.85", zorder=0)
        verdict = "success" if result["score"]["success"] else "FAIL"
        ax.set_title(f"{title}\n{verdict}, blade plane within {result['worst_mm']:.2f} mm", fontsize=9)
        ax.set_xlabel("time (s)")
        ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel("TCP position (mm, world)")
    axes[1, 0].set_ylabel("TCP position (mm, world)")
    axes[0, 0].legend(fontsize=7, ncol=2, loc="upper right")
    fig.suptitle("Scripted-oracle knife (TCP) trajectories: planned (lines) and executed at 20 Hz (dots); "
                 "grey = knife in the food", fontsize=11)
    fig.tight_layout()
    save_figure(fig, path)


def markdown(stored: dict) -> str:
    machine = stored["machine"]
    lines = ["# Scripted oracle: planned vs executed cuts", "",
             f"Generated by `bench/plot_cut_trajectories.py --control-mode {stored['control_mode']} --seed "
             f"{stored['seed']}` on {stored['date']}: the scripted oracle plans each task for a 0.20 x 0.04 x 0.04 m "
             "cucumber-sized box lying along y at (0.5, 0.02, 0.04) m and drives the knife through a robot-only "
             "session of the real server. The scene has no food, so the knife cuts air: this measures the plan "
             "and the controller, not cutting forces (those are the robot episodes', e.g. "
             "[cut_episode.md](cut_episode.md)). A cut is correct when the deepest blade plane scores as the task's "
             "cut, position and angle.", "",
             f"Machine: {machine['cpu_model']}, {machine['cores']} cores, {machine['platform']}.", "",
             "| task | instruction | plan (s) | cuts correct | worst blade-plane distance to target while cutting (mm) "
             "| lowest TCP z (mm; object bottom 20) |",
             "|---|---|---|---|---|---|"]
    for row in stored["tasks"]:
        lines.append(f"| {row['title']} | {row['instruction']} | {row['plan_s']:.1f} | "
                     f"{row['cuts_correct']} / {row['cuts_required']} | {row['worst_mm']:.2f} | "
                     f"{row['lowest_mm']:.1f} |")
    lines += ["", "![trajectories](../images/cut_trajectories.png)", ""]
    return "\n".join(lines)


def main() -> int:
    parser = arguments(__doc__, whole_doc=True)
    parser.add_argument("--control-mode", default="pd_ee_pose_quat")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    docs = docs_for(args)
    results = []
    with ServerProcess() as server, Client(server.address) as client:
        for title, instruction in TASKS[:1] if args.quick else TASKS:
            result = run_task(client, instruction, args.control_mode, args.seed)
            print(f"{title:<34} {result['score']['summary']}; blade plane within {result['worst_mm']:.2f} mm, "
                  f"{result['plan']['duration_s']:.1f} s", flush=True)
            results.append((title, instruction, result))
    image = docs.image("cut_trajectories.png")
    plot(results, image)
    stored = {"machine": machine_info(), "date": today(), "timestamp": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
              "control_mode": args.control_mode, "seed": args.seed,
              "tasks": [{"title": title, "instruction": instruction, "plan_s": r["plan"]["duration_s"],
                         "cuts_correct": r["score"]["cuts_correct"], "cuts_required": r["score"]["cuts_required"],
                         "success": bool(r["score"]["success"]), "summary": r["score"]["summary"],
                         "worst_mm": float(r["worst_mm"]), "lowest_mm": float(r["lowest_mm"])}
                        for title, instruction, r in results]}
    docs.publish(PAGE, markdown(stored), RESULTS, stored, __file__)
    print(f"wrote {image} and {docs.path(PAGE)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

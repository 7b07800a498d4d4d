#!/usr/bin/env python3
"""How pd_ee_pose_quat converges: random knife poses above the board, each from the ready pose, driven
through the real server. Writes docs/benchmarks/ee_pose_tracking.md and a plot in docs/images/.

Usage: .venv/bin/python bench/ee_pose_tracking.py [--targets 24] [--seed 0]
Needs python3-matplotlib (Debian) for the plot.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from culinarycut import Client
from culinarycut.geometry import quat_angle, quat_from_axis_angle, quat_mul
from culinarycut.launch import ServerProcess

from step_latency import machine_info  # bench/, this script's folder

ROOT = Path(__file__).resolve().parents[1]

KNIFE_DOWN = np.array([0.0, 1.0, 0.0, 0.0])   # (w, x, y, z): TCP z axis pointing down
POSITION_TOLERANCE_M = 1e-3
ANGLE_TOLERANCE_RAD = np.deg2rad(1.0)
HORIZON_STEPS = 60                              # 3 s at 20 Hz


def random_target(rng: np.random.Generator) -> np.ndarray:
    """A knife pose over the cutting board: random position, yaw within +-60 deg, tilt within 15 deg."""
    position = rng.uniform([0.35, -0.2, 0.08], [0.65, 0.2, 0.35])  # m, world
    yaw = quat_from_axis_angle([0.0, 0.0, rng.uniform(-np.pi / 3, np.pi / 3)])
    tilt_axis = rng.normal(size=2)
    tilt = quat_from_axis_angle(np.r_[tilt_axis / np.linalg.norm(tilt_axis), 0.0] * rng.uniform(0, np.deg2rad(15)))
    return np.r_[position, quat_mul(tilt, quat_mul(yaw, KNIFE_DOWN))]


def track(client: Client, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position (m) and angle (rad) error after each of HORIZON_STEPS pd_ee_pose_quat steps."""
    sid = client.create_session(None).session_id
    try:
        client.reset(sid, seed=0)
        position_error, angle_error = [], []
        for _ in range(HORIZON_STEPS):
            tcp = np.asarray(client.step(sid, "pd_ee_pose_quat", target).observation.tcp_pose)
            position_error.append(np.linalg.norm(tcp[:3] - target[:3]))
            angle_error.append(quat_angle(tcp[3:], target[3:]))
        return np.array(position_error), np.array(angle_error)
    finally:
        client.close_session(sid)


def first_within(position_error, angle_error, dt) -> float:
    """Sim time (s) of the first step from which both errors stay within tolerance; inf if never."""
    inside = (position_error <= POSITION_TOLERANCE_M) & (angle_error <= ANGLE_TOLERANCE_RAD)
    for i in range(len(inside)):
        if inside[i:].all():
            return (i + 1) * dt
    return float("inf")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--targets", type=int, default=24)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("error: the plot needs matplotlib: apt-get install python3-matplotlib", file=sys.stderr)
        return 2

    rng = np.random.default_rng(args.seed)
    targets = [random_target(rng) for _ in range(args.targets)]
    with ServerProcess(max_sessions=2) as server, Client(server.address) as client:
        handshake = client.create_session(None)
        client.close_session(handshake.session_id)
        dt = handshake.control_timestep  # s per Step
        stiffness = handshake.resolved_scene.robot.joint_stiffness  # 1/s
        runs = []
        for index, target in enumerate(targets, 1):
            runs.append(track(client, target))
            print(f"target {index}/{len(targets)}: final error {runs[-1][0][-1] * 1e3:.3f} mm, "
                  f"{np.rad2deg(runs[-1][1][-1]):.3f} deg", flush=True)

    times = np.array([first_within(p, a, dt) for p, a in runs])
    final_mm = np.array([p[-1] for p, _ in runs]) * 1e3
    final_deg = np.rad2deg([a[-1] for _, a in runs])
    t = dt * np.arange(1, HORIZON_STEPS + 1)
    figure, (left, right) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for position_error, angle_error in runs:
        left.semilogy(t, np.maximum(position_error * 1e3, 1e-4), color="tab:blue", alpha=0.5)
        right.semilogy(t, np.maximum(np.rad2deg(angle_error), 1e-4), color="tab:orange", alpha=0.5)
    left.axhline(1.0, color="k", linestyle="--", label="1 mm")
    right.axhline(1.0, color="k", linestyle="--", label="1 deg")
    left.set(xlabel="sim time (s)", ylabel="TCP position error (mm)", title=f"pd_ee_pose_quat, {len(runs)} random targets")
    right.set(xlabel="sim time (s)", ylabel="TCP orientation error (deg)", title="from the ready pose, 20 Hz control")
    left.legend()
    right.legend()
    image = ROOT / "docs" / "images" / "ee_pose_tracking.png"
    figure.savefig(image, dpi=110)

    machine = machine_info()
    reached = np.isfinite(times)
    report = [
        "# pd_ee_pose_quat tracking",
        "",
        f"Measured {time.strftime('%Y-%m-%dT%H:%M:%S%z')} on {machine['cpu_model']}, {machine['cores']} cores, "
        f"through the real server (`bench/ee_pose_tracking.py --targets {args.targets} --seed {args.seed}`).",
        f"{len(runs)} random knife poses over the board (x 0.35-0.65 m, y +-0.2 m, z 0.08-0.35 m, yaw +-60 deg, "
        f"tilt up to 15 deg), each from the ready pose, with the default controller ({1 / dt:g} Hz control, "
        f"joint stiffness {stiffness:g} 1/s). A target the IK cannot reach from the arm's current "
        "configuration stays unreached (see docs/robot.md).",
        "",
        "| measure | value |",
        "|---|---|",
        f"| targets reached within 1 mm and 1 deg within 3 s | {reached.sum()} of {len(runs)} |",
        f"| time to stay within tolerance, median / max (s) | {np.median(times[reached]):.2f} / {times[reached].max():.2f} |",
        f"| final position error of reached targets, median / max (mm) | "
        f"{np.median(final_mm[reached]):.4f} / {final_mm[reached].max():.4f} |",
        f"| final orientation error of reached targets, median / max (deg) | "
        f"{np.median(final_deg[reached]):.4f} / {final_deg[reached].max():.4f} |",
        "| unreached targets: final error | " + (", ".join(
            f"#{i + 1}: {final_mm[i]:.1f} mm, {final_deg[i]:.1f} deg (IK not converged)"
            for i in np.flatnonzero(~reached)) or "none") + " |",
        "",
        "![position and orientation error over time](../images/ee_pose_tracking.png)",
    ]
    (ROOT / "docs" / "benchmarks" / "ee_pose_tracking.md").write_text("\n".join(report) + "\n")
    print(f"wrote docs/benchmarks/ee_pose_tracking.md and {image.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

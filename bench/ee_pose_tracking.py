#!/usr/bin/env python3
"""How pd_ee_pose_quat converges: random knife poses above the board, each from the ready pose, driven
through the real server. Writes docs/benchmarks/ee_pose_tracking.{md,json} and a plot in docs/images/.

Usage: .venv/bin/python bench/ee_pose_tracking.py [--targets 24] [--seed 0] [--render-only]
Needs python3-matplotlib (Debian) for the plot.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from culinarycut import Client
from culinarycut.geometry import quat_angle, quat_from_axis_angle, quat_mul
from culinarycut.launch import ServerProcess

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import arguments, docs_for, machine_info, pyplot, save_figure, today  # noqa: E402

PAGE, RESULTS = "benchmarks/ee_pose_tracking.md", "benchmarks/ee_pose_tracking.json"
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
    inside = (np.asarray(position_error) <= POSITION_TOLERANCE_M) & (np.asarray(angle_error) <= ANGLE_TOLERANCE_RAD)
    for i in range(len(inside)):
        if inside[i:].all():
            return (i + 1) * dt
    return float("inf")


def measure(targets: int, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    poses = [random_target(rng) for _ in range(targets)]
    with ServerProcess(max_sessions=2) as server, Client(server.address) as client:
        handshake = client.create_session(None)
        client.close_session(handshake.session_id)
        dt = handshake.control_timestep  # s per Step
        stiffness = handshake.resolved_scene.robot.joint_stiffness  # 1/s
        runs = []
        for index, target in enumerate(poses, 1):
            position_error, angle_error = track(client, target)
            runs.append({"target": target.tolist(), "position_error_m": position_error.tolist(),
                         "angle_error_rad": angle_error.tolist()})
            print(f"target {index}/{len(poses)}: final error {position_error[-1] * 1e3:.3f} mm, "
                  f"{np.rad2deg(angle_error[-1]):.3f} deg", flush=True)
    return {"machine": machine_info(), "date": today(), "timestamp": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
            "targets": targets, "seed": seed, "control_timestep_s": dt, "joint_stiffness_per_s": stiffness,
            "position_tolerance_m": POSITION_TOLERANCE_M, "angle_tolerance_rad": float(ANGLE_TOLERANCE_RAD),
            "runs": runs}


def plot(stored: dict, path: Path) -> None:
    runs, dt = stored["runs"], stored["control_timestep_s"]
    t = dt * np.arange(1, len(runs[0]["position_error_m"]) + 1)
    figure, (left, right) = pyplot().subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for run in runs:
        left.semilogy(t, np.maximum(np.asarray(run["position_error_m"]) * 1e3, 1e-4), color="tab:blue", alpha=0.5)
        right.semilogy(t, np.maximum(np.rad2deg(run["angle_error_rad"]), 1e-4), color="tab:orange", alpha=0.5)
    left.axhline(1.0, color="k", linestyle="--", label="1 mm")
    right.axhline(1.0, color="k", linestyle="--", label="1 deg")
    left.set(xlabel="sim time (s)", ylabel="TCP position error (mm)", title=f"pd_ee_pose_quat, {len(runs)} random targets")
    right.set(xlabel="sim time (s)", ylabel="TCP orientation error (deg)",
              title=f"from the ready pose, {1 / dt:g} Hz control")
    left.legend()
    right.legend()
    save_figure(figure, path)


def markdown(stored: dict) -> str:
    runs, dt, machine = stored["runs"], stored["control_timestep_s"], stored["machine"]
    times = np.array([first_within(r["position_error_m"], r["angle_error_rad"], dt) for r in runs])
    final_mm = np.array([r["position_error_m"][-1] for r in runs]) * 1e3
    final_deg = np.rad2deg([r["angle_error_rad"][-1] for r in runs])
    reached = np.isfinite(times)
    horizon_s = dt * len(runs[0]["position_error_m"])
    median_max = lambda v: f"{np.median(v):.4f} / {v.max():.4f}" if len(v) else "-"  # noqa: E731
    report = [
        "# pd_ee_pose_quat tracking",
        "",
        f"Measured {stored['timestamp']} on {machine['cpu_model']}, {machine['cores']} cores, "
        f"through the real server (`bench/ee_pose_tracking.py --targets {stored['targets']} --seed {stored['seed']}`).",
        f"{len(runs)} random knife poses over the board (x 0.35-0.65 m, y +-0.2 m, z 0.08-0.35 m, yaw +-60 deg, "
        f"tilt up to 15 deg), each from the ready pose, with the default controller ({1 / dt:g} Hz control, "
        f"joint stiffness {stored['joint_stiffness_per_s']:g} 1/s). A target the IK cannot reach from the arm's "
        "current configuration stays unreached (see docs/robot.md).",
        "",
        "| measure | value |",
        "|---|---|",
        f"| targets reached within 1 mm and 1 deg within {horizon_s:g} s | {reached.sum()} of {len(runs)} |",
        "| time to stay within tolerance, median / max (s) | "
        + (f"{np.median(times[reached]):.2f} / {times[reached].max():.2f}" if reached.any() else "-") + " |",
        f"| final position error of reached targets, median / max (mm) | {median_max(final_mm[reached])} |",
        f"| final orientation error of reached targets, median / max (deg) | {median_max(final_deg[reached])} |",
        "| unreached targets: final error | " + (", ".join(
            f"#{i + 1}: {final_mm[i]:.1f} mm, {final_deg[i]:.1f} deg (IK not converged)"
            for i in np.flatnonzero(~reached)) or "none") + " |",
        "",
        "![position and orientation error over time](../images/ee_pose_tracking.png)",
    ]
    return "\n".join(report) + "\n"


def main() -> int:
    parser = arguments(__doc__, whole_doc=True, render_only=True)
    parser.add_argument("--targets", type=int, default=24)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    docs = docs_for(args)
    if args.render_only:
        stored = docs.stored(RESULTS)
    else:
        stored = measure(2 if args.quick else args.targets, args.seed)
        docs.write_json(RESULTS, stored, __file__)
    plot(stored, docs.image("ee_pose_tracking.png"))
    docs.write_page(PAGE, markdown(stored), __file__, RESULTS, stored)
    print(f"wrote {docs.path(PAGE)} and {docs.image('ee_pose_tracking.png')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

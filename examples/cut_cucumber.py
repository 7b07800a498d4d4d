#!/usr/bin/env python3
"""One cut, end to end: the scripted oracle cuts a cucumber through the server; writes the three
camera videos, a force-time plot and the scored outcome. Needs the culinarycut package (the project's
.venv has it; see README).

    .venv/bin/python examples/cut_cucumber.py                        # starts its own server
    .venv/bin/python examples/cut_cucumber.py --address 127.0.0.1:50051 --quality standard

Outputs in --out (default out/cut_cucumber): front.mp4, left.mp4, right.mp4, force.png and
result.json (the task score, the force trace, wall time per stage). Exits 1 if the cut fails.
"""
from __future__ import annotations

import argparse
import json
import sys
from contextlib import ExitStack
from pathlib import Path

import numpy as np

from culinarycut import Client
from culinarycut.launch import ServerProcess
from culinarycut.policies import run_oracle_episode
from culinarycut.scenes import CUT_CUCUMBER_INSTRUCTION, cut_cucumber_scene

CAMERAS = ("front", "left", "right")


def plot_force(trace: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    time_s = np.asarray(trace["time_s"])
    force = np.asarray(trace["wrist_force_n"])
    fig, ax = plt.subplots(figsize=(8, 3.5), dpi=120)
    ax.plot(time_s, np.linalg.norm(force, axis=1), label="|F| (N)", color="black")
    for axis, colour in zip("xyz", ("tab:red", "tab:green", "tab:blue")):
        ax.plot(time_s, force[:, "xyz".index(axis)], label=f"F{axis} (N, flange frame)", color=colour, lw=0.8)
    cut_steps = [i for i, phase in enumerate(trace["phase"]) if phase == "cut"]
    if cut_steps:
        ax.axvspan(time_s[cut_steps[0]], time_s[cut_steps[-1]], color="0.9", label="oracle's cut phase")
    if trace["first_contact_step"]:
        ax.axvline(time_s[trace["first_contact_step"] - 1], color="tab:orange", ls="--", label="first contact")
    if trace["terminated_step"]:
        ax.axvline(time_s[trace["terminated_step"] - 1], color="tab:purple", ls=":", label="task done")
    ax.set_xlabel("simulated time (s)")
    ax.set_ylabel("food force on the knife (N)")
    ax.set_title(trace["instruction"])
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--address", help="a running server; default: start one (build/server/culinarycut-server)")
    parser.add_argument("--instruction", default=CUT_CUCUMBER_INSTRUCTION)
    parser.add_argument("--quality", default="draft", choices=("draft", "standard", "fine"))
    parser.add_argument("--width", type=int, default=224)
    parser.add_argument("--height", type=int, default=224)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=Path("out/cut_cucumber"))
    args = parser.parse_args()

    import cv2  # Debian: python3-opencv

    args.out.mkdir(parents=True, exist_ok=True)
    with ExitStack() as stack:
        if args.address is None:
            server = ServerProcess(max_sessions=2, idle_timeout_s=600)
            stack.callback(server.stop)
            args.address = server.address
        client = stack.enter_context(Client(args.address, timeout_s=600))
        scene = cut_cucumber_scene(args.instruction, args.quality, args.width, args.height, CAMERAS)
        fps = 20.0  # the default control rate: one frame per step plays in real time
        writers = {name: cv2.VideoWriter(str(args.out / f"{name}.mp4"), cv2.VideoWriter_fourcc(*"mp4v"), fps,
                                         (args.width, args.height)) for name in CAMERAS}
        for name, writer in writers.items():
            stack.callback(writer.release)
            if not writer.isOpened():
                print(f"error: OpenCV cannot write {args.out / name}.mp4 (no mp4v encoder?)", file=sys.stderr)
                return 2

        def on_step(step, observation, info):
            for name, writer in writers.items():
                writer.write(observation["sensor_data"][name]["rgb"][:, :, ::-1])  # OpenCV wants BGR
            if step % 20 == 0:
                force = np.linalg.norm(observation["extra"]["wrist_wrench"][:3])
                pieces = len(info.get("food", {}).get("pieces", []))
                print(f"step {step:4d}  t={info['sim_time']:5.2f} s  |F|={force:6.2f} N  pieces={pieces}", flush=True)

        print(f"{args.instruction!r} at the {args.quality} preset on {args.address}", flush=True)
        trace = run_oracle_episode(client, scene, seed=args.seed, on_step=on_step)

    plot_force(trace, args.out / "force.png")
    (args.out / "result.json").write_text(json.dumps(trace, indent=1))
    score = trace["score"]
    print(f"{score.get('summary', 'no score') if trace['success'] else 'FAILED: ' + score.get('summary', 'no score')}; "
          f"{trace['pieces']} pieces, peak |F| {np.linalg.norm(trace['wrist_force_n'], axis=1).max():.1f} N, "
          f"{trace['steps']} steps in {trace['client_wall_s']:.1f} s")
    print(f"wrote {', '.join(f'{n}.mp4' for n in CAMERAS)}, force.png and result.json in {args.out}")
    return 0 if trace["success"] else 1


if __name__ == "__main__":
    sys.exit(main())

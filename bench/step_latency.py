#!/usr/bin/env python3
"""Step round-trip latency of a robot-only session: p50/p90/p99 (ms) and steps/s, written as JSON.
bench/robot_step_report.py runs it for the Python client's rows of docs/benchmarks/robot_step.md."""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
from culinarycut import Client
from culinarycut.errors import CulinaryCutError
from culinarycut.launch import ServerProcess, server_binary

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import machine_info, percentiles  # noqa: E402


def robot_only_scene(control_hz: float) -> dict:
    """The default scene (robot and knife, no food) at a given control rate; physics stays at 500 Hz."""
    return {"robot": {"control_frequency_hz": control_hz, "physics_frequency_hz": 500.0}}


def measure(client: Client, steps: int, warmup: int, control_hz: float) -> dict:
    sid = client.create_session(robot_only_scene(control_hz)).session_id
    try:
        client.reset(sid, seed=0)
        zeros = np.zeros(7)  # pd_joint_delta_pos: hold the current pose
        for _ in range(warmup):
            client.step(sid, "pd_joint_delta_pos", zeros)
        latency_ns = np.empty(steps, dtype=np.int64)
        server_ms = np.empty(steps)
        t_start = time.perf_counter_ns()
        for i in range(steps):
            t0 = time.perf_counter_ns()
            response = client.step(sid, "pd_joint_delta_pos", zeros)
            latency_ns[i] = time.perf_counter_ns() - t0
            server_ms[i] = response.info.step_wall_time_ms
        total_s = (time.perf_counter_ns() - t_start) * 1e-9
    finally:
        client.close_session(sid)
    ms = latency_ns * 1e-6
    server = percentiles(server_ms, (50, 99))
    return {
        "steps": steps, "warmup": warmup, "control_hz": control_hz,
        **percentiles(ms, (50, 90, 99)), "mean_ms": float(ms.mean()), "max_ms": float(ms.max()),
        "steps_per_s": steps / total_s,
        "server_step_wall_p50_ms": server["p50_ms"], "server_step_wall_p99_ms": server["p99_ms"],
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--address", help="connect to this running server (host:port) instead of starting one")
    parser.add_argument("--server", default=None, help=f"server binary to start (default {server_binary()})")
    parser.add_argument("--steps", type=int, default=2000, help="measured Step round trips")
    parser.add_argument("--warmup", type=int, default=100, help="unmeasured Steps first")
    parser.add_argument("--control-hz", type=float, default=20.0,
                        help="control rate; physics runs at 500 Hz, so 20 Hz means 25 substeps per Step")
    parser.add_argument("--out", type=Path, help="write the results as JSON here")
    args = parser.parse_args(argv)
    if args.steps < 1 or args.warmup < 0:
        parser.error("--steps must be >= 1 and --warmup >= 0")

    server = None
    try:
        if args.address:
            address = args.address
        else:
            server = ServerProcess(args.server, max_sessions=1)
            address = server.address
        with Client(address) as client:
            info = client.server_info()
            result = measure(client, args.steps, args.warmup, args.control_hz)
    except (CulinaryCutError, OSError, RuntimeError, TimeoutError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 1
    finally:
        if server is not None:
            server.stop()

    result.update({"address": address, "started_server": server is not None,
                   "server": {"version": info.version, "build_id": info.build_id},
                   "machine": machine_info(), "timestamp": time.strftime("%Y-%m-%dT%H:%M:%S%z")})
    print(f"{result['steps']} steps: p50 {result['p50_ms']:.3f} ms  p90 {result['p90_ms']:.3f} ms  "
          f"p99 {result['p99_ms']:.3f} ms  {result['steps_per_s']:.0f} steps/s  "
          f"(server sim p50 {result['server_step_wall_p50_ms']:.3f} ms; {result['machine']['cpu_model']}, "
          f"{result['machine']['cores']} cores)")
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps(result, indent=2) + "\n")
        print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Command line: `info` prints what a server offers; `demo` runs a scripted knife motion; `parse`,
`instructions` and `oracle` use the cutting tasks (see cli_tasks.py); `bench` runs benchmark suites (cli_bench.py); `data` makes datasets (cli_data.py);
`safety` makes and fits the safety module's force model (cli_safety.py); `policy serve` serves a policy over the
policy protocol (cli_policy.py)."""
from __future__ import annotations

import argparse
import sys

import numpy as np
from google.protobuf import json_format

from culinarycut import cli_bench, cli_data, cli_policy, cli_safety, cli_tasks
from culinarycut.client import Client
from culinarycut.errors import CulinaryCutError, Unavailable
from culinarycut.extras import missing_extra_message
from culinarycut.geometry import quat_angle, quat_rotate

KNIFE_DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # (w, x, y, z): 180 deg about world x, TCP z axis down
# TCP waypoints (m) above the cutting board (centred at x = 0.5 m, y = 0, top at z = 0.02 m).
WAYPOINTS = [(0.50, 0.00, 0.25), (0.50, 0.06, 0.20), (0.50, -0.06, 0.20), (0.50, 0.00, 0.15)]
REACH_TOL_M = 0.002          # a waypoint counts as reached within 2 mm ...
REACH_TOL_RAD = np.deg2rad(2)  # ... and 2 degrees
MAX_STEPS_PER_WAYPOINT = 60  # 3 s at 20 Hz
DESCENT_STEP_M = 0.01        # pd_ee_delta_pose descent per step (m; the action is normalised by 0.1 m)
DESCENT_STEPS = 5            # at most 5 cm down: stays >= 8 cm above the board top


class DemoFailure(Exception):
    """The scripted motion did not do what it should."""


def _mm(v) -> str:
    return "[" + ", ".join(f"{x * 1e3:7.1f}" for x in v) + "]"


def _line(label: str, response, target_pos) -> str:
    tcp = np.asarray(response.observation.tcp_pose)
    err = np.linalg.norm(tcp[:3] - np.asarray(target_pos)) * 1e3
    return (f"{label:<24} frame {response.stamp.frame_id:4d}  t={response.stamp.sim_time:6.2f} s  "
            f"tcp {_mm(tcp[:3])} mm  err {err:6.2f} mm")


def cmd_info(args) -> int:
    with Client(args.address, timeout_s=args.timeout) as client:
        info = client.server_info()
    if args.json:
        print(json_format.MessageToJson(info, preserving_proto_field_name=True))
        return 0
    print(f"server        {args.address}")
    print(f"version       {info.version} (build {info.build_id or '?'})")
    print(f"MPM kernels   {info.simd or '?'} (--simd; results are the same bits only within one)")
    print(f"protocol      {info.protocol}")
    print(f"capabilities  {', '.join(info.capabilities) or '-'}")
    print(f"control modes {', '.join(info.control_modes) or '-'}")
    print(f"sessions      {info.limits.active_sessions} active of {info.limits.max_sessions} max, "
          f"idle timeout {info.limits.idle_timeout_s:g} s")
    limits = info.limits
    print("connections   " + (f"at most {limits.max_connections}, {limits.max_connections_per_address} per client "
                              "address" if limits.max_connections else "unix socket, uncapped"))
    print(f"telemetry     {info.telemetry_endpoint or 'off'}")
    for index, preset in enumerate(info.quality_presets):
        expected = preset.expected
        accuracy = (f"force error {expected.force_error:.0%}, cost {expected.relative_cost:.2f}x standard"
                    if expected.measured else "unmeasured")
        print(f"{'presets' if index == 0 else '':<13} {preset.name:<9} {expected.setting:<26} {accuracy}")
    return 0


def _reach(client, sid, target, label) -> None:
    """Step pd_ee_pose_quat towards target until within tolerance, printing one line at the end."""
    for _ in range(MAX_STEPS_PER_WAYPOINT):
        response = client.step(sid, "pd_ee_pose_quat", target)
        tcp = np.asarray(response.observation.tcp_pose)
        pos_err = np.linalg.norm(tcp[:3] - target[:3])
        ang_err = quat_angle(tcp[3:], target[3:])
        if pos_err < REACH_TOL_M and ang_err < REACH_TOL_RAD:
            break
    print(_line(label, response, target[:3]) + f"  {np.rad2deg(ang_err):5.2f} deg")
    if pos_err >= REACH_TOL_M or ang_err >= REACH_TOL_RAD:
        raise DemoFailure(f"{label} not reached in {MAX_STEPS_PER_WAYPOINT} steps: "
                          f"{pos_err * 1e3:.1f} mm, {np.rad2deg(ang_err):.1f} deg off")


def _demo(client: Client) -> None:
    info = client.server_info()
    print(f"connected to {client.address}: culinarycut-server {info.version} ({info.protocol})")
    session = client.create_session(None)
    sid = session.session_id
    try:
        reset = client.reset(sid, seed=0)
        tcp0 = np.asarray(reset.observation.tcp_pose)
        q_home = list(reset.observation.agent.qpos)
        tool_z = quat_rotate(tcp0[3:], [0, 0, 1])
        print(f"session {sid}: reset seed {reset.seed}, TCP {_mm(tcp0[:3])} mm, "
              f"knife axis {np.round(tool_z, 3).tolist()}")
        # Keep the reset orientation if it already points the knife down, else use the canonical one.
        quat = tcp0[3:] if tool_z[2] < -0.95 else KNIFE_DOWN

        for i, wp in enumerate(WAYPOINTS, 1):
            _reach(client, sid, np.concatenate([wp, quat]), f"pd_ee_pose_quat wp {i}/{len(WAYPOINTS)}")

        tcp = np.asarray(client.observe(sid).observation.tcp_pose[:3])
        for i in range(1, DESCENT_STEPS + 1):
            target = tcp + [0.0, 0.0, -DESCENT_STEP_M]  # deltas are relative to the TCP at each step
            response = client.step(sid, "pd_ee_delta_pose", [0, 0, -DESCENT_STEP_M / 0.1, 0, 0, 0])
            print(_line(f"pd_ee_delta_pose dz {i}/{DESCENT_STEPS}", response, target))
            tcp = np.asarray(response.observation.tcp_pose[:3])

        for _ in range(MAX_STEPS_PER_WAYPOINT):
            response = client.step(sid, "pd_joint_pos", q_home)
            if np.max(np.abs(np.asarray(response.observation.agent.qpos) - q_home)) < 1e-3:
                break
        print(_line("pd_joint_pos home", response, tcp0[:3]))
        joint_err = np.max(np.abs(np.asarray(response.observation.agent.qpos) - q_home))
        if joint_err >= 1e-3:
            raise DemoFailure(f"pd_joint_pos did not return home: max joint error {joint_err:.4f} rad")
    finally:
        client.close_session(sid)
    print("demo finished")


def cmd_demo(args) -> int:
    with Client(args.address, timeout_s=args.timeout) as client:
        _demo(client)
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m culinarycut", description=__doc__)
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--address", default="127.0.0.1:50051", help="server host:port (default %(default)s)")
    common.add_argument("--timeout", type=float, default=30.0, help="per-RPC timeout in s (default %(default)s)")
    sub = parser.add_subparsers(dest="command", required=True,
                                metavar="{info,demo,parse,instructions,oracle,bench,data,safety,policy}")
    info = sub.add_parser("info", parents=[common], help="print the server's version, capabilities and limits")
    info.add_argument("--json", action="store_true", help="print the ServerInfo message as JSON")
    info.set_defaults(func=cmd_info)
    demo = sub.add_parser("demo", parents=[common], help="move the knife through scripted waypoints")
    demo.set_defaults(func=cmd_demo)
    cli_tasks.register(sub, common)
    cli_bench.register(sub)
    cli_data.register(sub)
    cli_safety.register(sub)
    cli_policy.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)  # for the resume hint of bench run
    if args.timeout <= 0:
        print("error: --timeout must be positive", file=sys.stderr)
        return 2
    try:
        return args.func(args)
    except Unavailable as err:
        print(f"error: cannot reach a CulinaryCut server at {args.address} ({err.details}); "
              "is culinarycut-server running and listening there?", file=sys.stderr)
        return 3
    except CulinaryCutError as err:
        print(f"error: server rejected a request: {err.code.name}: {err.details}", file=sys.stderr)
        return 4
    except DemoFailure as err:
        print(f"error: demo failed: {err}", file=sys.stderr)
        return 1
    except ModuleNotFoundError as err:
        message = missing_extra_message(err, args.command)
        if message is None:
            raise
        print(f"error: {message}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130

#!/usr/bin/env python3
"""Benchmark: what the safety limiter costs per Step, limiter off against on, measured side by side in one run
on one server (rounds alternate between the settings so drift in the machine's load touches each alike).
Writes docs/benchmarks/safety_overhead.{md,json}.

The limiter needs food in the scene (a robot-only scene refuses it), so its cost on a robot-only step is its
own stage time (StepInfo.safety_wall_time_ms, with the knife moving in free air above a food) over the median
robot-only Step round trip. Beside that, two on/off ratios of the Step round trip with food: the knife in free
air (the food's MPM asleep, the step nearly robot-only) and the oracle cutting a cucumber.

    .venv/bin/python bench/safety_overhead.py [--rounds 5 --steps 200 --cut-rounds 3]
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from culinarycut import Client
from culinarycut.launch import ServerProcess, server_binary

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import arguments, dated_machine_info, docs_for, interleaved, percentiles  # noqa: E402
from bench.lib import quick  # noqa: E402

PAGE, RESULTS = "benchmarks/safety_overhead.md", "benchmarks/safety_overhead.json"
TARGET_SHARE = 0.02  # the limiter should cost under 2 % of a robot-only step
FOOD = [{"food": "cucumber"}]
# Small end-effector steps up and down in turn: the knife moves every step and stays far above the food.
FREE_AIR_ACTIONS = (np.array([0, 0, 0.3, 0, 0, 0.0]), np.array([0, 0, -0.3, 0, 0, 0.0]))


def food_scene(limiter: bool, tiny: bool = False) -> dict:
    """The cucumber at draft with the limiter on or off; `tiny`: a coarse strawberry (the smoke pass)."""
    effects = {"mpm": True, "damage": True, "friction": True, "force_sensing": True, "safety_limiter": limiter}
    scene = {"quality": "draft", "objects": FOOD, "effects": effects,
             "task": {"instruction": "cut the cucumber in the middle"}}
    return quick.food_scene(scene, coarse=True) if tiny else scene


def free_air_times(client: Client, scene: dict | None, steps: int) -> tuple[list[float], list[float]]:
    """Step round trips (ms) and the server's safety stage time per step (ms), the knife moving in free air."""
    session = client.create_session(scene).session_id
    try:
        client.reset(session, seed=0)
        for action in FREE_AIR_ACTIONS * 5:  # warm the connection, the session and the food's settling
            client.step(session, "pd_ee_delta_pose", action)
        round_trips, safety = [], []
        for k in range(steps):
            started = time.perf_counter()
            response = client.step(session, "pd_ee_delta_pose", FREE_AIR_ACTIONS[k % 2])
            round_trips.append(1e3 * (time.perf_counter() - started))
            safety.append(response.info.safety_wall_time_ms)
    finally:
        client.close_session(session)
    return round_trips, safety


def cut_times(client: Client, scene: dict) -> tuple[list[float], list[float]]:
    """Step round trips (ms) and safety stage times (ms) of the scripted oracle cutting the scene's task."""
    session = client.create_session(scene).session_id
    try:
        client.reset(session, seed=0)
        client.tasks.start_oracle(session)
        round_trips, safety = [], []
        while True:
            action = client.tasks.oracle_action(session)
            if action.finished:
                break
            started = time.perf_counter()
            response = client.step(session, action.action.control_mode, action.action.values)
            round_trips.append(1e3 * (time.perf_counter() - started))
            safety.append(response.info.safety_wall_time_ms)
    finally:
        client.close_session(session)
    return round_trips, safety


def summary(times: list[float]) -> dict:
    return {**percentiles(times), "steps": len(times)}


def main() -> int:
    parser = arguments(__doc__)
    parser.add_argument("--rounds", type=int, default=5, help="alternating rounds of the free-air comparison")
    parser.add_argument("--steps", type=int, default=200, help="steps per round and setting")
    parser.add_argument("--cut-rounds", type=int, default=3, help="alternating oracle cuts per setting")
    parser.add_argument("--out", type=Path, default=None, help="the folder of the page and JSON "
                                                               "(default docs/benchmarks)")
    args = parser.parse_args()
    docs = docs_for(args, args.out)
    if args.quick:  # one round of 3 steps, one cut of a coarse strawberry per setting
        args.rounds, args.steps, args.cut_rounds = 1, 3, 1
    settings = {"robot only": None, "food, limiter off": food_scene(False, args.quick),
                "food, limiter on": food_scene(True, args.quick)}
    cut_settings = {"limiter off": food_scene(False, args.quick), "limiter on": food_scene(True, args.quick)}
    server = ServerProcess(server_binary())
    try:
        with Client(server.address, timeout_s=600) as client:
            free_runs = interleaved({name: (lambda s=scene: free_air_times(client, s, args.steps))
                                     for name, scene in settings.items()}, args.rounds)
            cut_runs = interleaved({name: (lambda s=scene: cut_times(client, s))
                                    for name, scene in cut_settings.items()}, args.cut_rounds)
    finally:
        server.stop()
    # Each setting's round trips (ms) over its runs, and the limiter's stage times with it on.
    free = {name: [t for times, _ in runs for t in times] for name, runs in free_runs.items()}
    free_safety = [s for _, safety in free_runs["food, limiter on"] for s in safety]
    cut = {name: [t for times, _ in runs for t in times] for name, runs in cut_runs.items()}
    cut_totals = {name: [float(np.sum(times)) for times, _ in runs] for name, runs in cut_runs.items()}  # ms per cut
    cut_safety = [s for _, safety in cut_runs["limiter on"] for s in safety]
    round_medians = {**{name: [float(np.median(times)) for times, _ in runs] for name, runs in free_runs.items()},
                     **{f"cut, {name}": [float(np.median(times)) for times, _ in runs]
                        for name, runs in cut_runs.items()}}
    robot_p50 = float(np.median(free["robot only"]))
    results = {
        "free_air": {name: summary(t) for name, t in free.items()},
        "cutting": {name: summary(t) for name, t in cut.items()},
        "round_medians_ms": round_medians,
        "safety_stage_ms": {"free_air_p50": float(np.median(free_safety)), "free_air_p90": float(np.percentile(free_safety, 90)),
                            "cutting_p50": float(np.median(cut_safety)), "cutting_p90": float(np.percentile(cut_safety, 90))},
    }
    share_free = results["safety_stage_ms"]["free_air_p50"] / robot_p50
    share_cut = results["safety_stage_ms"]["cutting_p50"] / robot_p50
    # Paired by round (the two settings ran back to back), then the median: load drift cancels within a pair.
    ratio_free = float(np.median(np.divide(round_medians["food, limiter on"], round_medians["food, limiter off"])))
    ratio_cut = float(np.median(np.divide(cut_totals["limiter on"], cut_totals["limiter off"])))
    results["cut_total_ms"] = cut_totals
    results.update(share_of_robot_step_free_air=share_free, share_of_robot_step_cutting=share_cut,
                   ratio_on_off_free_air=ratio_free, ratio_on_off_cutting=ratio_cut)
    machine = dated_machine_info()
    verdict = "under" if max(share_free, share_cut) < TARGET_SHARE else "over"
    lines = ["# The safety limiter: cost per Step", "",
             "Generated by `bench/safety_overhead.py`: one local server, the Python client, draft MPM, 20 Hz "
             f"control; settings alternate round by round ({args.rounds} rounds of {args.steps} steps in free air, "
             f"{args.cut_rounds} oracle cuts of a cucumber per setting).", "",
             f"Machine: {machine['cpu_model']}, {machine['cores']} cores, {machine['platform']}; {machine['date']}.", "",
             "The limiter needs food in the scene, so a robot-only scene cannot run it; its cost on a robot-only "
             "step is its own stage time (`StepInfo.safety_wall_time_ms`) over the robot-only Step round trip.", "",
             "| | p50 (ms) | p90 (ms) | steps |", "|---|---|---|---|"]
    for name, r in results["free_air"].items():
        lines.append(f"| free air: {name} | {r['p50_ms']:.3f} | {r['p90_ms']:.3f} | {r['steps']} |")
    for name, r in results["cutting"].items():
        lines.append(f"| cutting: {name} | {r['p50_ms']:.3f} | {r['p90_ms']:.3f} | {r['steps']} |")
    stage = results["safety_stage_ms"]
    lines += ["", "| measure | value |", "|---|---|",
              f"| limiter stage, knife in free air: p50 / p90 | {1e3 * stage['free_air_p50']:.1f} / "
              f"{1e3 * stage['free_air_p90']:.1f} us |",
              f"| limiter stage, cutting: p50 / p90 | {1e3 * stage['cutting_p50']:.1f} / {1e3 * stage['cutting_p90']:.1f} us |",
              f"| **limiter stage / robot-only Step round trip** (free air; cutting) | **{100 * share_free:.2f} %**; "
              f"{100 * share_cut:.2f} % ({verdict} the {100 * TARGET_SHARE:g} % target) |",
              f"| Step round trip with food, limiter on / off: free air (median over rounds of the rounds' p50 ratio) "
              f"| {ratio_free:.3f} |",
              f"| a whole oracle cut's Step round trips, limiter on / off (median over cuts) | {ratio_cut:.3f} |", "",
              "A cut's steps are bimodal (about a millisecond while the food's MPM sleeps, hundreds while the knife "
              "is in it), so the cut compares whole cuts: "
              + "; ".join(f"{name} {', '.join(f'{t / 1e3:.1f}' for t in totals)} s" for name, totals in cut_totals.items())
              + ". The on/off ratios of round trips carry the machine's noise (p50 of each free-air round: "
              + "; ".join(f"{name} {', '.join(f'{m:.2f}' for m in ms)} ms" for name, ms in round_medians.items()
                          if not name.startswith("cut"))
              + "); the stage time is the limiter's own cost."]
    docs.publish(PAGE, "\n".join(lines) + "\n", RESULTS, {"machine": machine, "results": results}, __file__)
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())

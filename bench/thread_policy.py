#!/usr/bin/env python3
"""Two sessions cutting at once on one server, with the cores shared among the Steps running (`--step-threads
shared`, the default) against every Step taking the threads its food chose (`--step-threads model`, the behaviour
before): a runner's two workers on a 2-core machine. Each round restores both sessions to just before the knife
meets a standard-preset cucumber (22k particles, so its model asks for 2 threads) and steps both, concurrently,
a fixed number of control steps into the food; the two servers take turns round by round, and the ratio is taken
pair by pair. The machine's load during the run is recorded: on a busy machine oversubscription costs the most.
Writes docs/benchmarks/thread_policy.md and .json.

    .venv/bin/python bench/thread_policy.py [--rounds 3] [--steps 2]
"""
from __future__ import annotations

import statistics
import sys
import threading
import time
from pathlib import Path

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import LoadSampler, arguments, docs_for, machine_info, server_binary, spread, today  # noqa: E402
from culinarycut import Client  # noqa: E402
from culinarycut.launch import ServerProcess  # noqa: E402

PAGE, RESULTS = "benchmarks/thread_policy.md", "benchmarks/thread_policy.json"
POLICIES = ("shared", "model")
SCENE = {"quality": "standard", "objects": [{"food": "cucumber"}],
         "effects": {"mpm": True, "damage": True, "friction": True, "topology": True, "force_sensing": True}}
STEP_TIMEOUT_S = 900.0  # a cutting step at standard is ~800 MPM substeps of 22k particles: tens of seconds when busy
DOWN = [0.0, 0.0, -0.5, 0.0, 0.0, 0.0]  # pd_ee_delta_pose, normalised: half the step's largest move, straight down


def prepare(client: Client, quality: str, sessions: int = 2) -> list[tuple[str, bytes]]:
    """Sessions whose knife was lowered at full speed until the food woke (the first one lowered, the others
    restored to it); each with the snapshot taken there."""
    scene = {**SCENE, "quality": quality}
    first = client.create_session(scene).session_id
    client.reset(first, seed=0)
    for _ in range(400):
        if client.step(first, "pd_ee_delta_pose", [0.0, 0.0, -1.0, 0.0, 0.0, 0.0]).info.mpm_substeps > 0:
            break
    else:
        raise RuntimeError("the knife never woke the food")
    snapshot = client.save_snapshot(first)
    prepared = [(first, snapshot)]
    for _ in range(sessions - 1):
        other = client.create_session(scene).session_id
        client.reset(other, seed=0)
        client.restore_snapshot(other, snapshot)
        prepared.append((other, snapshot))
    return prepared


def cut_in_parallel(client: Client, sessions: list[tuple[str, bytes]], steps: int) -> tuple[float, int]:
    """Both sessions restored to their snapshot, then `steps` steps each at once; wall time (s) and MPM substeps."""
    for session, snapshot in sessions:
        client.restore_snapshot(session, snapshot)
    substeps = [0] * len(sessions)

    def run(i: int, session: str) -> None:
        for _ in range(steps):
            substeps[i] += client.step(session, "pd_ee_delta_pose", DOWN).info.mpm_substeps

    threads = [threading.Thread(target=run, args=(i, s)) for i, (s, _) in enumerate(sessions)]
    started = time.perf_counter()
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    return time.perf_counter() - started, sum(substeps)


def markdown(stored: dict) -> str:
    machine = stored["machine"]
    load = stored["load_average"]
    lines = ["# Threads shared among the Steps running at once", "",
             f"Measured {stored['date']} on {machine['cpu_model']} ({machine['cores']} cores) by "
             "`bench/thread_policy.py`: two sessions cutting a cucumber at the "
             f"{stored['quality']} preset ({stored['particles']:,} particles; its model asks for 2 MPM threads), "
             f"stepped at once, {stored['steps']} control steps each from just before the knife meets the food, "
             f"{stored['rounds']} rounds, the two servers taking turns round by round. The machine's 1-minute load "
             f"average during the run: {min(load):.1f}-{max(load):.1f} (other work was running).", "",
             "- **shared** (`--step-threads shared`, the default): each Step's MPM gets the cores divided by the "
             "Steps running at once: one thread each here.",
             "- **model** (`--step-threads model`, as before): each Step takes its food's 2 threads: 4 threads on "
             f"{machine['cores']} cores.", "",
             "| policy | wall per round, median (s) | fastest (s) | MPM substeps per round |", "|---|---|---|---|"]
    for policy in POLICIES:
        row = stored["policies"][policy]
        lines.append(f"| {policy} | {row['wall_s']['median']:.2f} | {row['wall_s']['min']:.2f} | "
                     f"{row['substeps']} |")
    ratios = stored["model_over_shared"]
    lines += ["", f"Model over shared, round by round: median {statistics.median(ratios):.2f}x "
              f"(range {min(ratios):.2f}-{max(ratios):.2f}x). Both do the same substeps: the results are the same "
              "bits on any team size.", ""]
    return "\n".join(lines)


def main() -> int:
    parser = arguments(__doc__, render_only=True)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--steps", type=int, default=2)
    args = parser.parse_args()
    docs = docs_for(args)
    if args.render_only:
        docs.render_stored(PAGE, RESULTS, markdown, __file__)
        return 0
    rounds, steps, quality = (1, 2, "draft") if args.quick else (args.rounds, args.steps, "standard")
    servers = {p: ServerProcess(server_binary(), max_sessions=4, idle_timeout_s=3600,
                                extra_args=["--step-threads", p]) for p in POLICIES}
    walls: dict[str, list[float]] = {p: [] for p in POLICIES}
    substeps: dict[str, int] = {}
    try:
        for server in servers.values():
            server.__enter__()
        clients = {p: Client(servers[p].address, timeout_s=STEP_TIMEOUT_S) for p in POLICIES}
        prepared = {p: prepare(clients[p], quality) for p in POLICIES}
        particles = clients[POLICIES[0]].session_stats(prepared[POLICIES[0]][0][0]).mpm_particles
        with LoadSampler(period_s=5.0) as load:
            for r in range(rounds):
                for policy in (POLICIES if r % 2 == 0 else POLICIES[::-1]):
                    wall_s, substeps[policy] = cut_in_parallel(clients[policy], prepared[policy], steps)
                    walls[policy].append(wall_s)
                    print(f"round {r + 1}: {policy} {wall_s:.2f} s", flush=True)
        samples = load.samples or [0.0]
    finally:
        for server in servers.values():
            server.__exit__(None, None, None)
    ratios = [m / s for m, s in zip(walls["model"], walls["shared"])]
    stored = {"machine": machine_info(), "date": today(), "quality": quality, "particles": particles,
              "rounds": rounds, "steps": steps, "load_average": samples, "model_over_shared": ratios,
              "policies": {p: {"wall_s": spread(walls[p]), "substeps": substeps[p]} for p in POLICIES}}
    docs.publish(PAGE, markdown(stored), RESULTS, stored, __file__)
    print(markdown(stored))
    return 0


if __name__ == "__main__":
    sys.exit(main())

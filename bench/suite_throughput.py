"""Benchmark: episodes per hour of the suite runner, where an episode's time goes (the server's stages, the
policy, the harness), the same with the three 224 px cameras the VLA adapters need, and how the wall time scales
with 1, 2 and 4 server processes on this machine.

Runs `culinarycut bench run` as a user does, against servers it starts, into fresh run folders; writes
docs/benchmarks/suite_throughput.{md,json}.

    .venv/bin/python bench/suite_throughput.py [--server-binary build/server/culinarycut-server]
"""
from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

from culinarycut.launch import ServerProcess, local_servers, server_binary

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import ROOT, arguments, docs_for, machine_info, today  # noqa: E402
from bench.lib import quick  # noqa: E402
from bench.lib.suite_runs import per_episode_parts, run_suite as run_bench, with_top_level  # noqa: E402

PAGE, RESULTS = "benchmarks/suite_throughput.md", "benchmarks/suite_throughput.json"
# (label, suite, extra arguments, cameras): the smoke suite whole, and one trial of each cucumber task of
# unseen-seeds (52 tasks: every style x state) as a sample of the big suite at draft quality, without cameras
# and with the three 224 px cameras (front, left, right) that the VLA adapters read.
SAMPLE = ["--tasks", "cucumber/*", "--trials", "1"]
WORKLOADS = [("smoke", "smoke", [], False), ("unseen-seeds (cucumber, 1 trial per task)", "unseen-seeds", SAMPLE, False),
             ("unseen-seeds (cucumber, 1 trial per task), 3 cameras of 224 px", "unseen-seeds", SAMPLE, True)]
CAMERAS = ("front", "left", "right")
IMAGE_PX = 224
# (servers, workers): one worker per server, plus one server with two workers, so that what two servers
# add beyond running two episodes at once shows.
SCALING = ((1, 1), (1, 2), (2, 2), (4, 4))
TARGET_EPISODES_PER_HOUR = 1000.0
PAPER_EPISODES = 7280  # 20 trials x 52 tasks x 7 foods


def with_cameras(suite: Path, folder: Path, image_px: int) -> Path:
    """The suite's TOML with the three cameras added at its top level (same name, another folder)."""
    cameras = ", ".join(f'{{ name = "{name}", width = {image_px}, height = {image_px} }}' for name in CAMERAS)
    return with_top_level(suite, f"cameras = [{cameras}]", folder)


def run_suite(suite: str | Path, extra: list[str], servers: list[ServerProcess], workers: int, out: Path) -> dict:
    result = run_bench(suite, [server.address for server in servers], workers, out, extra)
    episode_wall, wall_s = result["episode_s"], result["wall_s"]
    return {"suite": str(suite), "args": extra, **{k: result[k] for k in ("servers", "workers", "episodes", "successes")},
            "run_wall_s": wall_s, "episodes_per_hour": 3600.0 * result["episodes"] / wall_s,
            "episode_wall_s": episode_wall, "server_call_s": result["server_call_s"], "policy_s": result["policy_s"],
            # Inside episodes: client time outside server calls and the policy (scene, recording, rows).
            "harness_share_in_episodes": result["harness_s"] / episode_wall,
            # Around episodes: cluster start, pre-flight checks, storing, idle workers at the end.
            "run_overhead_share": 1.0 - episode_wall / (workers * wall_s),
            "per_episode_s": per_episode_parts([result]), "resolved_cfl": result["resolved_cfl"]}


def main() -> int:
    parser = arguments(__doc__)
    parser.add_argument("--server-binary", default=str(server_binary()))
    parser.add_argument("--out", type=Path, default=None, help="the folder of the page and JSON "
                                                               "(default docs/benchmarks)")
    args = parser.parse_args()
    docs = docs_for(args, args.out)
    results = []
    with tempfile.TemporaryDirectory() as scratch:
        # The smoke pass: one strawberry episode as the one-server scaling run and one with 32 px cameras (the
        # workloads run the same code).
        folder = Path(scratch)
        workloads = [("quick, with cameras", str(quick.suite(folder)), [], True)] if args.quick else WORKLOADS
        scaling = SCALING[:1] if args.quick else SCALING
        smoke = str(quick.suite(folder)) if args.quick else "smoke"
        image_px = quick.IMAGE_SIZE if args.quick else IMAGE_PX
        with local_servers(1, binary=args.server_binary, max_sessions=8, idle_timeout_s=600) as servers:
            for index, (label, suite, extra, cameras) in enumerate(workloads):
                if cameras:
                    source = Path(suite) if suite.endswith(".toml") else ROOT / "benchmarks" / f"{suite}.toml"
                    (folder / f"cameras-{index}").mkdir()
                    suite = str(with_cameras(source, folder / f"cameras-{index}", image_px))
                result = run_suite(suite, extra, servers, 2, folder / f"throughput-{index}")
                results.append({"kind": "throughput", "label": label, "cameras": len(CAMERAS) if cameras else 0,
                                "image_px": image_px if cameras else 0, **result})
                print(json.dumps(results[-1]), flush=True)
        for count, workers in scaling:
            # Servers started together share the cores (each told its part, --step-cores).
            with local_servers(count, binary=args.server_binary, max_sessions=8, idle_timeout_s=600) as servers:
                result = run_suite(smoke, [], servers, workers, folder / f"smoke-{count}-{workers}")
            results.append({"kind": "scaling", "label": f"smoke, {count} server(s), {workers} worker(s)", **result})
            print(json.dumps(results[-1]), flush=True)
    info = machine_info()
    machine = {"cpu_count": info["cores"], "platform": info["platform"], "processor": info["cpu_model"],
               "date": today()}  # the keys this page has always stored
    docs.publish(PAGE, _markdown(machine, results), RESULTS, {"machine": machine, "results": results}, __file__)
    print(f"wrote {docs.path(PAGE)}")
    return 0


def _markdown(machine: dict, results: list[dict]) -> str:
    cfls = sorted({c for r in results for c in r.get("resolved_cfl", [])})
    lines = ["# Suite runner: throughput, where an episode's time goes, scaling with servers", "",
             "Generated by `bench/suite_throughput.py`: `culinarycut bench run` with the oracle policy against "
             "local servers, every episode at the draft preset"
             + (f" (CFL {', '.join(f'{c:g}' for c in cfls)})" if cfls else "")
             + " with the foods' real material presets; no cameras unless the workload says so.", "",
             f"Machine: {machine['processor']}, {machine['cpu_count']} cores, {machine['platform']}; {machine['date']}.",
             "", "| workload | servers | workers | episodes | success | run wall s | episodes / hour | "
             "harness share in episodes | run overhead share |", "|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        lines.append(f"| {r['label']} | {r['servers']} | {r['workers']} | {r['episodes']} | {r['successes']} | "
                     f"{r['run_wall_s']:.1f} | {r['episodes_per_hour']:.0f} | "
                     f"{100 * r['harness_share_in_episodes']:.2f} % | {100 * r['run_overhead_share']:.1f} % |")
    throughput = [r for r in results if r["kind"] == "throughput" and "per_episode_s" in r]
    if throughput:
        names = list(throughput[0]["per_episode_s"])
        lines += ["", "Where an episode's time goes (seconds per episode, the worker's wall time; the stages are the "
                  "server's own timers; 2 episodes at once):", "",
                  "| part | " + " | ".join(r["label"] for r in throughput) + " |", "|---|" + "---|" * len(throughput)]
        for name in names:
            lines.append(f"| {name} | " + " | ".join(f"{r['per_episode_s'][name]:.2f}" for r in throughput) + " |")
        lines.append("| **episode** | " + " | ".join(f"**{r['episode_wall_s'] / r['episodes']:.2f}**"
                                                    for r in throughput) + " |")
    target = next((r for r in throughput if r.get("cameras") == len(CAMERAS) and r.get("image_px") == IMAGE_PX), None)
    if target:
        rate = target["episodes_per_hour"]
        lines += ["", f"**The target** ({TARGET_EPISODES_PER_HOUR:,.0f} episodes/h for the paper-size evaluation with "
                  f"three 224 px cameras, on 2 cores): this sample runs at **{rate:.0f} episodes/h** "
                  f"({rate / TARGET_EPISODES_PER_HOUR:.2f} of it; "
                  + ("met" if rate >= TARGET_EPISODES_PER_HOUR else "not met")
                  + f"). At this rate the paper's {PAPER_EPISODES:,} episodes would take "
                  f"{PAPER_EPISODES / rate:.0f} h; the sample is cucumbers only, and the suite's melons (5-12 min an "
                  "episode) and strawberries (a refined grid) cost more, so the whole suite takes longer."]
    scaling = [r for r in results if r["kind"] == "scaling"]
    base = scaling[0]["run_wall_s"]
    lines += ["", "Scaling (smoke suite; wall time of 1 server with 1 worker / wall time of each, measured in one run "
              "of this script): " +
              ", ".join(f"{r['servers']} server(s) x {r['workers']} worker(s) {base / r['run_wall_s']:.2f}x"
                        for r in scaling) + ". "
              f"The episodes are MPM-bound on the servers, so the speed-up stops at the machine's "
              f"{machine['cpu_count']} cores; the harness itself stays well under 5 % of episode time. Servers "
              "started together share the cores (`--step-cores` = cores / servers, at least 1), as "
              "`culinarycut data generate --local-servers` starts them.", "",
              "*Harness share in episodes*: the client's time in an episode outside server calls and the policy "
              "(making the scene, reading observations, recording the trace). *Run overhead share*: the part of "
              "workers x run wall time not spent in episodes (cluster start, pre-flight checks, storing rows, "
              "workers idle while the last episodes finish)."]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.exit(main())

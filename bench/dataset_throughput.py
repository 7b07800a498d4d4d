"""Benchmark: dataset episodes per hour on this machine (`culinarycut data generate` as a user runs it,
three 224x224 RGB cameras, MPM and force on, the success filter), the export's cost per episode, and the
machine-hours the paper's 325,000 trajectories would take here.

The workload is every style on cucumber at three states (ratio 0.3, middle, split into 3); the projection
weights the states as the paper's tasks do (9 ratios, 1 middle, 3 splits of 13). Writes
docs/benchmarks/dataset_throughput.{md,json}.

    .venv/bin/python bench/dataset_throughput.py [--quality draft] [--servers 2] [--workers 2]
    .venv/bin/python bench/dataset_throughput.py --quality standard --styles normal   # the _standard page
"""
from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

from culinarycut.datasets.store import GenerationStore
from culinarycut.launch import local_servers

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import arguments, docs_for, machine_info, today  # noqa: E402
from bench.lib import quick  # noqa: E402
PAPER_TRAJECTORIES = 325_000
STATES = {"ratio": ("ratio-0.3", 9 / 13), "middle": ("middle", 1 / 13), "split": ("split-3", 3 / 13)}


def generate(out: Path, servers: list[str], workers: int, quality: str, size: int, styles: str,
             states: list[str], food: list[str]) -> float:
    command = [sys.executable, "-m", "culinarycut", "data", "generate", "--out", str(out), "--styles", styles,
               "--states", ",".join(states), "--quality", quality, "--image-size", str(size),
               "--workers", str(workers), "--shard-size", "1", "--no-progress", *food]
    for server in servers:
        command += ["--server", server]
    started = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stdout}\n{done.stderr}")
    return time.perf_counter() - started


def main() -> int:
    parser = arguments(__doc__)
    parser.add_argument("--quality", default="draft")
    parser.add_argument("--servers", type=int, default=2)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--image-size", type=int, default=224)
    parser.add_argument("--styles", default="all", help="a sample of the styles (comma list) for slow presets")
    parser.add_argument("--out", help="output path without suffix (default docs/benchmarks/dataset_throughput, "
                                      "with _QUALITY for other presets than draft)")
    args = parser.parse_args()
    suffix = "" if args.quality == "draft" else f"_{args.quality}"
    docs = docs_for(args, Path(args.out).parent if args.out else None)
    name = Path(args.out).name if args.out else f"dataset_throughput{suffix}"
    # The smoke pass: one strawberry middle cut, 32 px cameras, one server and worker.
    states, food = ((["middle"], ["--food", quick.FOOD]) if args.quick else
                    ([state for state, _ in STATES.values()], []))
    if args.quick:
        args.servers, args.workers, args.image_size, args.styles = 1, 1, quick.IMAGE_SIZE, "normal"
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        with local_servers(args.servers, max_sessions=4) as servers:  # sharing the machine's cores
            wall_s = generate(folder / "data", [s.address for s in servers], args.workers, args.quality,
                              args.image_size, args.styles, states, food)
        with GenerationStore(folder / "data") as store:
            rows = store.rows()
        started = time.perf_counter()
        subprocess.run([sys.executable, "-m", "culinarycut", "data", "export", str(folder / "data"), "--out",
                        str(folder / "export")], check=True, capture_output=True)
        export_s = time.perf_counter() - started
        size_bytes = sum(p.stat().st_size for p in (folder / "data" / "episodes").glob("*.h5"))
    kept = [r for r in rows if r["kept"]]
    parallelism = sum(r["wall_s"] for r in rows) / wall_s  # episodes running at once, on average
    by_state = {}
    for kind, (state, weight) in STATES.items():
        chosen = [r for r in rows if f"-{state}-" in r["key"]]
        by_state[kind] = {"state": state, "weight": weight, "episodes": len(chosen),
                          "kept": sum(r["kept"] for r in chosen),
                          "mean_episode_wall_s": sum(r["wall_s"] for r in chosen) / max(1, len(chosen)),
                          "mean_steps": sum(r["steps"] for r in chosen) / max(1, len(chosen))}
    # machine seconds per generated trajectory at the paper's state mix, run as here (parallelism included)
    weighted_s = sum(v["weight"] * v["mean_episode_wall_s"] for v in by_state.values()) / parallelism
    keep_rate = len(kept) / len(rows)
    export_per_episode_s = export_s / max(1, len(kept))
    per_kept_s = weighted_s / max(keep_rate, 1e-9) + export_per_episode_s
    result = {"date": today(), "machine": machine_info(), "quality": args.quality,
              "cameras": "front, left, right RGB", "image_size": args.image_size, "servers": args.servers,
              "workers": args.workers, "servers_used": len({r["server"] for r in rows}), "styles": args.styles, "episodes": len(rows), "kept": len(kept), "keep_rate": keep_rate,
              "run_wall_s": wall_s, "episodes_per_hour": 3600.0 * len(rows) / wall_s,
              "kept_per_hour": 3600.0 * len(kept) / wall_s, "parallelism": parallelism, "by_state": by_state,
              "export_s": export_s, "export_per_episode_s": export_per_episode_s,
              "episode_file_mb": size_bytes / max(1, len(kept)) / 1e6,
              "paper_trajectories": PAPER_TRAJECTORIES,
              "projected_machine_hours": PAPER_TRAJECTORIES * per_kept_s / 3600.0,
              "rejected": [{"key": r["key"], "reason": r["reason"]} for r in rows if not r["kept"]]}
    docs.publish(f"benchmarks/{name}.md", markdown(result), f"benchmarks/{name}.json", result, __file__, indent=2)
    print(markdown(result))
    return 0


def markdown(r: dict) -> str:
    m = r["machine"]
    lines = [f"# Dataset generation throughput ({r['quality']})", "",
             f"Measured {r['date']} by `bench/dataset_throughput.py` on {m['cpu_model']} ({m['cores']} cores), "
             f"Python {m['python']}: `culinarycut data generate` with {r['servers']} servers ({r['servers_used']} used) and "
             f"{r['workers']} Dask workers, three {r['image_size']}x{r['image_size']} RGB cameras, MPM, damage, "
             f"topology and force sensing on, styles `{r['styles']}` on cucumber at ratio 0.3, middle and split into 3.", "",
             "| | |", "|---|---|",
             f"| episodes (kept) | {r['episodes']} ({r['kept']}, {100 * r['keep_rate']:.0f} %) |",
             f"| run wall time | {r['run_wall_s']:.0f} s |",
             f"| episodes per hour | {r['episodes_per_hour']:.0f} (kept {r['kept_per_hour']:.0f}) |",
             f"| episodes at once (mean) | {r['parallelism']:.2f} |",
             f"| export (robomimic, LeRobot, RDT, statistics) | {r['export_per_episode_s']:.2f} s per episode |",
             f"| episode file | {r['episode_file_mb']:.1f} MB |", "",
             "| state | weight in the paper | episodes | kept | mean steps | mean episode wall (s) |",
             "|---|---|---|---|---|---|"]
    for kind, v in r["by_state"].items():
        lines.append(f"| {v['state']} | {v['weight']:.2f} | {v['episodes']} | {v['kept']} | {v['mean_steps']:.0f} | "
                     f"{v['mean_episode_wall_s']:.1f} |")
    lines += ["", f"Projected for the paper's {r['paper_trajectories']:,} kept trajectories on this machine, at the "
              "paper's state mix, this keep rate, with export: "
              f"**{r['projected_machine_hours']:,.0f} machine-hours** ({r['projected_machine_hours'] / 24:,.0f} days).",
              ""]
    if r["rejected"]:
        lines += ["Rejected episodes (the success filter):", ""]
        lines += [f"- `{x['key']}`: {x['reason']}" for x in r["rejected"]]
        lines.append("")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())

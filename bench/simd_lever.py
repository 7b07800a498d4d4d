#!/usr/bin/env python3
"""Benchmark: what running the MPM kernels at the CPU's best x86-64 level (the loader's pick, e.g. x86-64-v3: AVX2
and FMA) is worth against the baseline build (x86-64: SSE2), side by side in one run:
- the kernel: bench_mpm_throughput's cutting substep on one thread at 10k and 100k particles, `--simd` alternating
  pair by pair;
- whole episodes: the smoke suite with the oracle through `culinarycut bench run`, 2 workers, against a server
  started at each level (`culinarycut-server --simd`), in alternating rounds, with each episode's time by stage.
Writes docs/benchmarks/simd_lever.{md,json}.

    .venv/bin/python bench/simd_lever.py [--pairs 6] [--rounds 2]
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np
from culinarycut.launch import ServerProcess, server_binary

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import (ROOT, arguments, bench_binary, dated_machine_info, docs_for, google_benchmark,  # noqa: E402
                           interleaved, missing)
from bench.harness.machine import kernel_instruction_set  # noqa: E402
from bench.lib import quick  # noqa: E402
from bench.lib.suite_runs import rounds_totals, run_suite  # noqa: E402

PAGE, RESULTS = "benchmarks/simd_lever.md", "benchmarks/simd_lever.json"
BASELINE = "x86-64"
SUITE = ROOT / "benchmarks" / "smoke.toml"
WORKERS = 2
PARTICLES = (10_000, 100_000)


def substep_ms(binary: Path, level: str, particles: int, min_time_s: float) -> float:
    """One thread's milliseconds per cutting substep at `level` (bench_mpm_throughput --simd)."""
    data = google_benchmark(binary, f"--simd={level}", f"--benchmark_min_time={min_time_s}",
                            f"--benchmark_filter=BM_CuttingSubstep/particles:{particles}/threads:1/")
    if data["context"].get("simd") != level:
        raise RuntimeError(f"bench_mpm_throughput --simd={level} ran {data['context'].get('simd')}")
    return data["benchmarks"][0]["real_time"]  # ms: the benchmark reports in milliseconds


def kernel_pairs(binary: Path, levels: list[str], pairs: int, min_time_s: float) -> dict:
    """For each particle count, `pairs` alternating runs of each level and the ratio pair by pair."""
    out = {}
    for particles in PARTICLES:
        by_level = interleaved({level: (lambda l=level: substep_ms(binary, l, particles, min_time_s))
                                for level in levels}, pairs,
                               announce=lambda i, l: print(f"kernel {particles} particles, pair {i + 1}: {l}",
                                                           flush=True))
        ratios = [b / p for b, p in zip(by_level[levels[0]], by_level[levels[1]])]
        out[str(particles)] = {"ms_per_substep": by_level, "speedup_per_pair": ratios,
                               "speedup_median": float(np.median(ratios)),
                               "particle_steps_per_s": {l: particles / (float(np.median(v)) / 1e3)
                                                        for l, v in by_level.items()}}
    return out


def main() -> int:
    parser = arguments(__doc__)
    parser.add_argument("--pairs", type=int, default=6, help="alternating kernel runs per level")
    parser.add_argument("--rounds", type=int, default=2, help="runs of the suite per level, alternating")
    parser.add_argument("--binary", type=Path, default=bench_binary("bench_mpm_throughput"))
    args = parser.parse_args()
    docs = docs_for(args)
    if code := missing(args.binary, "--binary"):
        return code
    best = kernel_instruction_set()
    if best in (BASELINE, "unknown") or not best.startswith("x86-64"):
        print(f"the loader picks {best} on this machine: there is no second level to compare; nothing written")
        return 0
    levels = [BASELINE, best]
    pairs, rounds = (1, 1) if args.quick else (args.pairs, args.rounds)
    kernel = kernel_pairs(args.binary, levels, pairs, 0.2 if args.quick else 1.0)
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        suite = quick.suite(folder) if args.quick else SUITE
        counter = iter(range(10_000))
        with ServerProcess(server_binary(), max_sessions=8, idle_timeout_s=600, extra_args=["--simd", BASELINE]) as base, \
                ServerProcess(server_binary(), max_sessions=8, idle_timeout_s=600, extra_args=["--simd", best]) as wide:
            servers = {BASELINE: base, best: wide}
            by_round = interleaved({level: (lambda s=server: run_suite(suite, [s.address], WORKERS,
                                                                       folder / f"run-{next(counter)}"))
                                    for level, server in servers.items()}, rounds,
                                   announce=lambda i, level: print(f"suite round {i + 1}/{rounds}: {level}", flush=True))
    episodes = {level: rounds_totals(runs) for level, runs in by_round.items()}
    data = {"machine": dated_machine_info(), "levels": levels, "kernel": kernel, "pairs": pairs,
            "suite": str(SUITE.relative_to(ROOT)), "workers": WORKERS, "rounds": rounds, "episodes": episodes,
            "episodes_per_hour_ratio": episodes[best]["episodes_per_hour"] / episodes[BASELINE]["episodes_per_hour"]}
    text = _markdown(data)
    docs.publish(PAGE, text, RESULTS, data, __file__)
    print(text)
    return 0


def _markdown(data: dict) -> str:
    machine, (base, best) = data["machine"], data["levels"]
    lines = ["# The MPM kernels' instruction set: the baseline against the CPU's best level", "",
             f"Generated by `bench/simd_lever.py`. The MPM library is built once per x86-64 level and the loader runs "
             f"the best one the CPU has (here {best}); `--simd {base}` runs the baseline (SSE2) instead "
             "(docs/mpm.md, \"Instruction sets\"). Both are measured side by side in this run.", "",
             f"Machine: {machine['cpu_model']}, {machine['cores']} cores, {machine['platform']}; {machine['date']}.", "",
             f"**The kernel**: `bench_mpm_throughput`'s cutting substep, one thread, {data['pairs']} alternating "
             "pairs per size (median ms per substep; speed-up = baseline time over the level's, pair by pair):", "",
             f"| particles | {base} ms | {best} ms | {best} particle-steps/s | speed-up (median of pairs) | pairs |",
             "|---|---|---|---|---|---|"]
    for particles, k in data["kernel"].items():
        ms = {level: float(np.median(v)) for level, v in k["ms_per_substep"].items()}
        lines.append(f"| {int(particles):,} | {ms[base]:.2f} | {ms[best]:.2f} | "
                     f"{k['particle_steps_per_s'][best] / 1e6:.2f} M | **{k['speedup_median']:.2f}x** | "
                     + ", ".join(f"{r:.2f}" for r in k["speedup_per_pair"]) + " |")
    episodes = data["episodes"]
    lines += ["", f"**Whole episodes**: `culinarycut bench run` on `{data['suite']}` with the oracle, {data['workers']} "
              f"workers against a server at each level, {data['rounds']} alternating rounds, no cameras:", "",
              "| level | episodes | successes | wall s | episodes / hour | s per episode |", "|---|---|---|---|---|---|"]
    for level, r in episodes.items():
        lines.append(f"| {level} | {r['episodes']} | {r['successes']} | {r['wall_s']:.0f} | "
                     f"{r['episodes_per_hour']:.0f} | {r['episode_s']:.1f} |")
    lines += ["", f"Episodes per hour, {best} over {base}: **{data['episodes_per_hour_ratio']:.2f}x**.", "",
              "Where an episode's time goes (seconds per episode; the stages are the server's own timers):", "",
              f"| part | {base} | {best} |", "|---|---|---|"]
    for part in episodes[base]["per_episode_s"]:
        lines.append(f"| {part} | " + " | ".join(f"{episodes[l]['per_episode_s'][part]:.2f}" for l in (base, best))
                     + " |")
    lines += ["", "Each level gives the same bits for the same seed and thread count; the two levels do not give the "
              "same bits as each other (fused multiply-adds and wider vectors round differently), so the benchmark "
              "runner refuses to mix them in one run."]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.exit(main())

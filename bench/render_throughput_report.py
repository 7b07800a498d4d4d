#!/usr/bin/env python3
"""Runs bench_render_throughput and writes docs/benchmarks/render_throughput.md and .json:
three-camera sets per second (front, left, right) with the robot, the board, the scene and a
100k-particle cucumber, food surface extraction included, at 224 x 224 and 640 x 480, and the
split of one set into surface extraction, drawing and read-back.

Usage: .venv/bin/python bench/render_throughput_report.py [--binary build/bench/bench_render_throughput]
"""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import arguments, bench_binary, cpu_model, docs_for, google_benchmark, missing  # noqa: E402

PAGE, RESULTS = "benchmarks/render_throughput.md", "benchmarks/render_throughput.json"
QUICK_FILTER = "side:224/cut:0/kitchen:0/all_channels:0"  # the smoke pass: the target's configuration, once
TARGET_SETS_PER_S = 30.0  # the renderer's throughput target: 224 x 224, three cameras, llvmpipe, 2 cores
REPETITIONS = 3           # shared machines drift: report medians


def run(binary: Path, quick: bool = False) -> dict:
    print(f"running {binary} (about a minute)...", flush=True)
    # Surface extraction uses OpenMP; idle OpenMP workers spinning after each parallel region take
    # the cores llvmpipe rasterises on. Passive waiting is what a rendering server should run with.
    env = dict(os.environ, OMP_WAIT_POLICY=os.environ.get("OMP_WAIT_POLICY", "passive"))
    return google_benchmark(binary, f"--benchmark_repetitions={1 if quick else REPETITIONS}",
                            "--benchmark_report_aggregates_only=true",
                            *([f"--benchmark_filter={QUICK_FILTER}"] if quick else []), env=env)


def describe(name: str) -> tuple[str, str, str, str]:
    fields = dict(part.split(":", 1) for part in name.split("/")[1:] if ":" in part)
    size = "224 x 224" if fields.get("side") == "224" else "640 x 480"
    food = "cut (2 pieces)" if fields.get("cut") == "1" else "whole"
    scene = "kitchen" if fields.get("kitchen") == "1" else "table"
    channels = "RGB + depth + seg" if fields.get("all_channels") == "1" else "RGB"
    return size, scene, food, channels


def main() -> int:
    parser = arguments(__doc__, whole_doc=True)
    parser.add_argument("--binary", type=Path, default=bench_binary("bench_render_throughput"))
    parser.add_argument("--out", type=Path, default=None,
                        help="the page (default docs/benchmarks/render_throughput.md); its JSON goes beside it")
    args = parser.parse_args()
    docs = docs_for(args)
    if code := missing(args.binary, "--binary"):
        return code
    load_before = os.getloadavg()[0]
    data = run(args.binary, args.quick)
    load_after = os.getloadavg()[0]
    # The medians of the repetitions (a single repetition reports only its run).
    rows = [b for b in data["benchmarks"] if b.get("aggregate_name", "") == ("" if args.quick else "median")]
    context = data.get("context", {})
    gl_renderer = context.get("gl_renderer", "unknown")

    lines = [
        "# Renderer throughput",
        "",
        "Three-camera sets per second: front, left and right cameras rendered and read back, with the",
        "Panda and knife, the board, the scene furniture and a 100k-particle cucumber (sampled by",
        "`sim/mpm/food_shapes.h`), its surface extracted from the particles on every set. Written by",
        "`bench/render_throughput_report.py` from `bench/render_throughput.cc`; medians of",
        f"{1 if args.quick else REPETITIONS} repetitions.",
        "",
        "## Machine",
        "",
        f"- CPU: {cpu_model()}, {os.cpu_count()} cores visible",
        f"- OpenGL: {gl_renderer}",
        f"- OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY', 'passive')} (see docs/rendering.md, Performance)",
        f"- Load average (1 min) before / after the run: {load_before:.2f} / {load_after:.2f}"
        " (a load above the core count means other work shared the CPU and the numbers are low)",
        "",
        "## Results",
        "",
        "| image | scene | food | channels | sets/s | ms/set | surface ms | render ms | read-back ms | target 30 sets/s |",
        "|---|---|---|---|---:|---:|---:|---:|---:|---|",
    ]
    for bench in rows:
        size, scene, food, channels = describe(bench["run_name"])
        sets = bench["sets_per_s"]
        verdict = ""
        if size == "224 x 224" and channels == "RGB":
            verdict = "met" if sets >= TARGET_SETS_PER_S else f"missed ({sets / TARGET_SETS_PER_S:.0%})"
        lines.append(f"| {size} | {scene} | {food} | {channels} | {sets:.1f} | {1000.0 / sets:.1f} | "
                     f"{bench['surface_ms']:.1f} | {bench['render_ms']:.1f} | {bench['readback_ms']:.2f} | {verdict} |")
    lines += [
        "",
        "- *surface*: density grid and marching cubes of every food piece (`ExtractFoodSurfaces`, on the",
        "  calling thread); *render*: food upload, shadow pass and the three camera passes until",
        "  `glFinish`; *read-back*: `glReadPixels` of the requested channels and the row flips.",
        "- The target applies to 224 x 224 RGB on llvmpipe with 2 cores; 640 x 480 and the extra",
        "  channels are reported for reference. Re-run: build `bench_render_throughput`, then",
        "  `.venv/bin/python -m bench run render_throughput --build <build>`.",
        "",
    ]
    if args.out:  # a page elsewhere, its JSON beside it
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.with_suffix(".json").write_text(json.dumps(data, indent=1))
        args.out.write_text("\n".join(lines))
    else:
        docs.publish(PAGE, "\n".join(lines), RESULTS, data, __file__)
    print(f"wrote {args.out or docs.path(PAGE)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

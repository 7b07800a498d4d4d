#!/usr/bin/env python3
"""Runs bench_render_throughput and writes docs/benchmarks/render_throughput.md and .json:
three-camera sets per second (front, left, right) with the robot, the board, the scene and a
100k-particle cucumber, food surface extraction included, at 224 x 224 and 640 x 480, and the
split of one set into surface extraction, drawing and read-back.

Usage: .venv/bin/python bench/render_throughput_report.py [--binary build/bench/bench_render_throughput]
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TARGET_SETS_PER_S = 30.0  # the renderer's throughput target: 224 x 224, three cameras, llvmpipe, 2 cores
REPETITIONS = 3           # shared machines drift: report medians


def cpu_model() -> str:
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor() or "unknown"


def run(binary: Path) -> dict:
    print(f"running {binary} (about a minute)...", flush=True)
    # Surface extraction uses OpenMP; idle OpenMP workers spinning after each parallel region take
    # the cores llvmpipe rasterises on. Passive waiting is what a rendering server should run with.
    env = dict(os.environ, OMP_WAIT_POLICY=os.environ.get("OMP_WAIT_POLICY", "passive"))
    out = subprocess.run([str(binary), "--benchmark_format=json", f"--benchmark_repetitions={REPETITIONS}",
                          "--benchmark_report_aggregates_only=true"],
                         check=True, capture_output=True, text=True, env=env)
    return json.loads(out.stdout)


def describe(name: str) -> tuple[str, str, str, str]:
    fields = dict(part.split(":", 1) for part in name.split("/")[1:] if ":" in part)
    size = "224 x 224" if fields.get("side") == "224" else "640 x 480"
    food = "cut (2 pieces)" if fields.get("cut") == "1" else "whole"
    scene = "kitchen" if fields.get("kitchen") == "1" else "table"
    channels = "RGB + depth + seg" if fields.get("all_channels") == "1" else "RGB"
    return size, scene, food, channels


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", type=Path, default=ROOT / "build" / "bench" / "bench_render_throughput")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "benchmarks" / "render_throughput.md")
    args = parser.parse_args()
    if not args.binary.is_file():
        print(f"error: {args.binary} not found; build first (target bench_render_throughput)", file=sys.stderr)
        return 2
    load_before = os.getloadavg()[0]
    data = run(args.binary)
    load_after = os.getloadavg()[0]
    rows = [b for b in data["benchmarks"] if b.get("aggregate_name") == "median"]
    context = data.get("context", {})
    gl_renderer = context.get("gl_renderer", "unknown")

    lines = [
        "# Renderer throughput",
        "",
        "Three-camera sets per second: front, left and right cameras rendered and read back, with the",
        "Panda and knife, the board, the scene furniture and a 100k-particle cucumber (sampled by",
        "`sim/mpm/food_shapes.h`), its surface extracted from the particles on every set. Written by",
        "`bench/render_throughput_report.py` from `bench/render_throughput.cc`; medians of",
        f"{REPETITIONS} repetitions.",
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
        "  `.venv/bin/python bench/render_throughput_report.py --binary <build>/bench/bench_render_throughput`.",
        "",
    ]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines))
    args.out.with_suffix(".json").write_text(json.dumps(data, indent=1))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

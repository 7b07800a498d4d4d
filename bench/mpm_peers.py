#!/usr/bin/env python3
"""Benchmark: MPM per core against its peers, Taichi's and NVIDIA Warp's CPU backends, at equal work: the same
falling elastic block (bench/mpm_falling_block.cc: same particles, dx, particles per cell, CFL step, material,
steps, float32) in ours and in MLS-MPM kernels written for each peer (bench/peers/), interleaved round by round.
The peers are installed from PyPI (requirements/bench-peers.txt) into a throwaway virtualenv made for the run and
deleted after it. Writes docs/benchmarks/mpm_peers.{md,json}: particle-steps per second per engine, particles and
threads (median of the rounds), ours over each peer, and the centre of mass's drop, which must agree across all
three for the comparison to stand.

    .venv/bin/python bench/mpm_peers.py [--rounds 3] [--particles 10000 100000]
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import ROOT, arguments, bench_binary, build_id, dated_machine_info, docs_for  # noqa: E402
from bench.harness import google_benchmark, interleaved, missing, spread  # noqa: E402

PAGE, RESULTS = "benchmarks/mpm_peers.md", "benchmarks/mpm_peers.json"
REQUIREMENTS = ROOT / "requirements" / "bench-peers.txt"
SYSTEM_PYTHON = "/usr/bin/python3"  # the virtualenv's base: Debian's CPython 3.11, as .venv/'s
PEERS = {"taichi": ROOT / "bench" / "peers" / "taichi_falling_block.py",
         "warp": ROOT / "bench" / "peers" / "warp_falling_block.py"}
NAMES = {"ours": "CulinaryCut", "taichi": "Taichi", "warp": "Warp"}
PARTICLES = (10_000, 100_000)  # BM_FallingBlock's sizes (each rounded to a cube: 10,648 and 97,336)
THREADS = (1, 2)
# The drops may differ by float32 rounding only (three summation orders: nanometres); a step more or fewer, another
# dt, E or g moves the block by about one step's travel at the drop speed (v dt, micrometres). The tolerance sits
# between the two, at this fraction of v dt.
COM_TOLERANCE_OF_A_STEP = 0.02


def install_peers(folder: Path) -> Path:
    """A virtualenv in `folder` with the pinned peers; its python. Exits with a clear error when pip cannot install
    them (no network to PyPI, most often)."""
    venv = folder / "venv"
    subprocess.run([SYSTEM_PYTHON, "-m", "venv", str(venv)], check=True)
    python = venv / "bin" / "python"
    print(f"installing {REQUIREMENTS.relative_to(ROOT)} into a throwaway virtualenv ({venv})...", flush=True)
    done = subprocess.run([str(python), "-m", "pip", "install", "--disable-pip-version-check", "--only-binary=:all:",
                           "--retries", "2", "--timeout", "60", "-r", str(REQUIREMENTS)],
                          capture_output=True, text=True)
    if done.returncode != 0:
        tail = "\n".join((done.stdout + done.stderr).strip().splitlines()[-8:])
        raise SystemExit(f"error: pip could not install the peers (Taichi, Warp) from PyPI; this benchmark needs "
                         f"network access to PyPI (or a mirror pip is configured for). pip said:\n{tail}")
    return python


def ours(binary: Path, particles: int, threads: int) -> dict:
    """One run of BM_FallingBlock: its counters (the rate, the settings, the drop) and the kernels' level."""
    data = google_benchmark(binary, f"--benchmark_filter=BM_FallingBlock/particles:{particles}/threads:{threads}/")
    if len(data["benchmarks"]) != 1:
        raise RuntimeError(f"{binary.name} has no BM_FallingBlock at {particles} particles, {threads} threads")
    return {**data["benchmarks"][0], "simd": data["context"].get("simd")}


def peer(python: Path, engine: str, settings: dict, threads: int, cache: Path) -> dict:
    """One run of a peer's script on ours' settings; its JSON line."""
    command = [str(python), str(PEERS[engine]), "--particles", str(int(settings["particles"])),
               "--threads", str(threads), "--dx", repr(settings["dx_m"]), "--dt", repr(settings["dt_s"]),
               "--youngs", repr(settings["youngs_modulus_pa"]), "--poisson", repr(settings["poisson_ratio"]),
               "--density", repr(settings["density_kg_m3"]), "--gravity", repr(settings["gravity_m_s2"]),
               "--gap", repr(settings["gap_m"]), "--drop-speed", repr(settings["drop_speed_m_s"]),
               "--steps", str(int(settings["steps"])), "--warmup", str(int(settings["warmup_steps"])),
               "--cache", str(cache)]
    # The virtualenv's packages only: nothing from the checkout's PYTHONPATH.
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    done = subprocess.run(command, capture_output=True, text=True, env=env)
    if done.returncode != 0:
        raise RuntimeError(f"{PEERS[engine].name} failed:\n" + "\n".join(done.stderr.strip().splitlines()[-15:]))
    result = json.loads([line for line in done.stdout.splitlines() if line.startswith("{")][-1])
    if not result["inside_grid"]:
        raise RuntimeError(f"{PEERS[engine].name}: the block left its dense grid; the run is no measurement")
    return result


def run_name(engine: str, particles: int, threads: int) -> str:
    return f"{engine} {particles} {threads}"


def main() -> int:
    parser = arguments(__doc__)
    parser.add_argument("--rounds", type=int, default=3, help="runs of every engine and size, interleaved")
    parser.add_argument("--particles", type=int, nargs="+", choices=PARTICLES, default=list(PARTICLES),
                        help="BM_FallingBlock's sizes to run")
    parser.add_argument("--binary", type=Path, default=bench_binary("bench_mpm_falling_block"))
    args = parser.parse_args()
    docs = docs_for(args)
    if code := missing(args.binary, "--binary"):
        return code
    # The smoke pass: the smallest size, one thread, one round; the peers are still installed.
    sizes, threads, rounds = ((PARTICLES[0],), (1,), 1) if args.quick else (tuple(args.particles), THREADS,
                                                                             args.rounds)
    with tempfile.TemporaryDirectory(prefix="culinarycut-peers-") as scratch:
        python = install_peers(Path(scratch))
        cache = Path(scratch) / "kernels"  # the peers' compiled kernels, deleted with the virtualenv
        # One run of ours per size first: it gives the settings the peers take over (and warms ours up).
        settings = {n: ours(args.binary, n, 1) for n in sizes}
        runs = {}
        for n in sizes:
            for t in threads:
                runs[run_name("ours", n, t)] = lambda n=n, t=t: ours(args.binary, n, t)
                for engine in PEERS:
                    runs[run_name(engine, n, t)] = lambda e=engine, n=n, t=t: peer(python, e, settings[n], t, cache)
        by_run = interleaved(runs, rounds, announce=lambda i, name: print(f"round {i + 1}/{rounds}: {name}",
                                                                           flush=True))
    data = _summary(by_run, settings, sizes, threads, rounds)
    text = _markdown(data)
    docs.publish(PAGE, text, RESULTS, data, __file__)
    print(text)
    if not data["com_agree"]:
        print("error: the engines' centre-of-mass drops disagree: they did not simulate the same thing",
              file=sys.stderr)
        return 1
    return 0


def _summary(by_run: dict, settings: dict, sizes: tuple, threads: tuple, rounds: int) -> dict:
    """Every run kept; per engine, size and thread count the median rate, ours over each peer; the drop check."""
    keep = ("particle_steps_per_s", "seconds", "cores_busy", "com_drop_m", "real_time")
    rows, com_check, versions = [], {}, {}
    for n in sizes:
        drops = {}
        for t in threads:
            row = {}
            for engine in ("ours", *PEERS):
                results = by_run[run_name(engine, n, t)]
                versions[engine] = results[0].get("version") or f"checkout {build_id()}, kernels {results[0]['simd']}"
                drops.setdefault(engine, []).extend(r["com_drop_m"] for r in results)
                cores = [r["cores_busy"] for r in results if "cores_busy" in r]
                row[engine] = {"engine": engine, "particles": int(settings[n]["particles"]), "threads": t,
                               "particle_steps_per_s": spread(r["particle_steps_per_s"] for r in results),
                               "cores_busy_median": float(np.median(cores)) if cores else None,
                               "runs": [{k: r[k] for k in keep if k in r} for r in results]}
            for engine in PEERS:
                row["ours"]["over_" + engine] = (row["ours"]["particle_steps_per_s"]["median"]
                                                 / row[engine]["particle_steps_per_s"]["median"])
            rows += row.values()
        every = [d for values in drops.values() for d in values]
        s = settings[n]
        tolerance = COM_TOLERANCE_OF_A_STEP * s["drop_speed_m_s"] * s["dt_s"]
        com_check[str(int(s["particles"]))] = {
            "drops_m": drops, "spread_m": max(every) - min(every), "tolerance_m": tolerance,
            "agree": max(every) - min(every) <= tolerance}
    first = settings[sizes[0]]
    shared = {k: first[k] for k in ("dx_m", "dt_s", "cfl", "particles_per_cell", "youngs_modulus_pa", "poisson_ratio",
                                    "density_kg_m3", "gravity_m_s2", "gap_m", "drop_speed_m_s", "warmup_steps",
                                    "steps")}
    return {"machine": dated_machine_info(), "rounds": rounds, "threads": list(threads),
            "particles": [int(settings[n]["particles"]) for n in sizes], "settings": shared, "versions": versions,
            "requirements": [line for line in REQUIREMENTS.read_text().splitlines()
                             if line and not line.startswith("#")],
            "rows": rows, "com_check": com_check, "com_agree": all(c["agree"] for c in com_check.values())}


def _markdown(data: dict) -> str:
    machine, s, v = data["machine"], data["settings"], data["versions"]
    lines = ["# MPM per core against Taichi and Warp (CPU backends), at equal work", "",
             "Generated by `bench/mpm_peers.py`. The same scene in three engines: an elastic block (cucumber's E, nu "
             "and rho; fixed-corotated, no plasticity, no damage) landing on a frictionless floor, no knife, no "
             "board, float32 throughout. Ours is the solver's own substep (`bench/mpm_falling_block.cc`); the peers "
             "run MLS-MPM kernels written for them in `bench/peers/` (after Hu et al. 2018, MLS-MPM, and Taichi's "
             "mpm99 example: quadratic B-splines, APIC/MLS affine momentum, polar decomposition) on a dense grid "
             "over the block's fall. Same particles, dx, particles per cell, CFL step and number of steps; each "
             "engine's warm-up steps (the peers' kernels compile on the first) are not timed. The engines ran "
             f"interleaved, {data['rounds']} round(s); each cell is the median.", "",
             f"Machine: {machine['cpu_model']}, {machine['cores']} cores, {machine['platform']}; {machine['date']}.",
             f"Versions: ours {v.get('ours')}; Taichi {v.get('taichi')} (`ti.init(arch=ti.cpu, "
             f"cpu_max_num_threads=N)`), Warp {v.get('warp')} (device \"cpu\"; it has no thread setting), both from "
             "`requirements/bench-peers.txt` in a throwaway virtualenv.", "",
             "Particle-steps per second (M; ours over each peer at the same particles and threads):", "",
             "| particles | threads | ours | Taichi | Warp | ours / Taichi | ours / Warp |",
             "|---|---|---|---|---|---|---|"]
    by = {(r["engine"], r["particles"], r["threads"]): r for r in data["rows"]}
    for n in data["particles"]:
        for t in data["threads"]:
            rate = {e: by[(e, n, t)]["particle_steps_per_s"]["median"] / 1e6 for e in NAMES}
            mine = by[("ours", n, t)]
            lines.append(f"| {n:,} | {t} | {rate['ours']:.2f} | {rate['taichi']:.2f} | {rate['warp']:.2f} | "
                         f"**{mine['over_taichi']:.1f}x** | **{mine['over_warp']:.1f}x** |")
    lines += ["", "Cores the peers kept busy in their timed steps (process CPU time over wall time, median):", "",
              "| particles | threads | Taichi | Warp |", "|---|---|---|---|"]
    for n in data["particles"]:
        for t in data["threads"]:
            lines.append(f"| {n:,} | {t} | {by[('taichi', n, t)]['cores_busy_median']:.2f} | "
                         f"{by[('warp', n, t)]['cores_busy_median']:.2f} |")
    lines += ["", _warp_threads(data, by), "",
              "**Did the three simulate the same thing?** The block's centre of mass fell (or, once it bounced, rose: "
              "negative) by the same distance over the warm-up and timed steps in every run of every engine, within "
              f"{COM_TOLERANCE_OF_A_STEP:g} of one step's travel at the drop speed (float32 rounding in three "
              "summation orders differs by nanometres; a step more or fewer, another dt, E or g by about a step's "
              "travel):", "",
              "| particles | ours um | Taichi um | Warp um | spread nm | tolerance nm | agree |",
              "|---|---|---|---|---|---|---|"]
    for particles, check in data["com_check"].items():
        drop = {e: float(np.median(check["drops_m"][e])) * 1e6 for e in NAMES}
        lines.append(f"| {int(particles):,} | {drop['ours']:.3f} | {drop['taichi']:.3f} | {drop['warp']:.3f} | "
                     f"{check['spread_m'] * 1e9:.1f} | {check['tolerance_m'] * 1e9:.0f} | "
                     f"{'yes' if check['agree'] else '**NO**'} |")
    lines += ["", "Settings (from ours' counters, passed to the peers):", "",
              f"- grid spacing dx {s['dx_m'] * 1e3:g} mm, {s['particles_per_cell']:.0f} particles per cell "
              "(2 x 2 x 2), a cube of particles",
              f"- time step {s['dt_s'] * 1e6:.3f} us: CFL {s['cfl']:g} dx over the P-wave speed",
              f"- E {s['youngs_modulus_pa'] / 1e6:g} MPa, nu {s['poisson_ratio']:g}, rho {s['density_kg_m3']:g} "
              f"kg/m^3, gravity {s['gravity_m_s2']:g} m/s^2",
              f"- the block starts {s['gap_m'] * 1e3:g} mm above the floor, falling at {s['drop_speed_m_s']:g} m/s, "
              f"so that it lands within the {s['steps']:.0f} timed steps (after {s['warmup_steps']:.0f} of warm-up)",
              "", "Ours does more per step than the peers' kernels: it refits its grid box to the particles and sorts "
              "them into blocks, clamps J and caps speeds, and sums energies and momentum; the peers clear a fixed "
              "dense grid. Each engine's speed is its own design's: this is the same physics at the same settings, "
              "not the same code."]
    return "\n".join(lines) + "\n"


def _warp_threads(data: dict, by: dict) -> str:
    """What Warp did with a second thread, as measured, beside Taichi (which does use one) as the machine's check."""
    if 2 not in data["threads"]:
        return "Only one thread was measured: whether Warp's CPU backend uses a second core is not measured here."
    busy = {e: max(by[(e, n, 2)]["cores_busy_median"] for n in data["particles"]) for e in PEERS}
    if busy["taichi"] < 1.5:
        return (f"Offered two threads, Taichi kept at most {busy['taichi']:.2f} cores busy and Warp "
                f"{busy['warp']:.2f}: the machine gave the peers no second core in this run, so it does not show "
                "whether Warp uses one.")
    if busy["warp"] < 1.5:
        return (f"Warp's CPU backend ran on one core: offered two threads it kept at most {busy['warp']:.2f} cores "
                f"busy (Taichi {busy['taichi']:.2f}), so its 2-thread rows measure one core again.")
    return f"Warp's CPU backend used more than one core: up to {busy['warp']:.2f} busy when offered two threads."

if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Benchmark: what the draft preset's substep (its CFL factor) is worth in whole episodes: the smoke suite with
the oracle, run by `culinarycut bench run` as a user runs it, at the draft preset and at the other CFL (the
suite's `mpm = { cfl = ... }`): the accuracy study's draft pick when the preset is not it yet, else the previous
draft's; in alternating rounds against one server, with where each episode's time goes (the server's stages,
the policy, the harness). Writes docs/benchmarks/draft_lever.{md,json}.

    .venv/bin/python bench/draft_lever.py [--rounds 2]
"""
from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

from culinarycut.launch import ServerProcess, server_binary

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import ROOT, arguments, dated_machine_info, docs_for, interleaved  # noqa: E402
from bench.lib import quick  # noqa: E402
from bench.lib.accuracy import PREVIOUS_DRAFT, RESULTS_JSON, Setting, draft_pick, presets  # noqa: E402
from bench.lib.suite_runs import per_episode_parts, run_suite, with_top_level  # noqa: E402

PAGE, RESULTS = "benchmarks/draft_lever.md", "benchmarks/draft_lever.json"
SUITE = ROOT / "benchmarks" / "smoke.toml"
WORKERS = 2


def with_cfl(suite: Path, cfl: float, folder: Path) -> Path:
    """The suite's TOML with `mpm = { cfl = ... }` added at its top level (same name, another folder)."""
    return with_top_level(suite, f"mpm = {{ cfl = {cfl:g} }}", folder)


def other_draft() -> tuple[str, Setting]:
    """The setting to run beside the draft preset: the stored accuracy study's draft pick while the preset is not
    it, else the previous draft."""
    stored = json.loads(RESULTS_JSON.read_text())
    pick = draft_pick(stored["rows"], stored["slow"]["rows"], stored["whole"]["rows"])
    if pick and pick["key"] != presets()["draft"].key:
        chosen = next(r["setting"] for r in stored["rows"] if r["key"] == pick["key"])
        return "the accuracy study's draft pick", Setting(**chosen)
    return "previous draft", PREVIOUS_DRAFT


def run_once(suite: Path, server: ServerProcess, out: Path) -> dict:
    """One `culinarycut bench run` into a fresh folder: its wall time and per-episode sums from the rows."""
    return run_suite(suite, [server.address], WORKERS, out)


def main() -> int:
    parser = arguments(__doc__)
    parser.add_argument("--rounds", type=int, default=2, help="runs of the suite per setting, alternating")
    args = parser.parse_args()
    docs = docs_for(args)
    rounds = 1 if args.quick else args.rounds
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        suite = quick.suite(folder) if args.quick else SUITE
        (folder / "other").mkdir()
        role, other = other_draft()
        if (other.dx_mm, other.particles_per_cell) != (presets()["draft"].dx_mm, presets()["draft"].particles_per_cell):
            raise SystemExit(f"error: {other.label} differs from the draft preset in more than its CFL")
        settings = {f"draft preset ({presets()['draft'].label})": suite,
                    f"{role} ({other.label})": with_cfl(suite, other.cfl, folder / "other")}
        counter = iter(range(10_000))
        with ServerProcess(server_binary(), max_sessions=8, idle_timeout_s=600) as server:
            by_round = interleaved({name: (lambda s=path: run_once(s, server, folder / f"run-{next(counter)}"))
                                    for name, path in settings.items()}, rounds,
                                   announce=lambda i, name: print(f"round {i + 1}/{rounds}: {name}", flush=True))
    results = {name: _totals(runs) for name, runs in by_round.items()}
    preset, other_result = results.values()
    data = {"machine": dated_machine_info(), "suite": str(SUITE.relative_to(ROOT)), "workers": WORKERS,
            "rounds": rounds, "results": results,
            "episodes_per_hour_ratio": other_result["episodes_per_hour"] / preset["episodes_per_hour"]}
    text = _markdown(data)
    docs.publish(PAGE, text, RESULTS, data, __file__)
    print(text)
    return 0


def _totals(runs: list[dict]) -> dict:
    """The rounds of one setting summed: episodes per hour over all of them, seconds per episode by stage."""
    episodes = sum(r["episodes"] for r in runs)
    wall_s = sum(r["wall_s"] for r in runs)
    return {"episodes": episodes, "successes": sum(r["successes"] for r in runs), "wall_s": wall_s,
            "episodes_per_hour": 3600.0 * episodes / wall_s,
            "episode_s": sum(r["episode_s"] for r in runs) / episodes,
            "per_episode_s": per_episode_parts(runs),
            "resolved_cfl": sorted({c for r in runs for c in r["resolved_cfl"]}), "runs": runs}


def _markdown(data: dict) -> str:
    machine, results = data["machine"], data["results"]
    names = list(results)
    lines = ["# The draft preset's substep: episodes per hour", "",
             f"Generated by `bench/draft_lever.py`: `culinarycut bench run` on `{data['suite']}` with the oracle, "
             f"{data['workers']} workers against one server, no cameras; the draft preset against the same suite "
             "at another CFL (`mpm = { cfl = ... }` in the suite), "
             f"{data['rounds']} alternating rounds each.", "",
             f"Machine: {machine['cpu_model']}, {machine['cores']} cores, {machine['platform']}; {machine['date']}.", "",
             "| setting | episodes | successes | wall s | episodes / hour | s per episode |", "|---|---|---|---|---|---|"]
    for name, r in results.items():
        lines.append(f"| {name} | {r['episodes']} | {r['successes']} | {r['wall_s']:.0f} | "
                     f"{r['episodes_per_hour']:.0f} | {r['episode_s']:.1f} |")
    ratio, faster, slower = data["episodes_per_hour_ratio"], names[1], names[0]
    if ratio < 1.0:  # said as the faster over the slower
        ratio, faster, slower = 1.0 / ratio, names[0], names[1]
    lines += ["", f"Episodes per hour, the {faster} over the {slower}: **{ratio:.2f}x** "
              "(measured side by side in this run).", "",
              "Where an episode's time goes (seconds per episode, the worker's wall time; the stages are the server's "
              "own timers):", "", "| part | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]
    parts = list(next(iter(results.values()))["per_episode_s"])
    for part in parts:
        lines.append(f"| {part} | " + " | ".join(f"{results[n]['per_episode_s'][part]:.2f}" for n in names) + " |")
    lines += ["", "Stages that took no time (no cameras, no limiter) show 0.00. How the draft's CFL was chosen, and "
              "what it costs in accuracy: [../accuracy.md](../accuracy.md)."]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.exit(main())

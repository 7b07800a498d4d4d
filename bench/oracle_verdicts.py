"""Benchmark: the scripted oracle's verdicts under the success rule that scores the cut's orientation (its
position, the plane of the cut surface and the blade's plane in the food), on the smoke suite, one trial of each cucumber continuous-ratio
task and the coverage suite's apple, banana and cucumber (each in every style: bias, saw and guillotine cuts;
its melon, potato and similar tasks take 5-12 min an episode here), with each style's
signature in the knife's motion; the oracle's success in each of the paper's two scenes, from a small
`data generate` run that draws them; and what rendering costs in each scene.

Runs `culinarycut bench run` as a user does, against a server it starts, into run folders under --runs
(kept: run it again and the runner resumes where it stopped); then times one 224 px camera in each scene,
the two interleaved step by step in one session each. Writes docs/benchmarks/oracle_verdicts.{md,json}.

    .venv/bin/python bench/oracle_verdicts.py [--runs runs/oracle-verdicts]
"""
from __future__ import annotations

import fnmatch
import json
import sqlite3
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from culinarycut import Client
from culinarycut.launch import ServerProcess, server_binary

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import ROOT, arguments, docs_for, machine_info, today  # noqa: E402
from bench.lib import quick  # noqa: E402

PAGE, RESULTS = "benchmarks/oracle_verdicts.md", "benchmarks/oracle_verdicts.json"
# (suite, extra arguments): the smoke suite whole, one trial of each cucumber continuous-ratio task (its
# banana half repeats the same normal cuts on another food), and coverage's apple, banana and cucumber tasks.
# Coverage first: it has every style (bias, saw, guillotine), the ones the orientation rule tests hardest.
SUITES = (("coverage", ["--tasks", "[abc]*/*"]), ("smoke", []),
          ("continuous-ratio", ["--trials", "1", "--tasks", "cucumber/*"]))
RENDER_STEPS = 60      # control steps timed per scene
RENDER_WARMUP = 5
IMAGE_SIZE = 224       # px, the datasets' default
DATA_EPISODES_PER_TASK = 1  # the dataset seed 0 draws two table and two kitchen episodes


def run_suite(suite: str, extra: list[str], server: ServerProcess, out: Path, mixed: bool) -> float:
    """Runs (or resumes) the suite with the oracle; returns the wall time of this call (s). `mixed`: resume a
    run folder whose rows another build of the server stored."""
    command = [sys.executable, "-m", "culinarycut", "bench", "run", suite, "--policy", "oracle", "--workers", "2",
               "--out", str(out), "--server", server.address, "--no-progress", *extra,
               *(["--allow-mixed-versions"] if mixed else [])]
    started = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stdout}\n{done.stderr}")
    return time.perf_counter() - started


def _spread(values: list[float]) -> dict | None:
    """Median, 95th percentile and largest of some angle errors (deg); None when there are none."""
    if not values:
        return None
    array = np.asarray(values)
    return {"median": float(np.median(array)), "p95": float(np.percentile(array, 95)), "max": float(array.max())}


def verdicts(out: Path, extra: list[str]) -> dict:
    """Success rate, per style, and the measured cut planes' angle and position errors of one run (the tasks
    its --tasks pattern chose, if any: a run folder may hold more from an earlier, wider run)."""
    pattern = extra[extra.index("--tasks") + 1] if "--tasks" in extra else "*"
    db = sqlite3.connect(out / "results.sqlite")
    chosen = [row for row in db.execute("SELECT task, style, outcome, cuts, saw_strokes, pivot_deg, wall_s, build_id "
                                        "FROM episodes") if fnmatch.fnmatchcase(row[0], pattern)]
    rows = [row[1:6] for row in chosen]
    db.close()
    per_style: dict[str, list[int]] = {}
    signature: dict[str, dict[str, list[float]]] = {}
    angles, blade_angles, positions, unmeasured = [], [], [], 0
    for style, outcome, cuts, strokes, pivot in rows:
        per_style.setdefault(style, [0, 0])
        per_style[style][0] += 1
        per_style[style][1] += outcome == "success"
        if strokes is not None:
            signature.setdefault(style, {"saw_strokes": [], "pivot_deg": []})
            signature[style]["saw_strokes"].append(strokes)
            signature[style]["pivot_deg"].append(pivot)
        for cut in json.loads(cuts or "[]"):
            if cut.get("angle_error_deg") is None:
                unmeasured += bool(cut.get("placed"))
                continue
            angles.append(cut["angle_error_deg"])
            positions.append(cut["position_error_fraction"])
            if cut.get("blade_angle_error_deg") is not None:
                blade_angles.append(cut["blade_angle_error_deg"])
    return {"episodes": len(rows), "episode_wall_s": sum(row[6] for row in chosen),
            "builds": sorted({row[7] for row in chosen}), "successes": sum(s for _, s in per_style.values()), "per_style": per_style,
            "cuts_with_plane": len(angles), "placed_cuts_without_plane": unmeasured,
            "angle_error_deg": _spread(angles), "blade_angle_error_deg": _spread(blade_angles),
            "position_error_max": float(max(positions)) if positions else None,
            "signature": {style: {"saw_strokes_median": float(np.median(v["saw_strokes"])),
                                  "pivot_deg_median": float(np.median(v["pivot_deg"]))}
                          for style, v in signature.items()}}


def generate_both_scenes(server: ServerProcess, out: Path, tiny: bool = False) -> dict:
    """A small dataset over both scenes (every style, middle cuts on the cucumber, two episodes each, resumable):
    per scene, the episodes generated and kept (the oracle's success). `tiny`: one strawberry episode, 32 px."""
    command = [sys.executable, "-m", "culinarycut", "data", "generate", "--out", str(out), "--server", server.address,
               "--styles", "normal" if tiny else "all", "--states", "middle",
               "--episodes-per-task", str(DATA_EPISODES_PER_TASK), "--scenes", "table,kitchen", "--workers", "2",
               "--no-progress", *(["--food", quick.FOOD, "--image-size", str(quick.IMAGE_SIZE)] if tiny else [])]
    started = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stdout}\n{done.stderr}")
    db = sqlite3.connect(out / "generation.sqlite")
    counts = db.execute("SELECT scene, COUNT(*), SUM(kept) FROM jobs GROUP BY scene ORDER BY scene").fetchall()
    episode_wall_s = db.execute("SELECT SUM(wall_s) FROM jobs").fetchone()[0] or 0.0
    db.close()
    return {"wall_s": time.perf_counter() - started, "episode_wall_s": episode_wall_s,
            "per_scene": {scene: {"generated": n, "kept": kept} for scene, n, kept in counts}}


def render_cost(address: str, steps: int = RENDER_STEPS, warmup: int = RENDER_WARMUP) -> dict:
    """Per scene, the server's render time of one 224 px RGB camera per control step (ms), the two scenes
    stepped in turn so that both see the same machine load."""
    scenes = ("table", "kitchen")
    spec = {"quality": "draft", "effects": {"mpm": True}, "objects": [{"food": "cucumber"}],
            "cameras": [{"name": "front", "width": IMAGE_SIZE, "height": IMAGE_SIZE, "channels": ["rgb"]}]}
    times: dict[str, list[float]] = {scene: [] for scene in scenes}
    with Client(address, timeout_s=120) as client:
        sessions = {scene: client.create_session({**spec, "scene": scene}).session_id for scene in scenes}
        try:
            for sid in sessions.values():
                client.reset(sid, seed=0)
            hold = np.zeros(7)  # pd_joint_delta_pos: hold the pose
            for step in range(warmup + steps):
                for scene, sid in sessions.items():
                    response = client.step(sid, "pd_joint_delta_pos", hold)
                    if step >= warmup:
                        times[scene].append(response.info.render_wall_time_ms)
        finally:
            for sid in sessions.values():
                client.close_session(sid)
    medians = {scene: float(np.median(values)) for scene, values in times.items()}
    ratios = np.asarray(times["kitchen"]) / np.maximum(np.asarray(times["table"]), 1e-9)
    return {"steps": steps, "median_ms": medians, "kitchen_over_table_median_ratio": float(np.median(ratios))}


def markdown(results: dict) -> str:
    machine = results["machine"]
    lines = ["# The oracle's verdicts, orientation scored", "",
             f"Measured {results['date']} on {machine['cpu_model']} ({machine['cores']} cores) by "
             "`bench/oracle_verdicts.py`. A cut is correct when its position is within 1/10 of the object's length "
             "and both its orientations within 9 deg of the target plane (vertical across the long axis, or tilted "
             "20-35 deg about the edge for bias cuts): the plane of its cut surface, fitted to the particles either "
             "side of the blade, and the blade's mean plane while its edge passed the food, from the knife's pose.", "",
             f"Server builds that stored the rows: {', '.join(sorted({b for r in results['suites'].values() for b in r['builds']}))} "
             "(a build id is the commit the build was configured at; a local build reconfigures only when CMake "
             "files change).", "",
             "| suite | episodes | success | normal | bias | guillotine | saw | cuts with a plane | "
             "cut surface angle error median / p95 / max (deg) | blade angle error median / p95 / max (deg) | "
             "episode wall, summed (s) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, run in results["suites"].items():
        cells = []
        for style in ("normal", "bias", "guillotine", "saw"):
            n, ok = run["per_style"].get(style, [0, 0])
            cells.append(f"{ok}/{n}" if n else "-")
        angles = " | ".join(f"{a['median']:.1f} / {a['p95']:.1f} / {a['max']:.1f}" if a else "-"
                            for a in (run["angle_error_deg"], run.get("blade_angle_error_deg")))
        lines.append(f"| {name} | {run['episodes']} | {run['successes'] / max(1, run['episodes']):.0%} | "
                     + " | ".join(cells) + f" | {run['cuts_with_plane']} (placed without: {run['placed_cuts_without_plane']}) "
                     f"| {angles} | {run['episode_wall_s']:.0f} |")
    lines += ["", "## Each style's signature in the knife's motion", "",
              "Medians over each suite's episodes of that style, while the knife was in the food: reversals along the "
              "blade of at least 2 mm (`saw_strokes`) and the range of the blade's pitch (`pivot_deg`).", "",
              "| suite | style | saw strokes | pivot (deg) |", "|---|---|---|---|"]
    for name, run in results["suites"].items():
        for style, values in sorted(run["signature"].items()):
            lines.append(f"| {name} | {style} | {values['saw_strokes_median']:g} | {values['pivot_deg_median']:.1f} |")
    data = results["data"]
    lines += ["", "## The oracle in each scene", "",
              f"`culinarycut data generate` over both scenes (each episode draws one), every style, middle cuts on the "
              f"cucumber, {DATA_EPISODES_PER_TASK} episode(s) per style, 3 cameras of {IMAGE_SIZE} px "
              f"({data['episode_wall_s']:.0f} s of episodes, two at once):", "", "| scene | episodes | kept (oracle success) |", "|---|---|---|"]
    lines += [f"| {scene} | {v['generated']} | {v['kept']} |" for scene, v in data["per_scene"].items()]
    render = results["render"]
    lines += ["", "## Render cost per scene", "",
              f"One {IMAGE_SIZE} px RGB camera, draft cucumber, {render['steps']} control steps per scene, the two "
              "scenes stepped in turn (the server's render time per step):", "",
              "| scene | median render time per step (ms) |", "|---|---|"]
    lines += [f"| {scene} | {ms:.2f} |" for scene, ms in render["median_ms"].items()]
    lines += ["", f"Kitchen over table, step by step: {render['kitchen_over_table_median_ratio']:.2f}x (median ratio).", ""]
    return "\n".join(lines)


def main() -> int:
    parser = arguments(__doc__)
    parser.add_argument("--server-binary", default=str(server_binary()))
    parser.add_argument("--runs", default=str(ROOT / "runs" / "oracle-verdicts"), help="run folders (resumable)")
    parser.add_argument("--out", type=Path, default=None, help="the folder of the page and JSON "
                                                               "(default docs/benchmarks)")
    parser.add_argument("--allow-mixed-versions", action="store_true",
                        help="resume run folders another build stored into (the page lists the builds)")
    args = parser.parse_args()
    docs = docs_for(args, args.out)
    with tempfile.TemporaryDirectory() as scratch:
        # The smoke pass: a one-episode suite, one generated episode, 3 render steps, in a scratch folder.
        runs = Path(scratch) if args.quick else Path(args.runs)
        suites = (((str(quick.suite(runs)), []),) if args.quick else SUITES)
        results = {"date": today(), "machine": machine_info(), "suites": {}}
        with ServerProcess(args.server_binary, max_sessions=8, idle_timeout_s=600) as server:
            for suite, extra in suites:
                name = Path(suite).stem
                print(f"{name} ...", flush=True)
                wall_s = run_suite(suite, extra, server, runs / name, args.allow_mixed_versions)
                results["suites"][name] = {**verdicts(runs / name, extra), "wall_s": wall_s, "args": extra}
            print("data generate, both scenes ...", flush=True)
            results["data"] = generate_both_scenes(server, runs / "data", tiny=args.quick)
            results["render"] = render_cost(server.address, *((3, 1) if args.quick else ()))
    docs.publish(PAGE, markdown(results), RESULTS, results, __file__, indent=2)
    print(markdown(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The draft preset's reach: the scripted oracle's middle cut of every food (its real material preset) in every
style at `draft`, one trial each, through `culinarycut bench run coverage --policy oracle --workers 2` against a
local server it starts; the episodes that did not succeed, and the success of every task. Writes
docs/benchmarks/draft_coverage.{md,json}.

    .venv/bin/python bench/draft_coverage.py [--runs runs/draft-coverage] [--note TEXT ...] [--render-only]

The run folder is kept (run it again and the runner resumes where it stopped). --note adds a line on what this
run shows beside the one before (the page's notes are the run's, and a rerun starts without them).
"""
from __future__ import annotations

import sqlite3
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from culinarycut.bench.stats import wilson_interval
from culinarycut.launch import ServerProcess, server_binary

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import ROOT, arguments, dated_machine_info, docs_for  # noqa: E402
from bench.lib import quick  # noqa: E402

PAGE, RESULTS = "benchmarks/draft_coverage.md", "benchmarks/draft_coverage.json"
SUITE, WORKERS = "coverage", 2
# Why a task that fails fails, where that is known: shown under the table while it still fails.
EXPLAINED = {
    "melon/guillotine/middle": (
        "**The melon's guillotine cut** stalls before the blade touches the melon (`knife_stalled`, zero food "
        "force). It is the arm's reach, not the food: at the start pitch a 13.5 cm melon needs (65 deg, tip 1 mm into the board beyond the melon's far side) "
        "the knife's edge, and the hand behind it, face back towards the robot's base, and the arm reaches that pose "
        "with its elbow straight (joint 4 at its limit, -0.07 rad) about 4 mm short of the start. Two changes were "
        "tried and left out: setting the blade's collision box 5 mm back from the tip let the knife 4 mm lower, still "
        "at the elbow limit; pointing a guillotine's tip towards the robot turned the knife 180 deg on the way "
        "(6.5 s), reached the start and pivoted into the melon, but pressed 140-180 N on the wrist and stopped with "
        "joints 5 and 6 at their limits (-2.90 and 3.75 rad), one piece. At a full-size melon the planner already "
        "refuses the guillotine (start pitch 1.30 rad, at most 1.22). A guillotine on a melon needs a different grip "
        "or plan; the draft preset is not what stops it."),
}


def run_coverage(server: ServerProcess, out: Path, tasks: str | None) -> float:
    """Runs (or resumes) the coverage suite with the oracle; the wall time of this call (s)."""
    command = [sys.executable, "-m", "culinarycut", "bench", "run", SUITE, "--policy", "oracle", "--workers",
               str(WORKERS), "--out", str(out), "--server", server.address, "--no-progress",
               *(["--tasks", tasks] if tasks else [])]
    started = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stdout}\n{done.stderr}")
    return time.perf_counter() - started


def results_of(out: Path) -> dict:
    """Per task its trials and successes, the rows of the episodes that did not succeed, and the wall time."""
    db = sqlite3.connect(out / "results.sqlite")
    rows = db.execute("SELECT task, outcome, end_reason, pieces, stalled_steps, peak_force_n, wall_s, error "
                      "FROM episodes ORDER BY task, trial").fetchall()
    first, last = db.execute("SELECT MIN(finished_at - wall_s), MAX(finished_at) FROM episodes").fetchone()
    db.close()
    tasks: dict[str, dict] = {}
    for task, outcome, *_ in rows:
        tally = tasks.setdefault(task, {"trials": 0, "successes": 0})
        tally["trials"] += 1
        tally["successes"] += outcome == "success"
    failures = [{"task": task, "outcome": outcome, "end_reason": end_reason, "pieces": pieces,
                 "stalled_steps": stalled, "peak_force_n": force, "wall_s": wall_s, "error": error}
                for task, outcome, end_reason, pieces, stalled, force, wall_s, error in rows if outcome != "success"]
    return {"tasks": tasks, "failures": failures, "episode_wall_s": sum(r[6] or 0.0 for r in rows),
            "run_wall_s": (last - first) if rows else 0.0}


def markdown(stored: dict) -> str:
    m, tasks, failures = stored["machine"], stored["tasks"], stored["failures"]
    trials = sum(t["trials"] for t in tasks.values())
    successes = sum(t["successes"] for t in tasks.values())
    lines = ["# The draft preset's reach: every food in every style", "",
             f"`culinarycut bench run {SUITE} --policy oracle --workers {stored['workers']}` against one local server "
             "(`bench/draft_coverage.py`): the scripted oracle's middle cut of each food (real material presets) in "
             "each style at `draft`, one trial each.", "",
             f"Machine: {m['cpu_model']}, {m['cores']} cores, {m['platform']}; {m['date']}. {successes}/{trials} "
             f"succeeded; the episodes took {stored['episode_wall_s'] / 60:.0f} minutes of wall time in all "
             f"({stored['run_wall_s'] / 60:.0f} minutes with {stored['workers']} at once).", ""]
    if stored.get("imported"):
        lines += [f"*{stored['imported']}*", ""]
    if failures:
        lines += [f"## The episode{'s' if len(failures) > 1 else ''} that did not succeed", "",
                  "| task | outcome | end reason | pieces | steps with the arm stalled | peak wrist force (N) | wall s "
                  "| error |", "|---|---|---|---|---|---|---|---|"]
        for f in failures:
            lines.append(f"| {f['task']} | {f['outcome']} | {f['end_reason'] or ''} | {f['pieces']} | "
                         f"{f['stalled_steps']} | {f['peak_force_n'] or 0.0:.1f} | {f['wall_s']:.0f} | "
                         f"{f['error'] or ''} |")
        lines += [""] + [f"- {EXPLAINED[f['task']]}" for f in failures if f["task"] in EXPLAINED]
        lines += ["- Every other task succeeded: its cut within the success rule's tolerance.", ""]
    if stored.get("notes"):
        lines += ["## Notes on this run", ""] + [f"- {note}" for note in stored["notes"]] + [""]
    lines += ["## Success per task", "", "| task | success | rate | 95 % CI |", "|---|---|---|---|"]
    for task, t in sorted(tasks.items()):
        low, high = wilson_interval(t["successes"], t["trials"])
        lines.append(f"| {task} | {t['successes']}/{t['trials']} | {t['successes'] / t['trials']:.0%} | "
                     f"{low:.0%} - {high:.0%} |".replace("%", " %"))
    return "\n".join(lines) + "\n"


def main() -> int:
    parser = arguments(__doc__, whole_doc=True, render_only=True)
    parser.add_argument("--runs", type=Path, default=ROOT / "runs" / "draft-coverage", help="run folder (resumable)")
    parser.add_argument("--note", action="append", default=[], help="a line for the page's notes (repeatable)")
    args = parser.parse_args()
    docs = docs_for(args)
    if args.render_only:
        docs.render_stored(PAGE, RESULTS, markdown, __file__)
        return 0
    with tempfile.TemporaryDirectory() as scratch:
        runs = Path(scratch) / "coverage" if args.quick else args.runs  # the smoke pass: the strawberry's normal cut
        with ServerProcess(server_binary(), max_sessions=8, idle_timeout_s=600) as server:
            run_coverage(server, runs, f"{quick.FOOD}/normal/*" if args.quick else None)
        stored = {"machine": dated_machine_info(), "suite": SUITE, "workers": WORKERS, **results_of(runs),
                  "notes": args.note}
    docs.publish(PAGE, markdown(stored), RESULTS, stored, __file__)
    print(markdown(stored))
    return 0


if __name__ == "__main__":
    sys.exit(main())

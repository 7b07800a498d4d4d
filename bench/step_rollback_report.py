#!/usr/bin/env python3
"""What a cancellable Step saves for its rollback while the food sleeps: the lazy rollback (the robot and the
food's scalars; the particles only once the step is about to change them) against the full state copy every
Step made before, at the draft, standard and fine presets, interleaved in one process per preset
(bench_step_rollback). Writes docs/benchmarks/step_rollback.md and .json.

    .venv/bin/python bench/step_rollback_report.py [--bench build/bench/bench_step_rollback] [--rounds 40]
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import arguments, bench_binary, docs_for, machine_info, missing, today  # noqa: E402

PAGE, RESULTS = "benchmarks/step_rollback.md", "benchmarks/step_rollback.json"
PRESETS = ("draft", "standard", "fine")


def markdown(stored: dict) -> str:
    machine = stored["machine"]
    lines = ["# A Step's rollback while the food sleeps", "",
             f"Measured {stored['date']} on {machine['cpu_model']} ({machine['cores']} cores), "
             f"{stored['rounds']} rounds per preset, the four timings interleaved round by round in one process "
             "(bench_step_rollback). The knife holds still far above a cucumber, so the food sleeps and no MPM "
             "substep runs: the approach, the retreat and the robot between cuts. A server Step is always "
             "cancellable (a client may give up, the server may stop), so it saves what a cancelled step puts back.",
             "", "- **plain**: Step with nothing saved (no cancel check).",
             "- **full copy**: the whole state saved, then the Step: what every server Step did before.",
             "- **lazy**: what a server Step does now: the robot and the food's scalars saved; the particles only "
             "once the step is about to change them, which a sleeping food's step never is.",
             "- **rollback**: the lazy save alone.", "",
             "| preset | particles | plain (ms) | full copy (ms) | lazy (ms) | rollback (ms) | saved before / now (bytes) "
             "| full copy / lazy |", "|---|---|---|---|---|---|---|---|"]
    for row in stored["rows"]:
        lines.append(f"| {row['preset']} | {row['particles']:,} | {row['plain_ms']:.3f} | {row['full_copy_ms']:.3f} "
                     f"| {row['lazy_ms']:.3f} | {row['rollback_ms']:.4f} | {row['snapshot_bytes']:,} / "
                     f"{row['rollback_bytes']:,} | {row['full_copy_ms'] / row['lazy_ms']:.1f}x |")
    lines += ["", "Medians of the rounds. While the food is awake a step still copies its particles once, as before "
              "(the copy is the step's `rollback` stage: `StepInfo.rollback_wall_time_ms` and the session's "
              "`stage_wall_time_s`), next to MPM substeps that cost far more.", ""]
    return "\n".join(lines)


def main() -> int:
    parser = arguments(__doc__, render_only=True)
    parser.add_argument("--bench", type=Path, default=bench_binary("bench_step_rollback"))
    parser.add_argument("--rounds", type=int, default=40)
    args = parser.parse_args()
    docs = docs_for(args)
    if args.render_only:
        docs.render_stored(PAGE, RESULTS, markdown, __file__)
        return 0
    if code := missing(args.bench, "--bench"):
        return code
    rounds = 3 if args.quick else args.rounds
    presets = PRESETS[:1] if args.quick else PRESETS
    rows = []
    for preset in presets:
        print(f"{preset} ...", flush=True)
        out = subprocess.run([str(args.bench), preset, str(rounds)], check=True, capture_output=True, text=True).stdout
        rows.append(json.loads(out))
        print(f"  full copy {rows[-1]['full_copy_ms']:.3f} ms, lazy {rows[-1]['lazy_ms']:.3f} ms", flush=True)
    stored = {"machine": machine_info(), "date": today(), "rounds": rounds, "rows": rows}
    docs.publish(PAGE, markdown(stored), RESULTS, stored, __file__)
    print(f"wrote {docs.path(PAGE)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The learned policy's baseline on the benchmark suites, end to end and resumable:

1. generate a training split at draft: cucumber and banana in every style, at the middle, every ratio 0.1-0.9
   from the left and 0.2, 0.4, 0.6, 0.8 from the right (so the suites' other right-hand ratios are ratios the
   policy never saw from that end; `culinarycut data generate`, front and wrist cameras; it resumes itself);
2. export it (robomimic HDF5; again only when the dataset changed);
3. train (`python -m culinarycut_learning train`; resumes from its last checkpoint);
4. serve the checkpoint and run each suite through the openpi adapter (`culinarycut bench run`; each
   run folder resumes), and the floors (`--floor random`) on the same episodes;
5. write BASELINES.md and .json (default docs/benchmarks/baselines.{md,json} of this checkout): success
   per suite with 95 % Wilson intervals, per food, the data, the training and every stage's wall time.

Killed at any point, the same command goes on where it stopped (every stage is resumable and the stage
times add up in STUDY/study.json). It commits nothing. At full size (the defaults: 10 episodes per task,
112 tasks, 20,000 training steps, 5 trials of each suite's tasks) it takes many hours on a 2-core machine:
train on a GPU (`--device cuda`) and spread the episodes over servers (`--server` repeated).

    python learning/scripts/baseline_study.py --out studies/baseline --server 127.0.0.1:50051
"""
from __future__ import annotations

import argparse
import datetime
import json
import shutil
import sqlite3
import subprocess
import sys
from pathlib import Path

from culinarycut_learning.study import CHECKOUT, Study, machine, runs_report, serve, summarise
FOODS = ("cucumber", "banana")
STYLES = ("normal", "bias", "guillotine", "saw")
STATES = (("middle",) + tuple(f"ratio-{r / 10:g}" for r in range(1, 10))
          + tuple(f"ratio-{r / 10:g}-right" for r in (2, 4, 6, 8)))
SUITES = ("unseen-seeds", "multi-object", "unseen-language", str(CHECKOUT / "learning" / "suites" / "cross-object.toml"),
          "continuous-ratio", "split-partial", "topology-ablation")  # cross-object: trained on cucumber and banana
# learning/suites/two-foods/ holds these suites cut to the two foods and sized for one 2-core session.


def kept_episodes(dataset: Path) -> int:
    with sqlite3.connect(dataset / "generation.sqlite") as db:
        return int(db.execute("SELECT COUNT(*) FROM jobs WHERE kept = 1").fetchone()[0])


# The options that decide a study folder's data: another value for one of them needs another folder.
DATA_OPTIONS = ("foods", "styles", "states", "episodes_per_task", "image_size", "seed")


def export(study: Study, dataset: Path, out: Path) -> None:
    """Exports again only when the dataset has other kept episodes than the last export."""
    marker = out / "exported.json"
    kept = kept_episodes(dataset)
    if marker.is_file() and json.loads(marker.read_text()).get("kept") == kept:
        study.log(f"export: {out} is up to date ({kept} episodes)")
        study.called.append("export")  # reached, for the report's order
        return
    if out.exists():
        for path in sorted(out.rglob("*"), reverse=True):
            path.unlink() if path.is_file() else path.rmdir()
    study.stage("export", ["-m", "culinarycut", "data", "export", dataset, "--out", out, "--format", "robomimic"])
    marker.write_text(json.dumps({"kept": kept}) + "\n")


def evaluate(study: Study, args, url: str | None, policy: str, suite: str) -> dict | None:
    out = study.root / "bench" / f"{Path(suite).stem}-{policy}"
    command = ["-m", "culinarycut", "bench", "run", suite, "--policy", "openpi" if policy == "learned" else policy,
               "--out", out, "--workers", args.workers, "--no-progress"]
    if policy == "learned":
        command += ["--policy-url", url, "--policy-option", f"camera_size={args.image_size}"]
    for server in args.server:
        command += ["--server", server]
    if args.trials:
        command += ["--trials", args.trials]
    if args.tasks:
        command += ["--tasks", args.tasks]
    # 0: all ran cleanly; 3: some episodes stored as errors (counted in the table); 2: no task matches --tasks
    code = study.stage(f"evaluate {Path(suite).stem} {policy}", command, ok_codes=(0, 2, 3))
    return None if code == 2 else summarise(out)


def policy_label(policy: str) -> str:
    return "learned (openpi)" if policy == "learned" else policy


def suite_reports(study: Study, results: dict, folder: Path) -> list[str]:
    """Each suite's runs side by side as `culinarycut bench report` writes them (per task, style, food, group, the
    ratio radars) in FOLDER/SUITE/, and the success per suite chart; the markdown lines that show them."""
    from culinarycut.bench.report import load_run
    from culinarycut.bench.report_charts import success_per
    if folder.exists():
        shutil.rmtree(folder)  # this study's own folder: reports of suites no longer run go with it
    rows_of_policy: dict[str, list[dict]] = {}
    lines = []
    for suite, policies in results.items():
        runs = [(policy, study.root / "bench" / f"{suite}-{policy}") for policy, r in policies.items() if r is not None]
        if not runs:
            continue
        runs_report(folder / suite, [run for _, run in runs], [policy_label(p) for p, _ in runs], study.root)
        for policy, run in runs:
            rows_of_policy.setdefault(policy_label(policy), []).extend(load_run(run).rows)
        letters = ", ".join(f"{chr(ord('A') + i)}: {policy_label(p)}" for i, (p, _) in enumerate(runs))
        lines.append(f"- [{suite}]({folder.name}/{suite}/report.md) ({letters})")
        lines += [f"  ![{suite}: {chart.stem}]({folder.name}/{suite}/report_files/{chart.name})"
                  for chart in sorted((folder / suite / "report_files").glob("ratio_radar_*.png"))]
    chart = success_per(list(rows_of_policy.items()), "suite", "Success per suite (95 % Wilson intervals)",
                        sort_values=False)
    (folder / "success_per_suite.png").write_bytes(chart)
    return [f"![success per suite]({folder.name}/success_per_suite.png)", "",
            "Each suite's runs side by side (`culinarycut bench report`: success per task, style, food and group, "
            "cut quality, forces, failures):", ""] + lines


def write_report(study: Study, args, results: dict, docs: Path) -> None:
    import torch
    checkpoint = torch.load(study.root / "run" / "checkpoint.pt", map_location="cpu")
    training = {"steps": checkpoint["step"], "loss": checkpoint["loss"], "config": checkpoint["config"],
                "data": {k: checkpoint["data"][k] for k in ("episodes", "frames", "valid_episodes", "sha256")},
                "device": args.device}
    commit = subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], capture_output=True, text=True,
                            cwd=CHECKOUT).stdout.strip() or "unknown"
    report = {
        "generated": datetime.date.today().isoformat(), "commit": commit,
        "machine": machine(),
        "options": study.state["options"], "stages_wall_s": study.stage_times(),
        "training": training, "suites": results,
    }
    docs.mkdir(parents=True, exist_ok=True)
    (docs / "baselines.json").write_text(json.dumps(report, indent=1, sort_keys=True) + "\n")
    o = study.state["options"]
    lines = [
        "# Baselines: the learned policy on the suites", "",
        f"Generated by `learning/scripts/baseline_study.py` on {report['generated']} (commit {commit}; "
        f"{report['machine']['cpu_model']}, {report['machine']['cores']} cores, {report['machine']['platform']}, "
        f"torch {report['machine']['torch']}).", "",
        f"Training data: {', '.join(o['foods'])} in {', '.join(o['styles'])} at {', '.join(o['states'])}, "
        f"{o['episodes_per_task']} episode(s) per task at draft, front and wrist cameras at {o['image_size']} px: "
        f"{training['data']['episodes']} training episodes, {training['data']['frames']} frames. "
        f"Model: docs/learning.md, {training['steps']} steps on {args.device} (last batch loss {training['loss']:.4f}). "
        f"Evaluation: {'the first ' + str(o['trials']) + ' trial(s) of ' if o['trials'] else ''}each suite's tasks"
        f"{' matching ' + repr(o['tasks']) if o['tasks'] else ''}, through the openpi adapter's defaults.", "",
    ]
    if o.get("note"):
        lines += [o["note"], ""]
    lines += ["| suite | policy | episodes | success | rate | 95 % CI (Wilson) | errors |", "|---|---|---|---|---|---|---|"]
    for suite, policies in results.items():
        for policy, r in policies.items():
            if r is None:
                lines.append(f"| {suite} | {policy} | 0 | - | - | - | - |")
                continue
            rate = f"{100 * r['rate']:.0f} %" if r["rate"] is not None else "-"
            lines.append(f"| {suite} | {policy} | {r['episodes']} | {r['successes']}/{r['episodes']} | {rate} | "
                         f"{100 * r['ci95'][0]:.0f} % - {100 * r['ci95'][1]:.0f} % | {r['errors']} |")
    lines += ["", "Per food (successes / episodes):", "", "| suite | food | " + " | ".join(
        policy_label(p) for p in ["learned", *o["floor"]]) + " |", "|---|---|" + "---|" * (1 + len(o["floor"]))]
    for suite, policies in results.items():
        foods = sorted({f for r in policies.values() if r for f in r["by_food"]})
        for food in foods:
            cells = [(f"{r['by_food'][food]['successes']}/{r['by_food'][food]['episodes']}"
                      if r and food in r["by_food"] else "-") for r in policies.values()]
            lines.append(f"| {suite} | {food} | " + " | ".join(cells) + " |")
    lines += [""] + suite_reports(study, results, docs / "baselines")
    lines += ["", "Wall time per stage (s, accumulated over resumed invocations):", "",
              "| stage | wall (s) |", "|---|---|"]
    lines += [f"| {k} | {v:.1f} |" for k, v in report["stages_wall_s"].items()]
    (docs / "baselines.md").write_text("\n".join(lines) + "\n")
    study.log(f"wrote {docs / 'baselines.md'} and baselines.json")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, type=Path, help="the study folder (resumed when it exists)")
    parser.add_argument("--server", action="append", required=True, metavar="HOST:PORT", help="culinarycut-server (repeatable)")
    parser.add_argument("--foods", default=",".join(FOODS))
    parser.add_argument("--styles", default=",".join(STYLES))
    parser.add_argument("--states", default=",".join(STATES), help="comma list: middle, ratio-R, ratio-R-right, split-N")
    parser.add_argument("--episodes-per-task", type=int, default=10)
    parser.add_argument("--image-size", type=int, default=96, help="cameras and model images, pixels")
    parser.add_argument("--seed", type=int, default=0, help="the dataset's and the training's seed")
    parser.add_argument("--workers", type=int, default=2, help="episodes at once (generation and evaluation)")
    parser.add_argument("--steps", type=int, default=20000, help="training steps")
    parser.add_argument("--batch-size", type=int, default=32)
    parser.add_argument("--device", default="cpu", help="training and serving device: cpu, cuda, auto")
    parser.add_argument("--suites", default=",".join(SUITES), help="comma list of suite names or .toml files")
    parser.add_argument("--trials", type=int, default=5, help="the first N trials of each task (0: the suite's count)")
    parser.add_argument("--tasks", help="only the suites' tasks matching this pattern (bench run --tasks)")
    parser.add_argument("--floor", default="random", help="comma list of built-in policies run beside it ('' for none)")
    parser.add_argument("--docs", type=Path, default=CHECKOUT / "docs" / "benchmarks",
                        help="where baselines.md and baselines.json go")
    parser.add_argument("--port", type=int, help="the policy server's port (default: a free one, kept for resuming)")
    parser.add_argument("--note", default="", help="a sentence for the report (e.g. that this is a tiny run)")
    args = parser.parse_args(argv)
    options = {"foods": args.foods.split(","), "styles": args.styles.split(","), "states": args.states.split(","),
               "episodes_per_task": args.episodes_per_task, "image_size": args.image_size, "seed": args.seed,
               "steps": args.steps, "batch_size": args.batch_size, "suites": args.suites.split(","),
               "trials": args.trials, "tasks": args.tasks, "floor": [p for p in args.floor.split(",") if p],
               "note": args.note}
    study = Study(args.out.resolve(), options, DATA_OPTIONS, "baseline_study")
    root = study.root
    generate = ["-m", "culinarycut", "data", "generate", "--out", root / "data", "--styles", args.styles,
                "--states", args.states, "--episodes-per-task", args.episodes_per_task, "--cameras", "front,wrist",
                "--image-size", args.image_size, "--seed", args.seed, "--workers", args.workers, "--quality", "draft"]
    for food in options["foods"]:
        generate += ["--food", food]
    for server in args.server:
        generate += ["--server", server]
    study.stage("generate", generate)
    export(study, root / "data", root / "export")
    study.stage("train", ["-m", "culinarycut_learning", "train", "--data", root / "export", "--out", root / "run",
                          "--steps", args.steps, "--batch-size", args.batch_size, "--image-size", args.image_size,
                          "--seed", args.seed, "--device", args.device])
    process, url = serve(root / "run", args.device, study.port(wanted=args.port))
    results: dict[str, dict] = {}
    try:
        for suite in options["suites"]:
            name = Path(suite).stem
            results[name] = {"learned": evaluate(study, args, url, "learned", suite)}
            for floor in options["floor"]:
                results[name][floor] = evaluate(study, args, None, floor, suite)
    finally:
        process.terminate()
        process.wait(30)
    write_report(study, args, results, args.docs)
    return 0


if __name__ == "__main__":
    sys.exit(main())

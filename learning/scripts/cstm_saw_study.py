#!/usr/bin/env python3
"""The CulinaryCut paper's saw experiment with our learned policy and the CSTM, end to end and resumable:

1. train the policy twice on one export (`culinarycut data export`, e.g. the baseline study's, which holds every
   style): on its saw cuts only (`train --styles saw`) and on its normal cuts only (`--styles normal`);
2. train the CSTM's contact classifier C on the export's frames and the simulator's contact labels;
3. record (normal, saw) oracle pairs of the same scenes through a live server, and train the style generator f;
4. run one suite of saw tasks (the foods and states given, the success rule's position and blade orientation)
   with the oracle, the saw-trained policy, the normal-trained policy, and the normal-trained policy wrapped by
   the CSTM in the saw style, each served like a remote model and run through `culinarycut bench run`;
5. write CSTM_SAW.md and .json (default docs/benchmarks/cstm_saw.{md,json}): success with 95 % Wilson
   intervals, the saw strokes the cuts made, C's held-out accuracy, f's held-out L1, every stage's wall time.

Killed at any point, the same command goes on where it stopped. It commits nothing.

    python learning/scripts/cstm_saw_study.py --out runs/cstm-saw --data runs/baseline-study/export \\
        --server 127.0.0.1:50051
"""
from __future__ import annotations

import argparse
import datetime
import json
import sqlite3
import sys
from pathlib import Path

from culinarycut_learning.study import CHECKOUT, Study, machine, runs_report, serve, summarise

# The options that decide a study folder's results: another value for one of them needs another folder.
FIXED = ("data", "foods", "states", "pairs", "image_size", "seed", "steps", "trials")
POLICY_STYLES = ("saw", "normal")  # the two policies: trained on the export's saw cuts, on its normal cuts


def suite_text(foods: list[str], states: list[str], trials: int) -> str:
    """A suite of saw tasks: each food at each state (middle, or ratio-R measured from the left)."""
    lines = ['name = "cstm-saw"', 'description = "saw cuts for the CSTM experiment"', f"trials = {trials}",
             "max_episode_steps = 600", 'quality = "draft"', ""]
    food_list = "[" + ", ".join(f'"{food}"' for food in foods) + "]"
    for state in states:
        lines += ["[[tasks]]", f"food = {food_list}", 'style = "saw"']
        if state == "middle":
            lines += ['state = "middle"', ""]
        elif state.startswith("ratio-"):
            lines += ['state = "ratio"', f"ratio = {float(state[len('ratio-'):]):g}", 'side = "left"', ""]
        else:
            raise SystemExit(f"--states: {state} is neither middle nor ratio-R")
    return "\n".join(lines)


def run_folder(study: Study, label: str) -> Path:
    return study.root / "bench" / label.replace(" ", "-").replace("+", "plus")


def evaluate(study: Study, args, suite: Path, label: str, policy: str, options: list) -> dict:
    out = run_folder(study, label)
    command = ["-m", "culinarycut", "bench", "run", suite, "--policy", policy, *options, "--out", out,
               "--workers", args.workers, "--no-progress"]
    for server in args.server:
        command += ["--server", server]
    study.stage(f"evaluate {label}", command, ok_codes=(0, 3))  # 3: some episodes stored as errors (counted)
    result = summarise(out)
    with sqlite3.connect(out / "results.sqlite") as db:
        strokes = [s for (s,) in db.execute("SELECT saw_strokes FROM episodes WHERE outcome != 'error'")]
    result["saw_strokes_mean"] = sum(strokes) / len(strokes) if strokes else None
    return result


def last_logged(run: Path, key: str):
    """The last value of `key` in a run folder's log.jsonl (None when never logged)."""
    value = None
    for line in (run / "log.jsonl").read_text().splitlines():
        value = json.loads(line).get(key, value)
    return value


def side_by_side(study: Study, results: dict, folder: Path) -> list[str]:
    """The four runs as `culinarycut bench report` compares them (per task and food, the cut's position and the
    blade's orientation against the success rule's tolerances, forces, failures) in FOLDER, and a chart of
    success per food; the markdown lines that show them."""
    from culinarycut.bench.report import load_run
    from culinarycut.bench.report_charts import success_per
    runs = [run_folder(study, label) for label in results]
    runs_report(folder, runs, list(results), study.root)
    chart = success_per([(label, load_run(run).rows) for label, run in zip(results, runs)], "food",
                        "Saw cuts: success per food (95 % Wilson intervals)")
    (folder / "success_per_food.png").write_bytes(chart)
    return [f"![saw cuts: success per food]({folder.name}/success_per_food.png)", "",
            f"The runs side by side, with the cuts' position and blade-orientation errors: [{folder.name}/report.md]"
            f"({folder.name}/report.md).", ""]


def write_report(study: Study, results: dict, docs: Path) -> None:
    o, root = study.state["options"], study.root
    report = {"generated": datetime.date.today().isoformat(), "options": o,
              "machine": machine(),
              "classifier_valid_accuracy": last_logged(root / "classifier", "valid_accuracy"),
              "classifier_valid_balanced_accuracy": last_logged(root / "classifier", "valid_balanced_accuracy"),
              "generator_valid_l1": last_logged(root / "generator", "valid_l1"),
              "stages_wall_s": study.stage_times(), "policies": results}
    docs.mkdir(parents=True, exist_ok=True)
    (docs / "cstm_saw.json").write_text(json.dumps(report, indent=1, sort_keys=True) + "\n")
    accuracy = report["classifier_valid_accuracy"]
    l1 = report["generator_valid_l1"]
    lines = ["# The CSTM's saw experiment", "",
             f"Generated by `learning/scripts/cstm_saw_study.py` on {report['generated']} from the export given as "
             f"`--data` (its path in cstm_saw.json): the policy trained {o['steps']} steps on its saw cuts and on its normal cuts; C trained on "
             f"its frames (held-out accuracy {accuracy if accuracy is None else f'{accuracy:.3f}'}); f on "
             f"{o['pairs']} (normal, saw) oracle pairs per food and state (held-out L1 "
             f"{l1 if l1 is None else f'{l1:.4f}'}). Evaluated on saw cuts of {', '.join(o['foods'])} at "
             f"{', '.join(o['states'])}, {o['trials']} trial(s) each, at draft.", "",
             "| policy | episodes | success | rate | 95 % CI (Wilson) | saw strokes (mean) | errors |",
             "|---|---|---|---|---|---|---|"]
    for label, r in results.items():
        rate = f"{100 * r['rate']:.0f} %" if r["rate"] is not None else "-"
        strokes = "-" if r["saw_strokes_mean"] is None else f"{r['saw_strokes_mean']:.1f}"
        lines.append(f"| {label} | {r['episodes']} | {r['successes']}/{r['episodes']} | {rate} | "
                     f"{100 * r['ci95'][0]:.0f} % - {100 * r['ci95'][1]:.0f} % | {strokes} | {r['errors']} |")
    lines += [""] + side_by_side(study, results, docs / "cstm_saw")
    lines += ["Wall time per stage (s, accumulated over resumed invocations):", "", "| stage | wall (s) |",
              "|---|---|"] + [f"| {k} | {v:.1f} |" for k, v in report["stages_wall_s"].items()]
    (docs / "cstm_saw.md").write_text("\n".join(lines) + "\n")
    study.log(f"wrote {docs / 'cstm_saw.md'} and cstm_saw.json")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, type=Path, help="the study folder (resumed when it exists)")
    parser.add_argument("--data", required=True, type=Path, help="an export folder holding normal and saw cuts")
    parser.add_argument("--server", action="append", required=True, metavar="HOST:PORT",
                        help="culinarycut-server (repeatable; the pairs use the first)")
    parser.add_argument("--foods", default="cucumber,banana")
    parser.add_argument("--states", default="middle,ratio-0.3,ratio-0.5,ratio-0.7",
                        help="comma list: middle or ratio-R (pairs and evaluation)")
    parser.add_argument("--pairs", type=int, default=10, help="(normal, saw) pairs per food and state")
    parser.add_argument("--image-size", type=int, default=96, help="the export's camera size, pixels")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--steps", type=int, default=3000, help="training steps of each policy")
    parser.add_argument("--batch-size", type=int, default=32)
    parser.add_argument("--classifier-steps", type=int, default=2000)
    parser.add_argument("--generator-steps", type=int, default=2000)
    parser.add_argument("--trials", type=int, default=5, help="trials of each saw task")
    parser.add_argument("--workers", type=int, default=2, help="episodes at once")
    parser.add_argument("--device", default="cpu", help="training and serving device: cpu, cuda, auto")
    parser.add_argument("--docs", type=Path, default=CHECKOUT / "docs" / "benchmarks",
                        help="where CSTM_SAW.md and .json go (default docs/benchmarks of this checkout)")
    args = parser.parse_args(argv)
    foods, states = args.foods.split(","), args.states.split(",")
    options = {"data": str(args.data.resolve()), "foods": foods, "states": states, "pairs": args.pairs,
               "image_size": args.image_size, "seed": args.seed, "steps": args.steps, "trials": args.trials}
    study = Study(args.out.resolve(), options, FIXED, "cstm_saw_study")
    root, data = study.root, args.data.resolve()
    device = ["--device", args.device]
    for style in POLICY_STYLES:
        study.stage(f"train on {style} cuts", ["-m", "culinarycut_learning", "train", "--data", data, "--out",
                                               root / f"policy-{style}", "--styles", style, "--steps", args.steps,
                                               "--batch-size", args.batch_size, "--image-size", args.image_size,
                                               "--seed", args.seed, "--no-progress", *device])
    study.stage("train C", ["-m", "culinarycut_learning", "cstm-classifier", "train", "--data", data, "--out",
                            root / "classifier", "--steps", args.classifier_steps, "--seed", args.seed,
                            "--no-progress", *device])
    pairs = ["-m", "culinarycut_learning", "cstm-generator", "pairs", "--server", args.server[0], "--out",
             root / "pairs", "--style", "saw", "--pairs", args.pairs, "--seed", args.seed]
    for food in foods:
        pairs += ["--food", food]
    for state in states:
        pairs += ["--state", state]
    study.stage("record pairs", pairs)
    study.stage("train f", ["-m", "culinarycut_learning", "cstm-generator", "train", "--pairs", root / "pairs",
                            "--out", root / "generator", "--steps", args.generator_steps, "--seed", args.seed,
                            "--no-progress", *device])
    suite = root / "cstm-saw.toml"
    suite.write_text(suite_text(foods, states, args.trials))
    served = {style: serve(root / f"policy-{style}", args.device, study.port(f"port_{style}"))
              for style in POLICY_STYLES}
    learned = {style: ["--policy-url", url, "--policy-option", f"camera_size={args.image_size}"]
               for style, (_, url) in served.items()}
    try:
        results = {
            "oracle": evaluate(study, args, suite, "oracle", "oracle", []),
            "trained on saw cuts": evaluate(study, args, suite, "trained on saw cuts", "openpi", learned["saw"]),
            "trained on normal cuts": evaluate(study, args, suite, "trained on normal cuts", "openpi",
                                               learned["normal"]),
            "trained on normal cuts + CSTM (saw)": evaluate(
                study, args, suite, "trained on normal cuts + CSTM (saw)", "culinarycut_learning.cstm.policy:CstmPolicy",
                ["--policy-option", "inner=openpi", "--policy-url", served["normal"][1],
                 "--policy-option", f"inner.camera_size={args.image_size}",
                 "--policy-option", f"classifier={root / 'classifier'}",
                 "--policy-option", f"generator={root / 'generator'}", "--policy-option", "style=saw"]),
        }
    finally:
        for process, _ in served.values():
            process.terminate()
            process.wait(30)
    write_report(study, results, args.docs)
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""How far the accuracy study's errors move with the particle-sampling seed alone, and whether the settings it
ranks differ by more than that. The study (bench/accuracy_cost.py; its library is bench/lib/accuracy.py) runs
each setting once, at seed 0, and calls one setting as accurate as another when no error is higher by more than
a fixed margin; this reruns the robot's slow cuts at the settings that decide the 5x target with other seeds (the
same cut, the food's particles drawn again) and compares each setting with the previous standard preset seed by
seed (paired: both see the same particles). Writes docs/benchmarks/seed_spread.md, .json and docs/images/seed_spread.png.

    .venv/bin/python bench/seed_spread.py [--cc-cut build/tools/cc_cut/cc-cut] [--workers 2] [--runs DIR]
        [--seeds 5] [--whole-seeds 3]

Runs at seed 0 are the accuracy study's own (shared through --runs); every run is one cc-cut process on one thread.
"""
from __future__ import annotations

import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path

import numpy as np

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import arguments, cc_cut, docs_for, machine_info, missing, pyplot, save_figure, today  # noqa: E402
from bench.lib.accuracy import (PREVIOUS_STANDARD, QUANTITY_NAMES, REFERENCE, RESOLVED, SLOW_CASE,  # noqa: E402
                                WHOLE_CASE, Setting, errors, slow_case, stored_run, stored_run_path, with_setting)

PAGE, RESULTS = "benchmarks/seed_spread.md", "benchmarks/seed_spread.json"
# The settings that decide the 5x target on the slow cuts (docs/accuracy.md): the yardstick, the standard
# preset's CFL 0.4 and 0.5, fewer particles per cell, and mass scaling. The whole cucumber costs 1-5 minutes a
# run (x8 is left out).
_REAL_MASS = [PREVIOUS_STANDARD, Setting(4, 8, 0.4), Setting(4, 8, 0.5), Setting(4, 6, 0.5), Setting(4, 5, 0.5),
              Setting(4, 6, 0.8)]
SETTINGS = {SLOW_CASE: [*_REAL_MASS, Setting(4, 8, 0.4, 4.0), Setting(4, 8, 0.5, 4.0), Setting(4, 8, 0.4, 8.0),
                        Setting(4, 8, 0.4, 16.0)],
            WHOLE_CASE: [*_REAL_MASS, Setting(4, 8, 0.4, 4.0), Setting(4, 8, 0.5, 4.0), Setting(4, 8, 0.4, 16.0)]}
# The study's peak force is over cc-cut's 5 ms window (the paper's dt_acc); a 20 ms window shows whether a shift
# lives in the force's short swings or in the force the cut takes.
LONG_WINDOW_S = 0.02
RESAMPLE_S = 2.5e-4  # the force is resampled this often before the windowed means
# The quantities the 5x decision turns on (knife speed and final shape hardly move between these settings, and the
# seed runs here keep no particles).
ACCURACY_METRICS = ("cut_position_mm", "peak_force", "mean_force", "force_curve_l2")
T_95 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26}  # Student t, two-sided


def run_all(cc_cut: Path, runs_dir: Path, workers: int, seeds: dict[str, int]) -> dict:
    """{case: {setting key: {seed: run}}}; the reference at seed 0 only (it is the study's)."""
    from tqdm import tqdm
    runs_dir.mkdir(parents=True, exist_ok=True)
    specs = slow_case()
    jobs = [(case, REFERENCE, 0) for case in SETTINGS]
    jobs += [(case, s, seed) for case, settings in SETTINGS.items() for s in settings for seed in range(seeds[case])]
    jobs.sort(key=lambda j: (j[0] == WHOLE_CASE, j[1] == REFERENCE, j[1].particles_per_cell / j[1].cfl
                             / j[1].mass_scaling ** 0.5), reverse=True)  # longest first: the workers end together

    def one(case: str, setting: Setting, seed: int) -> tuple[str, Setting, int, dict]:
        spec = with_setting(specs[case], setting)
        spec["scene"]["seed"] = seed
        stored = stored_run_path(runs_dir, case, setting.key, seed)  # seed 0: the accuracy study's own run
        return case, setting, seed, stored_run(cc_cut, spec, stored, particles=False)

    results: dict = {}
    with ThreadPoolExecutor(max_workers=workers) as pool, tqdm(total=len(jobs), unit="run") as bar:
        for future in as_completed([pool.submit(one, *job) for job in jobs]):
            case, setting, seed, result = future.result()
            results.setdefault(case, {}).setdefault(setting.key, {})[seed] = result
            bar.update(1)
    return results


def paired(values: list[float]) -> dict:
    """Mean, sample sd and 95 % interval of the mean of per-seed values."""
    v = np.asarray(values, dtype=float)
    sd = float(v.std(ddof=1)) if len(v) > 1 else 0.0
    half = T_95.get(len(v) - 1, 2.0) * sd / np.sqrt(len(v)) if len(v) > 1 else float("inf")
    return {"mean": float(v.mean()), "sd": sd, "low": float(v.mean() - half), "high": float(v.mean() + half)}


def windowed_peak_n(run: dict, window_s: float, knife_speed_m_s: float) -> float:
    """The blade force's highest mean over window_s of the knife's travel (the slow cuts descend at a constant
    speed, so depth stands for time), resampled every RESAMPLE_S."""
    step_mm = knife_speed_m_s * RESAMPLE_S * 1e3
    depth_mm = np.asarray(run["depth_mm"], dtype=float)
    order = np.argsort(depth_mm, kind="stable")
    uniform = np.arange(depth_mm[order[0]], depth_mm[order[-1]], step_mm)
    force = np.interp(uniform, depth_mm[order], np.asarray(run["blade_n"], dtype=float)[order])
    n = max(1, int(round(window_s / RESAMPLE_S)))
    return float(np.convolve(force, np.ones(n) / n, mode="valid").max())


def analyse(runs: dict) -> dict:
    """Per case and setting: each seed's errors against the case's reference, their spread, the paired
    differences from the previous standard, and the peak force's paired shift (signed, not an error)."""
    out = {}
    for case in SETTINGS:
        by_key = runs[case]
        reference = by_key[REFERENCE.key][0]
        yard = by_key[PREVIOUS_STANDARD.key]
        yard_errors = {seed: errors(r, reference) for seed, r in yard.items()}
        speed = slow_case()[case]["knife"]["descent_speed_m_s"]
        yard_long = {seed: windowed_peak_n(r, LONG_WINDOW_S, speed) for seed, r in yard.items()}
        rows = []
        for setting in SETTINGS[case]:
            mine = by_key[setting.key]
            seeds = sorted(mine)
            errs = {seed: errors(mine[seed], reference) for seed in seeds}
            row = {"key": setting.key, "label": setting.label, "seeds": seeds,
                   "same_particles": setting.particles_per_cell == PREVIOUS_STANDARD.particles_per_cell,
                   "wall_s": float(np.mean([mine[s]["wall_s"] for s in seeds])),
                   "speedup": float(np.mean([yard[s]["wall_s"] for s in seeds]) / np.mean([mine[s]["wall_s"] for s in seeds])),
                   "pieces": sorted({len(mine[s]["piece_volumes_m3"]) for s in seeds}),
                   "errors": {m: [errs[s][m] for s in seeds] for m in ACCURACY_METRICS},
                   "spread": {m: paired([errs[s][m] for s in seeds]) for m in ACCURACY_METRICS},
                   "difference": {m: paired([errs[s][m] - yard_errors[s][m] for s in seeds]) for m in ACCURACY_METRICS},
                   "peak_force_shift": paired([mine[s]["peak_blade_n"] / yard[s]["peak_blade_n"] - 1.0 for s in seeds]),
                   "long_window_peak_shift": paired([windowed_peak_n(mine[s], LONG_WINDOW_S, speed) / yard_long[s] - 1.0
                                                     for s in seeds]),
                   "peak_force_n": [mine[s]["peak_blade_n"] for s in seeds]}
            row["worse_on"] = [m for m in ACCURACY_METRICS if row["difference"][m]["low"] > RESOLVED[m]]
            row["within_noise"] = not row["worse_on"] and row["pieces"] == [len(reference["piece_volumes_m3"])]
            rows.append(row)
        out[case] = {"reference_peak_force_n": reference["peak_blade_n"], "rows": rows}
    return out


def plot(stored: dict, path: Path) -> None:
    cases = list(stored["cases"])
    fig, axes = pyplot().subplots(len(cases), len(ACCURACY_METRICS), figsize=(14, 3.6 * len(cases)), squeeze=False)
    for axes_row, case in zip(axes, cases):
        rows = stored["cases"][case]["rows"]
        for ax, metric in zip(axes_row, ACCURACY_METRICS):
            scale = 1.0 if metric == "cut_position_mm" else 100.0
            for i, row in enumerate(rows):
                values = np.asarray(row["errors"][metric], dtype=float) * scale
                ax.scatter(np.full(len(values), i) + np.linspace(-0.12, 0.12, len(values)), values, s=16,
                           color="tab:blue" if row["key"] == PREVIOUS_STANDARD.key else "tab:orange")
                ax.hlines(values.mean(), i - 0.25, i + 0.25, color="k", lw=1.5)
            ax.set_xticks(range(len(rows)))
            ax.set_xticklabels([f"{r['label'].replace('dx 4 mm, 8 ppc, ', '').replace(', ', chr(10))}\n{r['speedup']:.1f}x"
                                for r in rows],
                               fontsize=7)
            ax.set_ylabel(f"{QUANTITY_NAMES[metric]} error ({'mm' if scale == 1.0 else '%'})")
            ax.grid(True, axis="y", alpha=0.3)
        axes_row[0].set_title(case, loc="left", fontsize=9)
    fig.suptitle("Each seed's error against the reference (dots) and their mean (bar); speed-up over CFL 0.2")
    fig.tight_layout()
    save_figure(fig, path)


def _pm(summary: dict, scale: float = 100.0, unit: str = "") -> str:
    return f"{scale * summary['mean']:+.2f}{unit} [{scale * summary['low']:+.2f}, {scale * summary['high']:+.2f}]"


def markdown(stored: dict) -> str:
    m = stored["machine"]
    lines = [
        "# Seed spread: what the accuracy study can resolve",
        "",
        "Generated by `bench/seed_spread.py`. The accuracy study (docs/accuracy.md) runs every setting once, with the "
        "particles sampled from seed 0, and calls a setting as accurate as another when none of its errors is higher "
        "by more than a fixed margin (0.5 % of force, 0.05 mm of cut position). Here the robot's slow cuts are rerun "
        "at the settings that decide the 5x target with other seeds: the same food, knife and resolution, the food's "
        "particles drawn again. The reference (dx 2.5 mm, seed 0) is the study's.",
        "",
        f"Machine: {m['cpu_model']}, {m['cores']} cores, {m['platform']}; {stored['date']}. One cc-cut process per "
        f"run on one thread, {stored['workers']} at a time.",
        "",
        "![errors per seed](../images/seed_spread.png)",
        "",
    ]
    for case, data in stored["cases"].items():
        rows = data["rows"]
        lines += [f"## {case}", "",
                  f"Seeds 0-{max(len(r['seeds']) for r in rows) - 1}; each error as mean ± sample sd over the seeds.",
                  "", "| setting | speed-up | pieces | " + " | ".join(QUANTITY_NAMES[q] for q in ACCURACY_METRICS) + " |",
                  "|---|---|---|" + "---|" * len(ACCURACY_METRICS)]
        for r in rows:
            cells = []
            for q in ACCURACY_METRICS:
                s, scale, unit = r["spread"][q], (1.0 if q == "cut_position_mm" else 100.0), (" mm" if q == "cut_position_mm" else " %")
                cells.append(f"{scale * s['mean']:.2f} ± {scale * s['sd']:.2f}{unit}")
            lines.append(f"| {r['label']} | {r['speedup']:.1f}x | {', '.join(map(str, r['pieces']))} | " + " | ".join(cells) + " |")
        lines += ["", "Against the previous standard seed by seed (this setting's error minus its, mean and 95 % "
                  "interval of the mean), and the peak force's own shift (signed), over the study's 5 ms window and "
                  f"over {1e3 * LONG_WINDOW_S:.0f} ms. *Worse beyond the seeds' spread*: "
                  "the whole interval lies above the study's margin.", "",
                  "| setting | " + " | ".join(QUANTITY_NAMES[q] for q in ACCURACY_METRICS) +
                  f" | peak force shift | over {1e3 * LONG_WINDOW_S:.0f} ms | worse beyond the seeds' spread |",
                  "|---|" + "---|" * (len(ACCURACY_METRICS) + 3)]
        for r in rows[1:]:
            cells = [_pm(r["difference"][q], 1.0 if q == "cut_position_mm" else 100.0,
                         " mm" if q == "cut_position_mm" else " pt") for q in ACCURACY_METRICS]
            worse = ", ".join(QUANTITY_NAMES[q] for q in r["worse_on"]) or "no"
            lines.append(f"| {r['label']} | " + " | ".join(cells) + f" | {_pm(r['peak_force_shift'], unit=' %')} | "
                         f"{_pm(r['long_window_peak_shift'], unit=' %')} | {worse} |")
        lines.append("")
    lines += ["## What it says", ""] + findings(stored)
    return "\n".join(lines) + "\n"


def findings(stored: dict) -> list[str]:
    """The page's reading of its own numbers."""
    slow = {r["key"]: r for r in stored["cases"][SLOW_CASE]["rows"]}
    yard = slow[PREVIOUS_STANDARD.key]
    peak = yard["spread"]["peak_force"]
    sd_n = float(np.std(yard["peak_force_n"], ddof=1))
    lines = [f"- **One seed does not resolve the margins the study decides on.** At the previous standard the slow "
             f"cut's peak force error is {100 * peak['mean']:.1f} ± {100 * peak['sd']:.1f} % over the seeds (its peak "
             f"force itself varies by {sd_n:.2f} N, {100 * sd_n / np.mean(yard['peak_force_n']):.1f} %), mean force "
             f"{100 * yard['spread']['mean_force']['mean']:.1f} ± {100 * yard['spread']['mean_force']['sd']:.1f} %; "
             f"the study's margin is 0.5 %."]
    for case, data in stored["cases"].items():
        for r in data["rows"][1:]:
            shift = r["peak_force_shift"]
            verdict = ("no error is higher beyond the seeds' spread" if r["within_noise"] else
                       "higher beyond the seeds' spread on " + ", ".join(QUANTITY_NAMES[q] for q in r["worse_on"]))
            lines.append(f"- {case}, **{r['label']}** ({r['speedup']:.1f}x): {verdict}; its peak force is "
                         f"{100 * shift['mean']:+.1f} % (95 % interval {100 * shift['low']:+.1f} to "
                         f"{100 * shift['high']:+.1f} %) off the previous standard's " +
                         ("with the same particles." if r.get("same_particles", True) else
                          "seed for seed (other particles: the pairing adds nothing)."))
    lines += _short_swings(stored)
    fastest = max(stored["cases"][SLOW_CASE]["rows"][1:], key=lambda r: r["speedup"])
    shift = fastest["peak_force_shift"]
    if fastest["within_noise"] and (shift["low"] > 0.0 or shift["high"] < 0.0):
        lines.append(f"- **Within the spread is not the same as as accurate.** {fastest['label']} "
                     f"({fastest['speedup']:.1f}x) errs no more than the previous standard beyond what the seeds resolve "
                     f"({len(fastest['seeds'])} seeds), yet with the same particles it moves the peak force by "
                     f"{100 * shift['mean']:+.1f} % (95 % interval {100 * shift['low']:+.1f} to {100 * shift['high']:+.1f} "
                     "%): a bias of its own, hidden in the errors because the "
                     "dx 4 mm runs scatter on both sides of the reference. So the study does not count it as meeting "
                     "the previous standard's accuracy.")
    return lines


def _short_swings(stored: dict) -> list[str]:
    """Where mass scaling's peak force shift lives: in the force's short swings, or in the force the cut takes."""
    shifted = [(case, r) for case, data in stored["cases"].items() for r in data["rows"]
               if "mass x" in r["label"] and r["peak_force_shift"]["low"] > 0.0]
    if not shifted:
        return []

    def part(case: str, r: dict) -> str:
        return (f"{r['label']} on the {'whole cucumber' if case == WHOLE_CASE else '0.6-scale cut'} "
                f"{100 * r['peak_force_shift']['mean']:+.1f} % over 5 ms, "
                f"{100 * r['long_window_peak_shift']['mean']:+.1f} % over {1e3 * LONG_WINDOW_S:.0f} ms")

    # Short: at most half of the 5 ms shift is left once the force is averaged over the longer window.
    short = [(c, r) for c, r in shifted if r["long_window_peak_shift"]["mean"] <= 0.5 * r["peak_force_shift"]["mean"]]
    rest = [(c, r) for c, r in shifted if (c, r) not in short]
    line = (f"- **Where mass scaling's peak force shift lives.** Where the 5 ms peak moves beyond the seeds' spread, "
            f"the peak of the force averaged over {1e3 * LONG_WINDOW_S:.0f} ms moves less. ")
    if short:
        line += ("Mostly in swings shorter than that, not in the force the cut takes: "
                 + "; ".join(part(c, r) for c, r in short) + ". ")
    if rest:
        line += "In the force the cut takes as well: " + "; ".join(part(c, r) for c, r in rest) + ". "
    line += ("Why heavier food swings harder is not traced here. The 5 ms window is the paper's force accumulation "
             "window, and a robot's force limit sees those swings, so the study keeps judging the 5 ms peak.")
    return [line]


def main() -> int:
    parser = arguments(__doc__, render_only=True)
    parser.add_argument("--cc-cut", type=Path, default=cc_cut())
    parser.add_argument("--workers", type=int, default=2, help="cc-cut runs at a time (one thread each)")
    parser.add_argument("--runs", type=Path, default=Path(tempfile.gettempdir()) / "culinarycut-accuracy-runs",
                        help="finished runs are kept here (shared with accuracy_cost.py); a rerun reuses them")
    parser.add_argument("--seeds", type=int, default=5, help="seeds of the 0.6-scale slow cut (about 90 s of runs each)")
    parser.add_argument("--whole-seeds", type=int, default=3, help="seeds of the whole cucumber (about 9 min each)")
    args = parser.parse_args()
    docs = docs_for(args)
    if args.quick:
        print("error: seed_spread has no smoke pass of its own (every run is a 0.05 m/s cut, 1.5-9 min): use "
              "--render-only", file=sys.stderr)
        return 2
    if not args.render_only:
        if code := missing(args.cc_cut, "--cc-cut"):
            return code
        if min(args.seeds, args.whole_seeds) < 2:
            print("error: --seeds and --whole-seeds need at least 2 (a spread needs two runs)", file=sys.stderr)
            return 2
        runs = run_all(args.cc_cut, args.runs, args.workers, {SLOW_CASE: args.seeds, WHOLE_CASE: args.whole_seeds})
        stored = {"machine": machine_info(), "date": today(), "workers": args.workers, "cases": analyse(runs)}
        docs.write_json(RESULTS, stored, __file__)
    stored = docs.stored(RESULTS)
    plot(stored, docs.image("seed_spread.png"))
    docs.write_page(PAGE, markdown(stored), __file__, RESULTS, stored)
    print(f"wrote {docs.path(PAGE)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

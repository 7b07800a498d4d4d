#!/usr/bin/env python3
"""What accuracy costs in time: representative cuts run by cc-cut over a grid of the MPM's quality knobs
(grid spacing, particles per cell, CFL factor, mass scaling), each measured against the finest affordable run,
drawn as Pareto fronts (worst error over the cuts against their summed wall time) with the presets marked.
Writes docs/accuracy.md, docs/benchmarks/accuracy_cost.json, docs/images/accuracy_pareto.png and, through
tools/gen_accuracy_table.py, the table the server answers presets and accuracy targets from,
sim/world/measured_accuracy_table.cc (rebuild after a rerun).

    .venv/bin/python bench/accuracy_cost.py [--cc-cut build/tools/cc_cut/cc-cut] [--workers 2] [--runs DIR]
    .venv/bin/python bench/accuracy_cost.py --check [--cc-cut ...]
    .venv/bin/python bench/accuracy_cost.py --render-only

Every run is one cc-cut process on one thread; --workers runs that many at once. Finished runs are kept in
--runs (one JSON file each), so a killed study resumes where it stopped. --check is the test suite's guard:
it cuts the guard case at each preset and fails (exit 1) when an error against the stored reference exceeds
the bound the page documents. The settings, errors and guard are bench/lib/accuracy.py.
"""
from __future__ import annotations

import json
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])

from bench.harness import arguments, cc_cut, dated_machine_info, docs_for, missing, pyplot, save_figure  # noqa: E402
from bench.lib.accuracy import (ACTIVITY_RADII_MM, GUARD_CASE, GUARD_METRICS, HIGH_CFLS,  # noqa: E402
                                MAX_CHOSEN_CFL, PREVIOUS_DRAFT, PREVIOUS_STANDARD, QUANTITY_NAMES, REFERENCE,
                                RESOLVED, SLOW_CASE, SLOW_GRID, SLOW_GRIDS, SPEED_M_S, TARGET_SPEEDUP, WHOLE_CASE,
                                WHOLE_GRID, Setting, cases, check, draft_pick, grid, guard_bounds, presets, reference_record,
                                slow_case, slow_study,
                                stored_run, stored_run_path, study, with_setting, worse_than)

sys.path.insert(1, str(Path(__file__).resolve().parents[1] / "tools"))
from gen_accuracy_table import TABLE_CC, cxx_table  # noqa: E402  (tools/: the engine's table from the JSON)

PAGE, RESULTS = "accuracy.md", "benchmarks/accuracy_cost.json"


def run_all(cc_cut: Path, runs_dir: Path, workers: int) -> tuple[dict, dict]:
    """Every cut of the grid, and the slow cut at each mass scaling: {case: {setting key: run}} for each."""
    from tqdm import tqdm
    runs_dir.mkdir(parents=True, exist_ok=True)
    specs = {**cases(), **slow_case()}
    jobs = [(name, setting) for name in cases() for setting in grid()]
    jobs += [(name, setting) for name, grid in SLOW_GRIDS.items() for setting in grid]
    # The longest (finest, slowest, largest) runs first, so the workers finish together.
    effort = {SLOW_CASE: 10.0, WHOLE_CASE: 80.0}
    jobs.sort(key=lambda job: effort.get(job[0], 1.0) * job[1].dx_mm ** -3.8
              * job[1].particles_per_cell / job[1].mass_scaling ** 0.5, reverse=True)
    results: dict = {}

    def one(name: str, setting: Setting) -> tuple[str, Setting, dict]:
        stored = stored_run_path(runs_dir, name, setting.key)
        return name, setting, stored_run(cc_cut, with_setting(specs[name], setting), stored)

    with ThreadPoolExecutor(max_workers=workers) as pool, tqdm(total=len(jobs), unit="run") as bar:
        for future in as_completed([pool.submit(one, *job) for job in jobs]):
            name, setting, result = future.result()
            results.setdefault(name, {})[setting.key] = result
            bar.update(1)
    slow = {name: results.pop(name) for name in SLOW_GRIDS}
    return results, slow



def pareto(points: list[tuple[float, float]]) -> list[int]:
    """Indices of the points no other point beats in both cost and error, by cost."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], float("inf")
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


METRICS = (("cut_position_mm", "cut position error (mm)"), ("peak_force", "peak force error (relative)"),
           ("mean_force", "mean force error (relative)"), ("force_curve_l2", "force-depth curve error (rel. L2)"),
           ("knife_speed", "knife speed error (relative)"), ("final_shape_mm", "final shape error (mm, RMS)"))


def plot(stored: dict, path: Path) -> None:
    plt = pyplot()
    rows = [r for r in stored["rows"] if r["key"] != stored["reference"]]  # the reference has no error
    fig, axes = plt.subplots(2, 3, figsize=(16, 8.5))
    for ax, (metric, title) in zip(axes.flat, METRICS):
        shown = [r for r in rows if r["worst"][metric] is not None]
        xy = [(r["wall_s"], max(r["worst"][metric], 1e-4)) for r in shown]
        colours = ["tab:orange" if r["setting"]["mass_scaling"] != 1.0 else
                   "tab:green" if r["setting"].get("activity_mm") else "tab:blue" for r in shown]
        ax.scatter([p[0] for p in xy], [p[1] for p in xy], c=colours, s=22, zorder=2)
        front = pareto(xy)
        ax.plot([xy[i][0] for i in front], [xy[i][1] for i in front], "k--", lw=1, zorder=1, label="Pareto front")
        for r, (x, y) in zip(shown, xy):
            if r["preset"]:
                ax.scatter([x], [y], s=110, facecolors="none", edgecolors="red", zorder=3)
                ax.annotate(r["preset"], (x, y), textcoords="offset points", xytext=(6, 6), color="red")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time of the cuts, 1 thread (s)")
        ax.set_ylabel(f"worst {title}")
        ax.grid(True, which="both", alpha=0.3)
    axes.flat[0].scatter([], [], c="tab:blue", s=22, label="real mass")
    axes.flat[0].scatter([], [], c="tab:orange", s=22, label="mass scaling")
    axes.flat[0].scatter([], [], c="tab:green", s=22, label="activity")
    axes.flat[0].legend(loc="upper right", fontsize=8)
    fig.suptitle(f"What accuracy costs: {len(stored['cases'])} cuts against dx {REFERENCE.dx_mm:g} mm")
    fig.tight_layout()
    save_figure(fig, path)


def _fmt(value: float | None, percent: bool = True) -> str:
    if value is None:
        return "-"
    return f"{100 * value:.1f} %" if percent else f"{value:.2f}"


def _substep_finding(by_key: dict, slow_by_key: dict) -> str:
    """What the substep costs at the standard's particles per cell, from CFL 0.5 to the stability edge."""
    low, high = Setting(4, 6, 0.5), Setting(4, 6, HIGH_CFLS[-1])
    fast_low, fast_high = by_key[low.key]["worst"], by_key[high.key]["worst"]
    slow_low, slow_high = slow_by_key[low.key], slow_by_key[high.key]
    return (f"- **The substep is a lever up to the stability edge**: at 6 ppc from "
            f"CFL 0.5 to {HIGH_CFLS[-1]:g} (c dt = dx) the worst peak force error goes from "
            f"{100 * fast_low['peak_force']:.1f} to {100 * fast_high['peak_force']:.1f} %, the force curve's from "
            f"{100 * fast_low['force_curve_l2']:.1f} to {100 * fast_high['force_curve_l2']:.1f} %, for "
            f"{by_key[low.key]['wall_s'] / by_key[high.key]['wall_s']:.1f}x less wall time; on the slow cut the "
            f"knife's speed error goes from {100 * slow_low['errors']['knife_speed']:.2f} to "
            f"{100 * slow_high['errors']['knife_speed']:.2f} % (below). CFL {HIGH_CFLS[-1]:g} "
            + ("cut every food as the reference did" if fast_high["piece_count"] == 0
               and slow_high["errors"]["piece_count"] == 0 else "did not cut every food as the reference did")
            + f", but the presets and accuracy targets choose among settings up to CFL {MAX_CHOSEN_CFL:g}, a margin for "
            "the scenes this study does not run.")


def _findings(stored: dict) -> list[str]:
    """The page's reading of its own numbers, each taken from the stored rows."""
    by_key = {r["key"]: r for r in stored["rows"]}
    standard, draft = by_key[presets()["standard"].key], by_key[presets()["draft"].key]
    previous = by_key[PREVIOUS_STANDARD.key]
    pick, slow = stored["cheaper_than_standard"], stored["slow"]
    slow_by_key = {r["key"]: r for r in slow["rows"]}
    slow_real = slow_by_key[PREVIOUS_STANDARD.key]
    target = slow["target"]
    draft_choice = draft_pick(stored["rows"], slow["rows"], stored["whole"]["rows"])
    lines = [
        f"- **The standard preset is chosen from the front**: the cheapest real-mass setting at least as accurate as "
        f"the previous standard ({PREVIOUS_STANDARD.label}) on every quantity is **{pick['label']}**, "
        f"{pick['speedup']:.1f}x less wall time over the same cuts. "
        + ("That is the standard preset now." if pick["key"] == presets()["standard"].key else
           f"**The standard preset ({presets()['standard'].label}) is not that setting: update "
           "sim/world/quality_preset.cc.**"),
        *([] if draft_choice is None else [
        f"- **The draft's substep, from the front**: the cheapest real-mass setting at least as accurate "
        f"as {PREVIOUS_DRAFT.label} (the draft preset on 2026-11-28, kept as the yardstick) on every quantity, over these cuts and on both of the robot's "
        f"slow cuts, is **{draft_choice['label']}**: {draft_choice['speedup']:.1f}x less wall time and "
        f"{draft_choice['substep_ratio']:.1f}x fewer substeps over the same cuts. "
        + ("That is the draft preset now." if draft_choice["key"] == presets()["draft"].key else
           f"**The draft preset is still {presets()['draft'].label}**: switching it moves every force at draft, so it "
           "goes with refitting the safety model (fitted at draft, docs/safety.md) and rerunning the oracle's "
           "verdicts; what the pick is worth in whole episodes is measured in "
           "[benchmarks/draft_lever.md](benchmarks/draft_lever.md).")]),
        f"- **standard** is within {100 * standard['worst']['peak_force']:.1f} % of the reference's peak force, "
        f"{100 * standard['worst']['force_curve_l2']:.1f} % of its force curve and "
        f"{standard['worst']['cut_position_mm']:.2f} mm of its cut on every cut (the previous standard: "
        f"{100 * previous['worst']['peak_force']:.1f} %, {100 * previous['worst']['force_curve_l2']:.1f} %, "
        f"{previous['worst']['cut_position_mm']:.2f} mm); **draft** costs {draft['wall_s'] / standard['wall_s']:.2f}x "
        f"as much, with {100 * draft['worst']['peak_force']:.0f} % and {100 * draft['worst']['force_curve_l2']:.0f} %.",
        "- **Mass scaling is a lever for slow cuts only.** At the study's 0.5 m/s the food's kinetic energy is "
        f"already {previous['kinetic_to_elastic_energy']:.2f} of its elastic energy with real mass, and the scaled "
        "runs lose accuracy on the force curve. At the robot's 0.05 m/s it is "
        f"{slow_real['kinetic_to_elastic_energy']:.3f}.",
        _substep_finding(by_key, slow_by_key),
        f"- **At the robot's speed** the cheapest setting at least as accurate as the previous standard against the "
        f"slow cut's own reference is **{target['label']}**, {target['speedup']:.1f}x less wall time: "
        + ("the 5x target is met." if target["met"] else f"short of the {TARGET_SPEEDUP:g}x target (below)."),
        "- **The cucumber's force does not converge monotonically** (its faces' friction at dx 4 mm, docs/mpm.md): "
        "its peak force moves by about 10 % between dx 3 and 2.5 mm, which bounds how well any setting can be "
        "judged on that cut.",
        "- **The grid's extent is not a lever**: one empty cell around the particles instead of three saves under "
        "5 % and changes only rounding (benchmarks/grid_extent.md, which also profiles a cut: the per-particle "
        "transfers take over 80 % of it, so integrating fewer particles is the lever left).",
        _whole_finding(stored),
        _activity_finding(stored),
        _knife_speed_finding(stored),
        _final_shape_finding(stored),
    ]
    return lines


def _knife_speed_finding(stored: dict) -> str:
    """How far the knife's speed (as the world slows it) moves with the setting, from the stored rows."""
    slow = {r["key"]: r for r in stored["slow"]["rows"]}
    whole = {r["key"]: r for r in stored["whole"]["rows"]}

    def loss(rows: dict, setting: Setting) -> float:
        """The share of its speed the knife loses to the food, %."""
        return 100 * (1.0 - rows[setting.key]["knife_speed_factor"])

    cfls = [s for s in sorted(SLOW_GRID, key=lambda s: s.cfl) if (s.dx_mm, s.particles_per_cell, s.mass_scaling,
                                                                     s.activity_mm) == (4, 6, 1.0, 0.0)]
    worst = {r["key"]: r["worst"]["knife_speed"] for r in stored["rows"]}
    return (f"- **The knife's speed converges with the forces**, and is in the rule. The world slows the knife by the "
            f"paper's quadratic speed resistance, whose contact strength is the edge's sweep, its engaged length "
            f"times its speed, free of the substep (docs/mpm.md). On the slow cucumber cut the knife loses "
            f"{loss(slow, REFERENCE):.2f} % of its speed at the reference, {loss(slow, PREVIOUS_STANDARD):.2f} % at "
            f"the previous standard and " + ", ".join(f"{loss(slow, s):.2f} %" for s in cfls)
            + f" at 6 ppc from CFL {cfls[0].cfl:g} to {cfls[-1].cfl:g} ({loss(slow, Setting(4, 8, 0.4, 16.0)):.2f} % "
            f"at CFL 0.4 with mass x16); on the whole cucumber {loss(whole, REFERENCE):.2f} % at the reference and "
            f"{loss(whole, presets()['standard']):.2f} % at the standard. Over the study's cuts the standard's knife "
            f"speed is up to {100 * worst[presets()['standard'].key]:.1f} % off the reference's (the previous "
            f"standard's {100 * worst[PREVIOUS_STANDARD.key]:.1f} %).")


def _final_shape_finding(stored: dict) -> str:
    """How far apart the settings' final piece shapes are, from the stored rows."""
    shapes = {r["key"]: r["worst"]["final_shape_mm"] for r in stored["rows"]
              if r["key"] != stored["reference"] and r["worst"]["final_shape_mm"] is not None}
    worst_key = max(shapes, key=shapes.get)
    worst_label = next(r["label"] for r in stored["rows"] if r["key"] == worst_key)
    return (f"- **The pieces' final shapes agree within what the measure resolves**: after a best rigid fit of each "
            f"piece, every setting's material ends {min(shapes.values()):.2f}-{max(shapes.values()):.2f} mm RMS from "
            f"where the reference carried it, draft ({shapes[presets()['draft'].key]:.2f} mm) as close as dx 3 mm "
            f"({shapes[Setting(3, 8, 0.2).key]:.2f} mm): no trend towards the finer grids, so what is left is the "
            f"measure's own floor between two particle samplings (each particle is compared with the reference's "
            f"nearest, moved by the rest offset, which is off where the edge crushed the material). The farthest is "
            f"{worst_label}. These foods are elastic where they are not cut, and once apart the pieces take back "
            "their shape.")


def _activity_rows(stored: dict) -> list[dict]:
    """Each activity radius on each kind of cut against the same setting without it, from the stored rows."""
    without = Setting(4, 8, 0.4)  # the standard preset when activity was studied
    found = []
    for title, rows, error_of in (("study's cuts, 0.5 m/s (worst)", stored["rows"], lambda r: r["worst"]),
                                  ("0.6-scale cucumber, 0.05 m/s", stored["slow"]["rows"], lambda r: r["errors"]),
                                  ("whole cucumber, 0.05 m/s", stored["whole"]["rows"], lambda r: r["errors"])):
        by_key = {r["key"]: r for r in rows}
        base = by_key[without.key]
        for radius in ACTIVITY_RADII_MM:
            r = by_key[Setting(4, 8, 0.4, 1.0, radius).key]
            found.append({"cut": title, "radius_mm": radius, "integrated": r.get("active_particle_fraction", 1.0),
                          "speedup": base["wall_s"] / r["wall_s"], "errors": error_of(r), "without": error_of(base)})
    return found


def _activity_finding(stored: dict) -> str:
    found = _activity_rows(stored)
    slow = [f for f in found if "0.05" in f["cut"]]
    return (f"- **Activity saves little on these cuts**: at 0.05 m/s it integrates "
            f"{100 * min(f['integrated'] for f in slow):.0f}-{100 * max(f['integrated'] for f in slow):.0f} % of the "
            f"particle-substeps and runs {min(f['speedup'] for f in slow):.2f}-{max(f['speedup'] for f in slow):.2f}x "
            "faster than the same setting without it; at 0.5 m/s nothing freezes. Under a knife the whole food moves "
            "a few mm/s, above the 3 mm/s it must stay under to freeze, and what does freeze cannot sag, bend or roll: "
            "on the whole cucumber the peak force error doubles (below).")


def _whole_finding(stored: dict) -> str:
    """The robot's own cut: which settings keep the previous standard's accuracy there, from the stored rows."""
    whole = stored["whole"]
    by_key = {r["key"]: r for r in whole["rows"]}
    previous = by_key[PREVIOUS_STANDARD.key]["errors"]
    misses = []
    for setting in (presets()["standard"], Setting(4, 8, 0.5, 4.0), Setting(4, 8, 0.4, 16.0)):
        r = by_key[setting.key]
        over = worse_than(r["errors"], previous)
        misses.append(f"{r['label']} ({r['speedup']:.1f}x) " + (
            "is as accurate" if not over else "misses it on the " + " and ".join(
                f"{QUANTITY_NAMES[m]} ({_fmt(r['errors'][m], m != 'cut_position_mm')} against "
                f"{_fmt(previous[m], m != 'cut_position_mm')})" for m in over)))
    target = whole["target"]
    return (f"- **On the whole cucumber, cut where the robot cuts it**, the cheapest setting as accurate as the "
            f"previous standard is **{target['label']}** ({target['speedup']:.1f}x): " + "; ".join(misses) + ". "
            "Rerun with other particle seeds (benchmarks/seed_spread.md), mass scaling's peak force stays worse "
            "beyond the seeds' spread, at x4 as at x16.")


def _near_misses(slow: dict, standard_worst: dict) -> list[str]:
    """The settings at the target's speed-up that miss the previous standard's accuracy on one quantity only,
    and whether they stay within the standard preset's worst error over the study's cuts."""
    previous = next(r for r in slow["rows"] if r["key"] == PREVIOUS_STANDARD.key)["errors"]
    misses, within = [], True
    for r in sorted(slow["rows"], key=lambda r: -r["wall_s"]):
        over = worse_than(r["errors"], previous)
        if r["speedup"] >= TARGET_SPEEDUP and len(over) == 1 and r["errors"][over[0]] is not None:
            m = over[0]
            within &= r["errors"][m] <= standard_worst[m]
            misses.append(f"{r['label']} ({r['speedup']:.1f}x): {QUANTITY_NAMES[m]} error "
                          f"{_fmt(r['errors'][m], m != 'cut_position_mm')} against {_fmt(previous[m], m != 'cut_position_mm')}")
    if not misses:
        return []
    return ["", f"At {TARGET_SPEEDUP:g}x or more, these settings miss the previous standard's accuracy on one quantity "
            "only: " + "; ".join(misses) + "." + (" Each of these errors is within the standard preset's worst over "
                                                  f"the study's cuts at {SPEED_M_S:g} m/s." if within else "")]


def _slow_section(slow: dict, standard_worst: dict) -> list[str]:
    """One slow cut's table, its cheapest setting at the previous standard's accuracy, and the near misses."""
    lines = ["| setting | wall s | speed-up | substeps | particles | integrated | pieces | cut position (mm) | "
             "peak force | mean force | force curve L2 | knife speed | final shape (mm) | kinetic / elastic |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(slow["rows"], key=lambda r: -r["wall_s"]):
        e = r["errors"]
        lines.append(f"| {r['label']} | {r['wall_s']:.1f} | {r['speedup']:.1f}x | {r['substeps']} | "
                     f"{r['particles']} | {100 * r.get('active_particle_fraction', 1.0):.0f} % | {r['pieces']} | "
                     f"{_fmt(e['cut_position_mm'], False)} | {_fmt(e['peak_force'])} | {_fmt(e['mean_force'])} | "
                     f"{_fmt(e['force_curve_l2'])} | {_fmt(e['knife_speed'])} | {_fmt(e['final_shape_mm'], False)} | "
                     f"{r['kinetic_to_elastic_energy']:.4f} |")
    target = slow["target"]
    itself = target["key"] == PREVIOUS_STANDARD.key
    return [*lines, "", f"The cheapest setting at least as accurate as the previous standard on this cut (same rule "
            f"as above, levers included): **{target['label']}**"
            + (" itself: no cheaper setting measured here is as accurate on every quantity." if itself else
               f", {target['speedup']:.1f}x less wall time "
               + ("(the 5x target is met)." if target["met"] else f"(short of the {TARGET_SPEEDUP:g}x target).")),
            *_near_misses(slow, standard_worst)]


def markdown(stored: dict) -> str:
    machine = stored["machine"]
    rows = stored["rows"]
    best = stored["cheaper_than_standard"]
    previous = next(r for r in rows if r["key"] == PREVIOUS_STANDARD.key)
    lines = ["# What accuracy costs in time", "",
             "Generated by `bench/accuracy_cost.py` (its cuts take "
             f"{stored['core_s'] / 60:.0f} minutes of one core in all). Each cut is one cc-cut run on one "
             f"thread ({stored['workers']} at a time): the foods' real material presets at scale 0.6, the knife "
             f"descending at {SPEED_M_S:g} m/s (the saw at 0.25 m/s with 5 mm, 10 Hz strokes). The reference is "
             f"the finest affordable run, dx {REFERENCE.dx_mm:g} mm with 8 particles per cell and CFL 0.2 (the "
             "`fine` preset's dx 2 mm would cost about 14x the standard's time per cut and is not run); each "
             "setting's error is its worst over the cuts, its cost the wall time of all of them. Finished runs are "
             "kept between invocations (--runs) and reused, so a setting added later was timed in a later "
             "invocation: its ratio to the others carries the machine's drift between the two (about 10 % either "
             "way here; particles times substeps, in the table, does not drift). The robot episode's 5x "
             "measurement is side by side in one run (benchmarks/wake_margin.md). "
             + stored.get("note", ""), "",
             f"Machine: {machine['cpu_model']}, {machine['cores']} cores, {machine['platform']}; {machine['date']}.",
             "", "Cuts: " + ", ".join(stored["cases"]) + ".", "",
             "![Pareto fronts: worst error against wall time](images/accuracy_pareto.png)", "",
             "## What it says", "",
             *_findings(stored), "",
             "## Every setting", "",
             "| setting | preset | wall s | s per simulated s | particles | substeps | peak MB | cut position (mm) | "
             "pieces off | piece volume | peak force | mean force | force curve L2 | knife speed | final shape (mm) | "
             "kinetic / elastic |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(rows, key=lambda r: r["wall_s"]):
        w = r["worst"]
        lines.append(f"| {r['label']} | {r['preset'] or ''} | {r['wall_s']:.1f} | {r['wall_per_sim_s']:.0f} | "
                     f"{r['particles']} | {r['substeps']} | {r['max_rss_mb']:.0f} | "
                     f"{_fmt(w['cut_position_mm'], False)} | {w['piece_count']} | {_fmt(w['piece_volume'])} | "
                     f"{_fmt(w['peak_force'])} | {_fmt(w['mean_force'])} | {_fmt(w['force_curve_l2'])} | "
                     f"{_fmt(w['knife_speed'])} | {_fmt(w['final_shape_mm'], False)} | "
                     f"{r['kinetic_to_elastic_energy']:.3f} |")
    lines += ["", "*Pieces off*: the most pieces a cut has more or fewer than the reference's. *Kinetic / elastic*: "
              "the food's kinetic over its elastic energy while the blade pushes on it (worst cut); mass scaling "
              "stays quasi-static while it is small. *Knife speed*: the knife's speed as the world would slow it by "
              "the food's quadratic speed resistance (the paper's, sim/mpm/physics/speed_resistance.h) at each 2 ms robot physics step, averaged over the cut. "
              "*Final shape*: the RMS distance between where each particle's material ended and where the reference "
              "carried the material from the same rest point, after the best rigid fit of each piece (Kabsch), so "
              "it measures the pieces' shapes, not how far they slid.", "",
              "## The reference's own error", "",
              "Peak force (5 ms window) at each dx with 8 particles per cell and CFL 0.2, and a Richardson "
              "extrapolation f(h) = f0 + C h^p through the three finest where they are monotone:", "",
              "| cut | peak force by dx (N) | order p | extrapolated (N) | reference's estimated error |",
              "|---|---|---|---|---|"]
    for name, ref in stored["refinement"].items():
        by_dx = ", ".join(f"{dx} mm: {f:.2f}" for dx, f in ref["peak_force_by_dx"].items())
        rich = ref["peak_force"]
        lines.append(f"| {name} | {by_dx} | {_fmt(rich['order'], False)} | {_fmt(rich['extrapolated'], False)} | "
                     f"{_fmt(rich['reference_error'])} |")
    lines += ["", "Where the three finest runs are not monotone there is no asymptotic range to extrapolate from, "
              f"and the last change (dx 3 to {REFERENCE.dx_mm:g} mm) stands for the reference's error.", "",
              "## The standard preset, chosen from the front", "",
              f"The cheapest real-mass setting whose worst errors are at or below the previous standard preset's "
              f"({PREVIOUS_STANDARD.label}) on every quantity (cut position, peak and "
              f"mean force, force curve, knife speed, final shape; differences under {RESOLVED['cut_position_mm']:g} mm or "
              f"{100 * RESOLVED['peak_force']:g} % count as equal, being under what the study resolves) with the same pieces: **{best['label']}**, "
              f"{best['speedup']:.1f}x less wall time over the same cuts "
              f"(previous standard: {previous['wall_s']:.0f} s). Mass scaling and activity are left out of the "
              "presets and of accuracy targets: mass scaling is valid for slow cuts only, and activity's price "
              "depends on the food's length and the knife's speed (at 0.5 m/s it freezes nothing, so its rows above "
              "repeat those of CFL 0.4 without it and differ in wall time only by the machine's noise). The server "
              "carries this page's table (sim/world/measured_accuracy_table.cc, "
              "written by this script through tools/gen_accuracy_table.py): `GetServerInfo` lists each preset with "
              "its expected errors and cost, every "
              "resolved scene says what its setting measured (`expected_accuracy`), and a scene may ask for an "
              "accuracy target instead of a preset (`quality: {force_error: 0.1}` from Python, "
              "`SceneSpec.accuracy_target`) to get the cheapest real-mass setting without activity here that meets it.", "",
              "## The guard in the tests", "",
              f"The test suite (ctest `accuracy_guard`, `bench/accuracy_cost.py --check`) cuts the {GUARD_CASE} cut "
              "at each preset and fails when an error against this study's reference exceeds its bound (1.5x what "
              "the study measured, with a little absolute slack):", "",
              "| preset | " + " | ".join(GUARD_METRICS) + " |", "|---|" + "---|" * len(GUARD_METRICS)]
    for preset, bounds in stored["guard_bounds"].items():
        lines.append(f"| {preset} | " + " | ".join(
            (f"{bounds[m]:.2f} mm" if m == "cut_position_mm" else f"{100 * bounds[m]:.1f} %") if m in bounds else "-"
            for m in GUARD_METRICS) + " |")
    standard_worst = next(r for r in rows if r["key"] == presets()["standard"].key)["worst"]
    lines += ["", "## Activity: freezing the food far from the knife", "",
              "At dx 4 mm, 8 ppc, CFL 0.4 (the standard preset when activity was studied), each radius against "
              "the same setting without activity, in this run. At 0.5 m/s nothing freezes: the work is the same, "
              "and the speed-up is the machine's noise.", "",
              "| cut | radius | integrated | speed-up | peak force error (without) | mean force error (without) | "
              "force curve L2 (without) |", "|---|---|---|---|---|---|---|"]
    for f in _activity_rows(stored):
        e, b = f["errors"], f["without"]
        lines.append(f"| {f['cut']} | {f['radius_mm']:g} mm | {100 * f['integrated']:.0f} % | {f['speedup']:.2f}x | "
                     f"{_fmt(e['peak_force'])} ({_fmt(b['peak_force'])}) | {_fmt(e['mean_force'])} "
                     f"({_fmt(b['mean_force'])}) | {_fmt(e['force_curve_l2'])} ({_fmt(b['force_curve_l2'])}) |")
    lines += ["",
              "## At the robot's cutting speed: the 5x target", "",
              "The planner's knife moves through food at 0.02-0.05 m/s. The cucumber cut at 0.05 m/s, each setting "
              f"against this slow cut's own reference (dx {REFERENCE.dx_mm:g} mm, 8 ppc, CFL 0.2, real mass), all "
              "run in this study; speed-up over the previous standard preset:", "",
              *_slow_section(stored["slow"], standard_worst), "",
              "### The whole cucumber, cut where the robot cuts it", "",
              "The robot episode's cut (examples/cut_cucumber.py): the whole cucumber (scale 1, 20 cm), 0.3 of its "
              "length from one end, at 0.05 m/s, against its own reference at the same resolution; the levers "
              "that reached the target's neighbourhood above:", "",
              *_slow_section(stored["whole"], standard_worst),
              "", "Every run here samples the food's particles from seed 0. How far the errors move with the seed alone, "
              "and whether the settings above differ by more than that, is measured in "
              "[benchmarks/seed_spread.md](benchmarks/seed_spread.md).",
              "", "The same settings on a whole robot episode (the example cut through the server, three cameras) "
              "are timed side by side in [benchmarks/cut_episode.md](benchmarks/cut_episode.md). A robot episode "
              "also integrates the food from when the knife comes near it; waking it only when the knife can reach "
              "its grid, and today's standard episode against the episode the 5x target was set against (the "
              "previous standard, woken 2 cm out), side by side: "
              "[benchmarks/wake_margin.md](benchmarks/wake_margin.md).",
              "", "`SceneSpec.mpm.mass_scaling` sets mass scaling for a session (docs/world.md): the food's inertia "
              "times s, its weight real (gravity acts on the scaled mass as g / s), the MPM substep sqrt(s) longer. "
              "It is valid while the kinetic / elastic column stays small; cc-cut reports it as "
              "`summary.kinetic_to_elastic_energy`.", "",
              "`SceneSpec.mpm.activity_radius` sets activity (docs/world.md): food farther than the radius (at least "
              "5 cells) from the knife that has stayed below 3 mm/s for four checks freezes, its mass and stress a "
              "fixed load on the grid, until the knife comes within the radius or moving food pushes a node it "
              "shares past 1 cm/s. *Integrated* is the share of particle-substeps it still integrates; frozen food "
              "cannot sag, bend or roll, which is its price.", ""]
    return "\n".join(lines) + "\n"


def main() -> int:
    parser = arguments(__doc__, render_only=True)
    parser.add_argument("--cc-cut", type=Path, default=cc_cut())
    parser.add_argument("--workers", type=int, default=2, help="cc-cut runs at a time (one thread each)")
    parser.add_argument("--runs", type=Path, default=Path(tempfile.gettempdir()) / "culinarycut-accuracy-runs",
                        help="finished runs are kept here; a rerun reuses them")
    parser.add_argument("--note", default="", help="a sentence for the page (e.g. what else ran on the machine)")
    parser.add_argument("--check", action="store_true", help="the test suite's guard (see above)")
    parser.add_argument("--table", type=Path, default=None,
                        help=f"where the engine's table goes (default {TABLE_CC.relative_to(TABLE_CC.parents[2])}; "
                             "with --docs, that folder)")
    args = parser.parse_args()
    docs = docs_for(args)
    if args.check:
        return check(args.cc_cut)
    table = args.table or (TABLE_CC if docs.is_checkout else docs.path("measured_accuracy_table.cc"))
    if args.quick:
        # The smoke pass: the guard's cut at the draft preset against the stored reference, then the page, plot
        # and table from the stored study, and the table must be the committed one.
        if code := missing(args.cc_cut, "--cc-cut"):
            return code
        failed = check(args.cc_cut, ["draft"])
        stored = docs.stored(RESULTS)
        write_outputs(docs, stored, table)
        if table.read_text() != TABLE_CC.read_text():
            print(f"error: {TABLE_CC} is not what {RESULTS} gives: run tools/gen_accuracy_table.py", file=sys.stderr)
            return 1
        return failed
    if not args.render_only:
        if code := missing(args.cc_cut, "--cc-cut"):
            return code
        results, slow = run_all(args.cc_cut, args.runs, args.workers)
        core_s = sum(r["wall_s"] for runs in (*results.values(), *slow.values()) for r in runs.values())
        stored = {"machine": dated_machine_info(), "workers": args.workers,
                  "core_s": core_s, "cases": list(results), "reference": REFERENCE.key,
                  "note": args.note, **study(results), "slow": slow_study(slow[SLOW_CASE], SLOW_GRID),
                  "whole": slow_study(slow[WHOLE_CASE], WHOLE_GRID),
                  "references": {name: reference_record(runs[REFERENCE.key]) for name, runs in results.items()}}
        stored["guard_bounds"] = guard_bounds(stored["rows"])
        docs.write_json(RESULTS, stored, __file__, indent=1)
    stored = docs.stored(RESULTS)
    if relabel_presets(stored):  # the engine's presets changed since the run (a preset re-chosen from its front)
        docs.write_json(RESULTS, stored, __file__, indent=1)
    write_outputs(docs, stored, table)
    print(f"wrote {docs.path(PAGE)} (standard-level accuracy {stored['cheaper_than_standard']['speedup']:.1f}x "
          f"cheaper with {stored['cheaper_than_standard']['label']})")
    return 0


def relabel_presets(stored: dict) -> bool:
    """Names each row's preset as the engine's presets are now and bounds the guard at them; True when anything changed."""
    before = json.dumps([stored["guard_bounds"], [r["preset"] for r in stored["rows"]]])
    for row in stored["rows"]:
        row["preset"] = next((name for name, preset in presets().items() if preset.key == row["key"]), None)
    stored["guard_bounds"] = guard_bounds(stored["rows"])
    return json.dumps([stored["guard_bounds"], [r["preset"] for r in stored["rows"]]]) != before


def write_outputs(docs, stored: dict, table: Path) -> None:
    """The engine's table, the Pareto plot and the page, all from the stored study."""
    table.write_text(cxx_table(stored))
    plot(stored, docs.image("accuracy_pareto.png"))
    docs.write_page(PAGE, markdown(stored), __file__, RESULTS, stored)


if __name__ == "__main__":
    sys.exit(main())

"""The report's charts as PNG bytes (matplotlib, headless): success per food, success per ratio (radar,
one panel per side) and knife force over time, one colour per run."""
from __future__ import annotations

import io
import math
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the headless backend)

from culinarycut.bench.tables import success_by  # noqa: E402

COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b")
RADAR_MIN_RATIOS = 3  # fewer spokes make no radar


def _png(figure) -> bytes:
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=110, bbox_inches="tight")
    plt.close(figure)
    return buffer.getvalue()


def success_per_food(runs: list[tuple[str, list[dict]]]) -> bytes:
    """Grouped bars: success rate per food, one bar per run, with 95 % Wilson intervals."""
    return success_per(runs, "food", "Success per food (95 % Wilson intervals)")


def success_per(runs: list[tuple[str, list[dict]]], key: str, title: str, sort_values: bool = True) -> bytes:
    """Grouped bars: success rate per value of the rows' column `key`, one bar per run, with 95 % Wilson
    intervals (values sorted, or in first-seen order)."""
    values = list(dict.fromkeys(str(row[key]) for _, rows in runs for row in rows))
    values = sorted(values) if sort_values else values
    figure, axes = plt.subplots(figsize=(min(12.0, max(5.0, 1.1 * len(values) * max(1, len(runs)))), 3.6))
    width = 0.8 / len(runs)
    for i, (label, rows) in enumerate(runs):
        by_value = {r.key: r for r in success_by(rows, key)}
        xs, rates, low, high = [], [], [], []
        for j, value in enumerate(values):
            if value not in by_value:
                continue
            rate = by_value[value]
            lo, hi = rate.interval
            xs.append(j + (i - (len(runs) - 1) / 2) * width)
            rates.append(100 * rate.rate)
            # Clamped: at 100 % (e.g. 60/60) rounding puts the Wilson bound a hair under the rate.
            low.append(max(0.0, 100 * (rate.rate - lo)))
            high.append(max(0.0, 100 * (hi - rate.rate)))
        axes.bar(xs, rates, width, yerr=[low, high], capsize=3, label=label, color=COLOURS[i % len(COLOURS)])
    axes.set_xticks(range(len(values)), values, fontsize=8 if len(values) > 5 else None)
    axes.set_ylabel("success (%)")
    axes.set_ylim(0, 105)
    axes.set_title(title)
    axes.legend(fontsize=8, loc="best")
    axes.grid(axis="y", alpha=0.3)
    return _png(figure)


SURFACE_ANGLE = "angle_error_deg"        # the cut surface's plane against the target plane
BLADE_ANGLE = "blade_angle_error_deg"    # the blade's plane in the food against the target plane
ANGLE_LABELS = {SURFACE_ANGLE: "angle between the cut surface and the target plane (deg)",
                BLADE_ANGLE: "angle between the blade in the food and the target plane (deg)"}


def angle_errors(rows: list[dict], key: str = SURFACE_ANGLE) -> list[float]:
    """One measured angle error (deg) of every required cut of the rows (cuts where it was not measured left out)."""
    import json
    return [cut[key] for row in rows for cut in json.loads(row.get("cuts") or "[]") if cut.get(key) is not None]


def angle_error_histogram(runs: list[tuple[str, list[dict]]], tolerance_deg: float, key: str = SURFACE_ANGLE) -> bytes:
    """Each run's distribution of one of the cuts' angle errors, with the success rule's tolerance marked."""
    figure, axes = plt.subplots(figsize=(6.0, 3.2))
    largest = max([tolerance_deg * 2] + [e for _, rows in runs for e in angle_errors(rows, key)])
    bins = [largest * k / 30 for k in range(31)]
    for i, (label, rows) in enumerate(runs):
        axes.hist(angle_errors(rows, key), bins=bins, histtype="step", linewidth=1.5, label=label,
                  color=COLOURS[i % len(COLOURS)])
    axes.axvline(tolerance_deg, color="black", linestyle="--", linewidth=1)
    axes.text(tolerance_deg, axes.get_ylim()[1] * 0.5, f"tolerance {tolerance_deg:g} deg ", fontsize=8, rotation=90,
              ha="right", va="center")
    axes.set_xlabel(ANGLE_LABELS[key])
    axes.set_ylabel("cuts")
    axes.set_title("Cut orientation")
    axes.legend(fontsize=8)
    return _png(figure)


def _ratio_rows(runs: list[tuple[str, list[dict]]], food: str) -> list[list[dict]]:
    return [[r for r in rows if r["state"] == "ratio" and r["food"] == food] for _, rows in runs]


def radar_sides(runs: list[tuple[str, list[dict]]], food: str) -> list[str]:
    """The sides (left, right) whose ratio cuts on `food` have enough distinct ratios for a radar."""
    chosen = [r for rows in _ratio_rows(runs, food) for r in rows]
    sides = sorted({r["side"] for r in chosen})
    return [side for side in sides if len({r["ratio"] for r in chosen if r["side"] == side}) >= RADAR_MIN_RATIOS]


def ratio_radar(runs: list[tuple[str, list[dict]]], food: str) -> bytes:
    """Success per cut ratio on one food as the paper's radar charts: one panel per side the ratio is
    measured from (left, right), since 0.3 from the left and 0.3 from the right are different cuts."""
    chosen = _ratio_rows(runs, food)
    sides = radar_sides(runs, food)
    figure = plt.figure(figsize=(4.2 * len(sides), 4.2))
    for panel, side in enumerate(sides, start=1):
        ratios = sorted({r["ratio"] for rows in chosen for r in rows if r["side"] == side})
        angles = [2 * math.pi * i / len(ratios) for i in range(len(ratios))]
        axes = figure.add_subplot(1, len(sides), panel, projection="polar")
        for i, ((label, _), rows) in enumerate(zip(runs, chosen)):
            by_ratio = {r.key: r.rate for r in success_by([r for r in rows if r["side"] == side],
                                                          lambda row: f"{row['ratio']:g}")}
            values = [100 * by_ratio.get(f"{ratio:g}", 0.0) for ratio in ratios]
            colour = COLOURS[i % len(COLOURS)]
            axes.plot(angles + angles[:1], values + values[:1], color=colour, label=label)
            axes.fill(angles + angles[:1], values + values[:1], color=colour, alpha=0.15)
        axes.set_xticks(angles, [f"{r:g}" for r in ratios])
        axes.set_ylim(0, 100)
        axes.set_title(f"{food}, from the {side}: success (%) per ratio", pad=14, fontsize=10)
        if panel == 1:
            axes.legend(fontsize=7, loc="lower left", bbox_to_anchor=(-0.15, -0.15))
    return _png(figure)


def force_overlays(runs: list[tuple[str, dict[str, list[dict]]]], tasks: list[str]) -> bytes:
    """Knife force at the wrist over time, every trial of each task as a thin line, one colour per run."""
    columns = min(3, len(tasks))
    rows_count = math.ceil(len(tasks) / columns)
    figure, axes = plt.subplots(rows_count, columns, figsize=(4.2 * columns, 2.6 * rows_count), squeeze=False)
    for index, task in enumerate(tasks):
        axis = axes[index // columns][index % columns]
        for i, (label, traces_of_task) in enumerate(runs):
            for k, trace in enumerate(traces_of_task.get(task, [])):
                axis.plot(trace["time_s"], trace["force_n"], color=COLOURS[i % len(COLOURS)], lw=0.8, alpha=0.6,
                          label=label if k == 0 else None)
        axis.set_title(task, fontsize=8)
        axis.set_xlabel("time (s)", fontsize=8)
        axis.set_ylabel("force (N)", fontsize=8)
        axis.tick_params(labelsize=7)
        axis.grid(alpha=0.3)
    for index in range(len(tasks), rows_count * columns):
        axes[index // columns][index % columns].axis("off")
    handles, labels = axes[0][0].get_legend_handles_labels()
    figure.tight_layout()
    if handles:
        figure.legend(handles, labels, fontsize=8, loc="upper center", ncol=len(handles), bbox_to_anchor=(0.5, 0.0))
    return _png(figure)


def traces_by_task(traces: list[tuple[str, dict]]) -> dict[str, list[dict]]:
    grouped: dict[str, list[dict]] = defaultdict(list)
    for task, trace in traces:
        grouped[task].append(trace)
    return grouped

"""The paper's safety-ablation figure for one task and trial: the knife's travel along its cutting direction
(top) and the contact force (bottom) over time, limiter off against each limiter-on setting; spans where the
limiter-off force is above 60 N shaded red, each setting's F_max as a dashed line."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the headless backend)

from culinarycut.bench.report_charts import COLOURS, _png  # noqa: E402
from culinarycut.bench.safety_tables import base_task, setting_key, setting_label  # noqa: E402

HIGH_FORCE_N = 60.0  # the paper's threshold for the red spans


def figure_task(rows: list[dict]) -> str:
    """The task (without its limiter suffix) whose limiter-off episodes pushed hardest: the figure's case."""
    off = [r for r in rows if not r.get("safety_limiter") and r["peak_knife_force_n"] is not None]
    chosen = max(off or rows, key=lambda r: r["peak_knife_force_n"] or 0.0)
    return base_task(chosen["task"])


def figure_cases(rows: list[dict], traces: list[dict], task: str) -> list[tuple[tuple, dict, dict]]:
    """(setting, row, trace) of the first trial every setting of `task` ran: the same scene in each."""
    chosen = [(r, t) for r, t in zip(rows, traces) if base_task(r["task"]) == task and t.get("time_s")]
    by_setting: dict[tuple, dict[int, tuple]] = {}
    for row, trace in chosen:
        by_setting.setdefault(setting_key(row), {})[row["trial"]] = (row, trace)
    common = set.intersection(*(set(trials) for trials in by_setting.values())) if by_setting else set()
    if not common:
        return []
    trial = min(common)
    return [(key, *by_setting[key][trial]) for key in sorted(by_setting, key=lambda k: (k[0], -k[1], k[2]))]


def _spans_above(times: list[float], forces: list[float], threshold: float) -> list[tuple[float, float]]:
    """Time spans (one control step wide each, merged) in which the force is above threshold."""
    spans: list[tuple[float, float]] = []
    for k, (time_s, force) in enumerate(zip(times, forces)):
        if force <= threshold:
            continue
        start = times[k - 1] if k > 0 else time_s
        if spans and spans[-1][1] >= start:
            spans[-1] = (spans[-1][0], time_s)
        else:
            spans.append((start, time_s))
    return spans


def ablation_figure(cases: list[tuple[tuple, dict, dict]], title: str) -> bytes:
    figure, (travel_axis, force_axis) = plt.subplots(2, 1, figsize=(8.0, 5.6), sharex=True)
    for i, (key, row, trace) in enumerate(cases):
        colour = COLOURS[i % len(COLOURS)]
        label = f"{setting_label(key)} ({row['outcome']})"
        start = trace["tcp_along_cut_m"][0] if trace.get("tcp_along_cut_m") else 0.0
        width = 1.4 if key[0] else 3.5  # the off case wide underneath: a setting that changes nothing lies on it
        travel_axis.plot(trace["time_s"], [100 * (v - start) for v in trace.get("tcp_along_cut_m", [])],
                         color=colour, lw=width, alpha=1.0 if key[0] else 0.45, label=label)
        force_axis.plot(trace["time_s"], trace["force_n"], color=colour, lw=width, alpha=1.0 if key[0] else 0.45,
                        label=label)
        if key[0]:
            force_axis.axhline(key[1], color=colour, ls="--", lw=0.9)
        else:
            for begin, end in _spans_above(trace["time_s"], trace["force_n"], HIGH_FORCE_N):
                for axis in (travel_axis, force_axis):
                    axis.axvspan(begin, end, color="red", alpha=0.2, lw=0)
    force_axis.axhline(HIGH_FORCE_N, color="red", ls=":", lw=0.9, label=f"{HIGH_FORCE_N:g} N")
    travel_axis.set_ylabel("knife travel along\nthe cut direction (cm)")
    force_axis.set_ylabel("contact force at the wrist (N)")
    force_axis.set_xlabel("time (s)")
    travel_axis.set_title(title, fontsize=10)
    for axis in (travel_axis, force_axis):
        axis.grid(alpha=0.3)
    force_axis.legend(fontsize=7, loc="upper left")
    figure.tight_layout()
    return _png(figure)

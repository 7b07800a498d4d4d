"""The safety ablation's tables from stored rows: per limiter setting (off, on at each F_max and guard set) the
means over trials of the maximum cutting speed and force, the success rate and the limiter's interventions,
with the paper's numbers beside ours."""
from __future__ import annotations

import json
import re
import statistics
from collections import defaultdict

from culinarycut.bench.suite import ALL_GUARDS
from culinarycut.bench.tables import success_by

PAPER_F_MAX_N = 100.0
# The paper's "Ablation Study of Safety module" table (20 trials, its aggressive policy): labelled as the paper's.
PAPER_WITHOUT = {"speed_m_s": 3.63, "force_n": 129.31}
PAPER_WITH = {"speed_m_s": 0.89, "force_n": 37.78}
LIMITER_SUFFIX = re.compile(r"/limiter-[^/]+$")


def is_ablation(rows: list[dict]) -> bool:
    """Rows with the limiter on and rows with it off (a run from before the column has neither)."""
    return {row.get("safety_limiter") for row in rows} >= {0, 1}


def setting_key(row: dict) -> tuple:
    """Off, or on with its F_max and guards: what one line of the table stands for."""
    if not row.get("safety_limiter"):
        return (0, 0.0, ())
    settings = json.loads(row["safety_settings"] or "{}")
    return (1, float(row["safety_max_force_n"]), tuple(sorted(settings.get("guards", ALL_GUARDS))))


def setting_label(key: tuple) -> str:
    on, f_max, guards = key
    if not on:
        return "limiter off"
    label = f"limiter on, F_max {f_max:g} N"
    return label if set(guards) == set(ALL_GUARDS) else f"{label}, guards {' + '.join(guards)}"


def base_task(task: str) -> str:
    """The task without its limiter suffix: the rows of every setting of one task and trial share a scene."""
    return LIMITER_SUFFIX.sub("", task)


def _mean(values: list) -> float | None:
    values = [v for v in values if v is not None]
    return statistics.fmean(values) if values else None


def _cell(value: float | None, digits: int = 2) -> str:
    return "-" if value is None else f"{value:.{digits}f}"


def setting_summary(rows: list[dict]) -> list[dict]:
    """Per setting, in the order off, then on by falling F_max: means over its episodes."""
    groups: dict[tuple, list[dict]] = defaultdict(list)
    for row in rows:
        groups[setting_key(row)].append(row)
    summary = []
    for key in sorted(groups, key=lambda k: (k[0], -k[1], len(k[2]) < len(ALL_GUARDS))):
        chosen = groups[key]
        rate = success_by(chosen, lambda _: "all")[0]
        summary.append({
            "key": key, "label": setting_label(key), "episodes": len(chosen), "successes": rate.successes,
            "cutting_speed_m_s": _mean([r["peak_cutting_speed_m_s"] for r in chosen]),
            "tcp_speed_m_s": _mean([r["peak_speed_m_s"] for r in chosen]),
            "commanded_speed_m_s": _mean([r["peak_commanded_speed_m_s"] for r in chosen]),
            "force_n": _mean([r["peak_knife_force_n"] for r in chosen]),
            "max_force_n": max((r["peak_knife_force_n"] or 0.0 for r in chosen), default=0.0),
            "acted_steps": _mean([r["safety_acted_steps"] for r in chosen]) if key[0] else None,
            "interventions": {g: sum(r[f"interventions_{g}"] or 0 for r in chosen) for g in ALL_GUARDS}
            if key[0] else None,
        })
    return summary


def _paper(key: tuple) -> dict | None:
    """The paper's row for a setting it ran: off, or on at its F_max with every guard."""
    if not key[0]:
        return PAPER_WITHOUT
    if key[1] == PAPER_F_MAX_N and set(key[2]) == set(ALL_GUARDS):
        return PAPER_WITH
    return None


SETTINGS_HEADER = ["setting", "episodes", "max cutting speed (m/s)", "paper (m/s)", "max force (N)", "paper (N)",
                   "success", "peak TCP speed (m/s)", "commanded into the food (m/s)", "limiter acted (steps)",
                   "interventions speed / force / entry angle"]


def settings_table(rows: list[dict]) -> tuple[list[str], list[list[str]]]:
    """The paper's table with ours beside it: means over the trials of each setting."""
    table = []
    for s in setting_summary(rows):
        paper = _paper(s["key"]) or {}
        interventions = s["interventions"]
        table.append([s["label"], str(s["episodes"]), _cell(s["cutting_speed_m_s"]),
                      _cell(paper.get("speed_m_s")), _cell(s["force_n"]), _cell(paper.get("force_n")),
                      f"{s['successes']}/{s['episodes']} ({100 * s['successes'] / s['episodes']:.0f} %)",
                      _cell(s["tcp_speed_m_s"]), _cell(s["commanded_speed_m_s"]), _cell(s["acted_steps"], 1),
                      " / ".join(str(interventions[g]) for g in ALL_GUARDS) if interventions else "-"])
    return SETTINGS_HEADER, table


def food_table(rows: list[dict]) -> tuple[list[str], list[list[str]]]:
    """The same means per food and setting (the foods' forces differ by an order of magnitude)."""
    header = ["food", "setting", "episodes", "max cutting speed (m/s)", "max force (N)", "success"]
    table = []
    for food in sorted({r["food"] for r in rows}):
        for s in setting_summary([r for r in rows if r["food"] == food]):
            table.append([food, s["label"], str(s["episodes"]), _cell(s["cutting_speed_m_s"]), _cell(s["force_n"]),
                          f"{s['successes']}/{s['episodes']}"])
    return header, table

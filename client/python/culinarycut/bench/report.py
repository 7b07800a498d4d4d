"""`culinarycut bench report`: one stored run, or several side by side, as Markdown (report.md) and an HTML
page (report.html: charts inlined), beside report_files/ (the PNGs and the failure videos).

The report is built once as a list of blocks (headings, text, tables, images, videos) and written in
both forms, so the two always say the same. The page shows each failure video as a thumbnail linked to
its file, so it stays small however many tasks fail. Runs side by side are named by letters (A, B, ...)
in the tables and charts; the first table says which run each letter is.
"""
from __future__ import annotations

import base64
import html
import json
import statistics
from dataclasses import dataclass
from pathlib import Path

from culinarycut.bench import report_charts, report_media, safety_figure, safety_tables
from culinarycut.bench.storage_faults import storage_faults
from culinarycut.bench.store import DATABASE_NAME, ResultStore
from culinarycut.bench.tables import markdown_table, rate_cells, split_partial, success_by

AGAIN = "run the report again"  # what a storage fault's message ends with
FORCE_PANELS_PER_FIGURE = 12  # force-time panels per image: every task is drawn, a dozen per figure
ANGLE_TOLERANCE_DEG = 9.0  # the success rule's angle tolerance (sim/task/success_metrics.h)


class ReportError(ValueError):
    pass


@dataclass
class Run:
    label: str             # policy @ server version (build); with the folder's name where two would be equal
    folder: Path
    metadata: dict
    rows: list[dict]
    traces: list[tuple[str, dict]]
    short: str = ""        # A, B, ... where several runs stand side by side; the label alone otherwise
    shown_folder: str = ""  # how the report names the folder (its path unless told)

    @property
    def title(self) -> str:
        """The letter and the label, where the run has a letter."""
        return self.label if self.short == self.label else f"{self.short}: {self.label}"


@dataclass
class Block:
    kind: str              # heading, text, table, image, video
    text: str = ""
    header: list | None = None
    rows: list | None = None
    data: bytes = b""
    name: str = ""         # image / video file name


def load_run(folder: Path) -> Run:
    if not (folder / DATABASE_NAME).is_file():
        raise ReportError(f"{folder} holds no run ({DATABASE_NAME} is missing); give the --out folder of bench run")
    with storage_faults(folder / DATABASE_NAME, AGAIN), ResultStore(folder) as store:
        rows = store.episodes()
        traces = [(row["task"], store.trace(row["task"], row["trial"]) or {"time_s": [], "force_n": []})
                  for row in rows]
        metadata = store.metadata()
    if not rows:
        raise ReportError(f"{folder} holds no episodes yet")
    # A server_error before the server said its version leaves the row without one: it names no build.
    versions = sorted({f"{r['server_version']} ({r['build_id'] or '?'}{', ' + r['simd'] if r.get('simd') else ''})"
                       for r in rows if r["server_version"]})
    label = f"{metadata.get('policy', rows[0]['policy'])} @ {', '.join(versions) or 'unknown server'}"
    return Run(label, folder, metadata, rows, traces)


def _name_runs(runs: list[Run]) -> None:
    """Distinct labels, and a letter for each run where several are compared (table headers stay short)."""
    labels = [r.label for r in runs]
    for index, run in enumerate(runs):
        if labels.count(run.label) > 1:
            run.label = f"{run.label} [{run.folder.name}]"
        run.short = chr(ord("A") + index) if len(runs) > 1 else run.label


def _cell(rows: list[dict], key) -> dict[str, list[str]]:
    return {r.key: rate_cells(r)[1:4] for r in success_by(rows, key)}


def _comparison(runs: list[Run], key, title: str, first_column: str) -> list[Block]:
    """One table: a row per value of `key`, success / rate / interval for each run side by side."""
    cells = [_cell(run.rows, key) for run in runs]
    keys = list(dict.fromkeys(k for c in cells for k in c))
    header = [first_column] + [f"{run.short} {name}" if len(runs) > 1 else name
                               for run in runs for name in ("success", "rate", "95 % CI")]
    rows = [[k] + [v for c in cells for v in c.get(k, ["-", "-", "-"])] for k in keys]
    return [Block("heading", title), Block("table", header=header, rows=rows)]


def _split_blocks(runs: list[Run]) -> list[Block]:
    blocks = [Block("heading", "Split cuts: partial success"),
              Block("text", "Share of episodes in which exactly k of the required cuts lie within the position "
                            "tolerance (the paper's partial-success table; full success needs all of them).")]
    for run in runs:
        table = split_partial(run.rows)
        if not table:
            continue
        most = max(int(t["split"].split("/")[1]) for t in table)
        header = ["food", "split", "episodes"] + [f"k = {k}" for k in range(most)]
        rows = [[t["food"], t["split"], str(t["episodes"])] +
                [f"{100 * t['share_with_k'][k]:.0f} %" if k in t["share_with_k"] else "" for k in range(most)]
                for t in table]
        if len(runs) > 1:
            blocks.append(Block("text", run.title))
        blocks.append(Block("table", header=header, rows=rows))
    return blocks


def _topology_blocks(runs: list[Run]) -> list[Block]:
    def base_task(row):
        return row["task"].replace("/topology-off", "")
    blocks = [Block("heading", "Topology updates on and off")]
    for run in runs:
        on = _cell([r for r in run.rows if r["topology"]], base_task)
        off = _cell([r for r in run.rows if not r["topology"]], base_task)
        keys = list(dict.fromkeys(list(on) + list(off)))
        rows = [[k] + on.get(k, ["-"] * 3)[:2] + off.get(k, ["-"] * 3)[:2] for k in keys]
        if len(runs) > 1:
            blocks.append(Block("text", run.title))
        blocks.append(Block("table", header=["task", "on: success", "on: rate", "off: success", "off: rate"],
                            rows=rows))
    return blocks


def _safety_blocks(runs: list[Run]) -> list[Block]:
    """The paper's safety ablation: its table (ours beside the paper's) and its figure, for each run that holds
    episodes with the limiter on and off."""
    blocks = [Block("heading", "Safety limiter: on against off"),
              Block("text", "Means over the trials of each setting. Max cutting speed: the knife's peak speed along "
                            "its cutting direction while in the food; max force: the peak food force on the knife "
                            "over every physics step (the server's session totals). The paper's numbers (its "
                            "aggressive policy, 20 trials, F_max 100 N) stand beside ours where it ran the setting.")]
    for index, run in enumerate(runs):
        if not safety_tables.is_ablation(run.rows):
            continue
        if len(runs) > 1:
            blocks.append(Block("text", run.title))
        header, rows = safety_tables.settings_table(run.rows)
        blocks.append(Block("table", header=header, rows=rows))
        header, rows = safety_tables.food_table(run.rows)
        blocks.append(Block("table", header=header, rows=rows))
        task = safety_figure.figure_task(run.rows)
        cases = safety_figure.figure_cases(run.rows, [trace for _, trace in run.traces], task)
        if cases:
            trial = cases[0][1]["trial"]
            caption = (f"{task}, trial {trial}: knife travel and contact force, limiter off and on (red: spans "
                       f"above {safety_figure.HIGH_FORCE_N:g} N with it off; dashed: each setting's F_max)")
            blocks.append(Block("image", caption, data=safety_figure.ablation_figure(cases, f"{task}, trial {trial}"),
                                name=f"safety_ablation{'_' + str(index) if index else ''}.png"))
    return blocks


def _failure_blocks(runs: list[Run]) -> list[Block]:
    blocks = [Block("heading", "First failure of each task")]
    for run in runs:
        first: dict[str, dict] = {}
        for row in run.rows:  # ordered by task, trial
            if row["outcome"] != "success" and row["task"] not in first:
                first[row["task"]] = row
        if not first:
            blocks.append(Block("text", f"{run.title}: no failures."))
            continue
        rows = [[r["task"], str(r["trial"]), r["end_reason"], r["instruction"],
                 (r["error"] or r["score_summary"] or "")[:160]] for r in first.values()]
        blocks.append(Block("text", run.title))
        blocks.append(Block("table", header=["task", "trial", "ended by", "instruction", "what happened"], rows=rows))
        # Runs side by side film the same tasks: each run's files get its letter.
        prefix = f"{run.short}_" if len(runs) > 1 else ""
        for row in first.values():
            if row["video"] and (run.folder / row["video"]).is_file():
                blocks.append(Block("video", f"{row['task']}, trial {row['trial']}",
                                    data=(run.folder / row["video"]).read_bytes(),
                                    name=prefix + Path(row["video"]).name))
    return blocks


def _cut_quality_blocks(runs: list[Run]) -> list[Block]:
    """Per run and style: how far the cut surfaces and the blade were from the target plane and the cuts from
    their place, and the style's signature in the knife's motion; then every run's angle-error distributions."""
    def median(values):
        return statistics.median(values) if values else None

    def number(value, digits=1):
        return "-" if value is None else f"{value:.{digits}f}"

    rows = []
    for run in runs:
        for style in sorted({r["style"] for r in run.rows}):
            chosen = [r for r in run.rows if r["style"] == style]
            angles = sorted(report_charts.angle_errors(chosen))
            blade_angles = report_charts.angle_errors(chosen, report_charts.BLADE_ANGLE)
            positions = [c["position_error_fraction"] for r in chosen for c in json.loads(r.get("cuts") or "[]")
                         if c.get("placed")]
            p95 = angles[min(len(angles) - 1, int(0.95 * len(angles)))] if angles else None
            rows.append([run.short, style, str(len(angles)), number(median(angles)), number(p95),
                         number(angles[-1] if angles else None), number(median(blade_angles)),
                         number(max(blade_angles) if blade_angles else None),
                         number(100 * max(positions) if positions else None),
                         number(median([r["saw_strokes"] for r in chosen if r.get("saw_strokes") is not None]), 0),
                         number(median([r["pivot_deg"] for r in chosen if r.get("pivot_deg") is not None]))])
    header = ["run", "style", "cuts with a plane", "surface angle error median (deg)", "p95", "max",
              "blade angle error median (deg)", "max", "position error max (% of length)", "saw strokes (median)",
              "pivot (deg, median)"]
    if len(runs) == 1:
        header, rows = header[1:], [row[1:] for row in rows]
    blocks = [Block("heading", "Cut placement and orientation"),
              Block("text", f"A cut is correct within 10 % of the length of its target and {ANGLE_TOLERANCE_DEG:g} deg "
                            "of the target plane, both for the plane of the cut surface the blade left and for the "
                            "blade's mean plane while its edge passed the food. Saw strokes and pivot are the style's "
                            "signature in the knife's motion while in the food."),
              Block("table", header=header, rows=rows)]
    for key, title, name in ((report_charts.SURFACE_ANGLE, "Angle between the cut surface and the target plane",
                              "cut_orientation.png"),
                             (report_charts.BLADE_ANGLE, "Angle between the blade in the food and the target plane",
                              "blade_orientation.png")):
        if any(report_charts.angle_errors(run.rows, key) for run in runs):
            blocks.append(Block("image", title, name=name,
                                data=report_charts.angle_error_histogram([(run.short, run.rows) for run in runs],
                                                                         ANGLE_TOLERANCE_DEG, key)))
    return blocks


def _force_blocks(runs: list[Run]) -> list[Block]:
    """Knife force over time for every task, FORCE_PANELS_PER_FIGURE tasks to a figure."""
    tasks = list(dict.fromkeys(r["task"] for run in runs for r in run.rows))
    traces = [(run.short, report_charts.traces_by_task(run.traces)) for run in runs]
    blocks = [Block("heading", "Knife force over time")]
    for page, first in enumerate(range(0, len(tasks), FORCE_PANELS_PER_FIGURE)):
        chosen = tasks[first:first + FORCE_PANELS_PER_FIGURE]
        caption = "Force at the wrist, every trial"
        if len(tasks) > FORCE_PANELS_PER_FIGURE:
            caption += f": tasks {first + 1}-{first + len(chosen)} of {len(tasks)}"
        blocks.append(Block("image", caption, data=report_charts.force_overlays(traces, chosen),
                            name=f"force_time{'_' + str(page + 1) if page else ''}.png"))
    return blocks


def build_blocks(runs: list[Run]) -> list[Block]:
    suites = sorted({run.rows[0]["suite"] for run in runs})
    blocks = [Block("heading", f"Benchmark report: {', '.join(suites)}")]
    summary_rows = []
    for run in runs:
        overall = success_by(run.rows, lambda _: "all")[0]
        harness = sum(r["wall_s"] - r["env_wall_s"] - r["policy_wall_s"] for r in run.rows)
        summary_rows.append([run.short, run.label, run.shown_folder or str(run.folder)] + rate_cells(overall)[1:] +
                            [f"{sum(r['wall_s'] for r in run.rows) / len(run.rows):.1f}",
                             f"{100 * harness / max(1e-9, sum(r['wall_s'] for r in run.rows)):.1f} %"])
    header = ["run", "policy @ server", "folder", "success", "rate", "95 % CI (Wilson)", "errors",
              "wall s / episode", "harness share"]
    if len(runs) == 1:  # one run: its label is the name, no letter needed
        header, summary_rows = header[1:], [row[1:] for row in summary_rows]
    blocks.append(Block("table", header=header, rows=summary_rows))
    blocks += _comparison(runs, "task", "Success per task", "task")
    for column, title in (("style", "Success per cut style"), ("state", "Success per cut state"),
                          ("food", "Success per food"), ("language", "Success per language split")):
        blocks += _comparison(runs, column, title, column)
    if any(row["group_name"] for run in runs for row in run.rows):
        blocks += _comparison(runs, "group_name", "Success per group", "group")
    named_rows = [(run.short, run.rows) for run in runs]
    blocks.append(Block("image", "Success per food", data=report_charts.success_per_food(named_rows),
                        name="success_per_food.png"))
    ratio_foods = sorted({r["food"] for run in runs for r in run.rows if r["state"] == "ratio"})
    for food in ratio_foods:
        if report_charts.radar_sides(named_rows, food):
            blocks.append(Block("image", f"Ratio cuts on {food}", data=report_charts.ratio_radar(named_rows, food),
                                name=f"ratio_radar_{food}.png"))
    if any(r["state"] == "split" for run in runs for r in run.rows):
        blocks += _split_blocks(runs)
    if len({r["topology"] for run in runs for r in run.rows}) > 1:
        blocks += _topology_blocks(runs)
    if any(safety_tables.is_ablation(run.rows) for run in runs):
        blocks += _safety_blocks(runs)
    blocks += _cut_quality_blocks(runs)
    blocks += _force_blocks(runs)
    blocks += _failure_blocks(runs)
    errors = [[run.short, r["task"], str(r["trial"]), r["end_reason"], r["error"][:200]]
              for run in runs for r in run.rows if r["outcome"] == "error"]
    if errors:
        blocks += [Block("heading", "Errors"), Block("table", header=["run", "task", "trial", "kind", "message"],
                                                     rows=errors)]
    return blocks


def to_markdown(blocks: list[Block], files: Path) -> str:
    parts = []
    for block in blocks:
        if block.kind == "heading":
            parts.append(("# " if not parts else "## ") + block.text)
        elif block.kind == "text":
            parts.append(block.text)
        elif block.kind == "table":
            parts.append(markdown_table(block.header, block.rows))
        else:
            (files / block.name).write_bytes(block.data)
            parts.append(f"![{block.text}]({files.name}/{block.name})")
    return "\n\n".join(parts) + "\n"


def to_html(blocks: list[Block], files: Path) -> str:
    """The page: charts inline; each video a thumbnail linked to its file in `files` (beside the page)."""
    body = []
    for block in blocks:
        if block.kind == "heading":
            tag = "h1" if not body else "h2"
            body.append(f"<{tag}>{html.escape(block.text)}</{tag}>")
        elif block.kind == "text":
            body.append(f"<p>{html.escape(block.text)}</p>")
        elif block.kind == "table":
            head = "".join(f"<th>{html.escape(str(c))}</th>" for c in block.header)
            rows = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>"
                           for row in block.rows)
            body.append(f"<table><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>")
        elif block.kind == "image":
            source = f"data:image/png;base64,{base64.b64encode(block.data).decode()}"
            body.append(f"<figure><img src=\"{source}\" alt=\"{html.escape(block.text)}\">"
                        f"<figcaption>{html.escape(block.text)}</figcaption></figure>")
        else:
            thumbnail = "data:image/jpeg;base64," + base64.b64encode(report_media.last_frame_jpeg(block.data)).decode()
            link, caption = html.escape(f"{files.name}/{block.name}"), html.escape(block.text)
            body.append(f"<figure class=\"video\"><a href=\"{link}\"><img src=\"{thumbnail}\" alt=\"{caption}\"></a>"
                        f"<figcaption>{caption} (last frame; <a href=\"{link}\">the video</a>)</figcaption></figure>")
    # A table wider than the window scrolls inside its own box; the page itself never scrolls sideways.
    style = ("body{font-family:sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222}"
             "table{border-collapse:collapse;margin:1em 0;font-size:13px;display:block;max-width:100%;overflow-x:auto}"
             "th,td{border:1px solid #ccc;padding:3px 6px;text-align:right}"
             "td:first-child,th:first-child{text-align:left}img{max-width:100%}"
             "figure.video{display:inline-block;margin:0.5em}")
    return (f"<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>{html.escape(blocks[0].text)}</title>"
            f"<style>{style}</style></head><body>{''.join(body)}</body></html>\n")


def write_report(folders: list[Path], out: Path | None = None, labels: list[str] | None = None,
                 folder_names: list[str] | None = None) -> list[Path]:
    """Writes report.md (+ report_files/) and report.html into `out` (default: the first run's folder);
    `labels` names the runs in place of "policy @ server" (e.g. a learned policy served over openpi) and
    `folder_names` their folders in place of the paths (e.g. relative to a study's folder)."""
    runs = [load_run(folder) for folder in folders]
    for run, label in zip(runs, labels or []):
        run.label = label
    for run, name in zip(runs, folder_names or []):
        run.shown_folder = name
    _name_runs(runs)
    out = out or folders[0]
    files = out / "report_files"
    blocks = build_blocks(runs)
    markdown, page = out / "report.md", out / "report.html"
    with storage_faults(out, f"{AGAIN} (or give another --out)"):
        files.mkdir(parents=True, exist_ok=True)
        markdown.write_text(to_markdown(blocks, files))
        page.write_text(to_html(blocks, files))
    return [markdown, page]

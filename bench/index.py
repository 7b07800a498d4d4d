"""docs/benchmarks/README.md: every benchmark's page, script and JSON with the date and machine of its numbers,
from the registry and the JSON files (`python -m bench index`; `python -m bench run` rewrites it after a run)."""
from __future__ import annotations

import os
from pathlib import Path

from bench.harness import Docs, machine_words, stamp_of
from bench.registry import BENCHMARKS, Benchmark

INDEX = "benchmarks/README.md"


def _link(target: str, text: str | None = None) -> str:
    relative = Path(os.path.relpath(target, Path(INDEX).parent)).as_posix()
    return f"[{text or Path(target).name}]({relative})"


def _row(docs: Docs, b: Benchmark) -> str:
    data = docs.load(b.json) if b.json else None
    stamp = stamp_of(data) if data else {}
    measured = stamp.get("date") or ("-" if data is None else "?")
    build = f" ({stamp['build_id']})" if stamp.get("build_id") else ""
    machine = machine_words(stamp["machine"]) if stamp.get("machine") else "-"
    page = _link(b.page) if b.page else "-"
    numbers = _link(b.json) if b.json else "-"
    return (f"| {b.name} | {b.measures} | {page} | {numbers} | `{b.script}` | {measured}{build} | {machine} | "
            f"{b.duration} |")


def markdown(docs: Docs) -> str:
    pages = [b for b in BENCHMARKS if b.page]
    figures = [b for b in BENCHMARKS if not b.page]
    lines = ["# Benchmarks", "",
             "Every page here is written by one script under `bench/`, with its numbers in a JSON file beside it. "
             "`bench/registry.py` lists them; this index is generated from it and the JSON files "
             "(`python -m bench index`). Each page ends with the command that regenerates it.", "",
             "```",
             "python -m bench list                    # every benchmark: page, JSON, what it measures, how long",
             "python -m bench run NAME [--build DIR]  # regenerate one (`all`: every one), then this index",
             "python -m bench run all --quick         # the smoke pass: every benchmark on a tiny case, into a "
             "temporary folder",
             "```", "",
             "*Measured*: the date of the page's numbers and, where the harness wrote them, the checkout they were "
             "measured at. *Full run*: roughly, on the project's 2-core machine.", "",
             "| benchmark | what it measures | page | JSON | script | measured | machine | full run |",
             "|---|---|---|---|---|---|---|---|"]
    lines += [_row(docs, b) for b in pages]
    lines += ["", "## Figures", "", "These write images for other pages and have no page or JSON of their own:", "",
              "| name | what it draws | images | script | full run |", "|---|---|---|---|---|"]
    lines += [f"| {b.name} | {b.measures} | {', '.join(_link(i) for i in b.images)} | `{b.script}` | {b.duration} |"
              for b in figures]
    lines += ["", "## The smoke pass", "",
              "`python -m bench run all --quick` runs every benchmark's code on a tiny case into a temporary folder "
              "(docs/ untouched), with the binaries of `--build` (default `build/`); ctest runs it as "
              "`bench_quick_pass`. What each one does there:", ""]
    for b in BENCHMARKS:
        if b.quick is None:
            lines.append(f"- **{b.name}**: left out: {b.why_not_quick}.")
        else:
            lines.append(f"- **{b.name}**: {b.quick_does}" + (f" ({b.why_not_quick})" if b.why_not_quick else "")
                         + ".")
    return "\n".join(lines) + "\n"


def write_index(docs: Docs) -> Path:
    path = docs.path(INDEX)
    path.write_text(markdown(docs))
    return path

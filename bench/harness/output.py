"""Where a benchmark writes and how: its page and its JSON side by side, both stamped with the date, the
checkout's build id and the machine, and the command line every script shares (--docs, --quick)."""
from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

from bench.harness.machine import build_id, kernel_instruction_set, machine_info, today
from bench.harness.paths import DOCS, ROOT


def arguments(doc: str, whole_doc: bool = False, render_only: bool = False) -> argparse.ArgumentParser:
    """A script's argument parser with the options every benchmark takes: --docs (write under another folder
    than docs/) and --quick (the smoke pass's tiny case), and with `render_only` --render-only (the page again
    from the stored JSON). The description is the docstring's first line, or all of it with `whole_doc`."""
    parser = argparse.ArgumentParser(description=doc.strip() if whole_doc else doc.strip().splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--docs", type=Path, default=None,
                        help="write pages, JSON and images under this folder instead of the checkout's docs/")
    parser.add_argument("--quick", action="store_true",
                        help="a smoke pass: the same code on a tiny case, in seconds; its numbers mean nothing, so "
                             "it needs --docs (python -m bench run NAME --quick gives it a temporary folder)")
    if render_only:
        parser.add_argument("--render-only", action="store_true", help="redraw the page from the stored JSON")
    return parser


def docs_for(args: argparse.Namespace, benchmarks: Path | None = None) -> "Docs":
    """The folder the script's arguments name (--docs), refusing a smoke pass into docs/; `benchmarks` is a
    script's own option for the folder of its page and JSON (--out), kept from before the harness."""
    if getattr(args, "quick", False) and not (args.docs or benchmarks):
        raise SystemExit("error: --quick measures a tiny case: give it --docs DIR so that docs/ keeps the real "
                         "numbers (python -m bench run NAME --quick does)")
    return Docs(args.docs, benchmarks)


def stamp(script: str | Path) -> dict:
    """What every JSON a benchmark writes carries under "generated": the script, the date, the checkout's build
    id, the instruction set its MPM kernels ran and the machine."""
    return {"script": _script_name(script), "date": today(), "build_id": build_id(),
            "simd": kernel_instruction_set(), "machine": machine_info()}


def stamp_of(data: dict) -> dict:
    """The stamp of a stored JSON: its "generated" or, for JSON written before the harness, what its own
    fields say (date, machine); missing parts are None."""
    if isinstance(data.get("generated"), dict):
        return data["generated"]
    machine = data.get("machine") if isinstance(data.get("machine"), dict) else {}
    context = data.get("context") if isinstance(data.get("context"), dict) else {}
    day = machine.get("date") or data.get("date") or (data.get("timestamp") or "")[:10] or context.get("date", "")[:10]
    return {"script": None, "date": day or None, "build_id": None,
            "machine": {"cpu_model": machine.get("cpu_model") or machine.get("processor") or data.get("cpu_model"),
                        "cores": machine.get("cores") or machine.get("cpu_count") or context.get("num_cpus")}}


def machine_words(machine: dict) -> str:
    """"AMD EPYC, 2 cores" from a stamp's machine."""
    cores = machine.get("cores")
    return f"{machine.get('cpu_model') or 'unknown CPU'}" + (f", {cores} cores" if cores else "")


class Docs:
    """The folder a benchmark writes its pages, JSON and images under: the checkout's docs/ by default, or
    another (--docs; the smoke pass writes into a temporary one). Paths are relative to it, as in the registry:
    "benchmarks/robot_step.md", "accuracy.md", "images/e_sweep.png"."""

    def __init__(self, root: Path | None = None, benchmarks: Path | None = None):
        self.root = Path(root).resolve() if root else DOCS
        # Where "benchmarks/..." goes: root/benchmarks, or a script's own --out folder.
        self.benchmarks = Path(benchmarks).resolve() if benchmarks else self.root / "benchmarks"

    @property
    def is_checkout(self) -> bool:
        return self.root == DOCS and self.benchmarks == DOCS / "benchmarks"

    def path(self, relative: str) -> Path:
        """The file's path under this folder, its folder made."""
        head, _, rest = relative.partition("/")
        path = self.benchmarks / rest if head == "benchmarks" and rest else self.root / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        return path

    def image(self, name: str) -> Path:
        return self.path(f"images/{name}")

    def load(self, relative: str, committed: bool = False) -> dict | None:
        """A stored JSON from this folder (None where there is none); with `committed`, from the checkout's docs/
        where this folder has none (a smoke pass re-rendering a page from the stored numbers)."""
        for path in (self.path(relative), DOCS / relative) if committed else (self.path(relative),):
            if path.is_file():
                return json.loads(path.read_text())
        return None

    def stored(self, relative: str) -> dict:
        """A stored JSON to draw a page from again (--render-only): this folder's, else the checkout's."""
        data = self.load(relative, committed=True)
        if data is None:
            raise SystemExit(f"error: no {relative} to draw from: run the benchmark first")
        return data

    def render_stored(self, page: str, json_relative: str, markdown, script: str | Path) -> dict:
        """Writes `page` again from its stored JSON with `markdown(stored)`; returns the stored JSON."""
        data = self.stored(json_relative)
        self.write_page(page, markdown(data), script, json_relative, data)
        return data

    def write_json(self, relative: str, data: dict, script: str | Path, indent: int | None = 1) -> Path:
        """Writes the benchmark's JSON with the stamp under "generated" (added to `data`)."""
        data["generated"] = stamp(script)
        path = self.path(relative)
        path.write_text(json.dumps(data, indent=indent) + "\n")
        return path

    def write_page(self, relative: str, text: str, script: str | Path, json_relative: str | None = None,
                   stored: dict | None = None) -> Path:
        """Writes a page with the footer every generated page ends in: which script and command made it, when,
        from which checkout, on what machine, and where its JSON is. The stamp is `stored`'s (the JSON the page
        shows) or, without one, today's."""
        path = self.path(relative)
        footer = _footer(relative, script, json_relative, stamp_of(stored) if stored is not None else stamp(script))
        path.write_text(text.rstrip("\n") + "\n\n" + footer + "\n")
        return path

    def publish(self, page: str, text: str | None, json_relative: str, data: dict, script: str | Path,
                indent: int | None = 1) -> Path:
        """A page and its JSON side by side: the JSON stamped, the page with the same stamp in its footer.
        `text` may be None to write the JSON alone (a page rendered afterwards from it)."""
        self.write_json(json_relative, data, script, indent)
        if text is not None:
            self.write_page(page, text, script, json_relative, data)
        return self.path(page)


def _script_name(script: str | Path) -> str:
    path = Path(script).resolve()
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(script)


def _footer(page: str, script: str | Path, json_relative: str | None, stamp_: dict) -> str:
    from bench.registry import entry_for  # the registry names the command; imported late (it is data only)
    name = _script_name(script)
    entry = entry_for(name, page)
    here = Path(page).parent
    link = lambda target: Path(os.path.relpath(target, here)).as_posix()  # noqa: E731
    made = f"Generated by `{name}`" + (f" (`python -m bench run {entry.name}`)" if entry else "")
    when = f" on {stamp_['date']}" if stamp_.get("date") else ""
    build = f", checkout {stamp_['build_id']}" if stamp_.get("build_id") else ""
    machine = f", {machine_words(stamp_['machine'])}" if stamp_.get("machine") else ""
    numbers = f" The numbers: [{Path(json_relative).name}]({link(json_relative)})." if json_relative else ""
    return (f"*{made}{when}{build}{machine}.{numbers} Every benchmark: "
            f"[benchmarks/README.md]({link('benchmarks/README.md')}).*")

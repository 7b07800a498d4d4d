"""python -m bench: the one command for every benchmark.

    python -m bench list [--json]                        every benchmark: name, page, JSON, what, how long
    python -m bench run NAME... [--build DIR] [ARGS]     regenerate these (`all`: every one), then the index;
                                                         ARGS go to the benchmark's script when one is named
    python -m bench run all --quick [--keep]             the smoke pass: each one's tiny case, into a temporary
                                                         folder (docs/ untouched); exit 1 if any fails
    python -m bench index                                docs/benchmarks/README.md from the registry and the JSON
    python -m bench check                                pages, JSON and the registry agree

Benchmarks run in this process, one after another (each script's main() with its own command line), so a pass
imports numpy, grpc and matplotlib once.
"""
from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import json
import shutil
import sys
import tempfile
import time
import traceback
from pathlib import Path

from bench.harness import Docs, use_build
from bench.harness.paths import DOCS, ROOT
from bench.index import INDEX, write_index
from bench.registry import BENCHMARKS, Benchmark, get


def _list(as_json: bool) -> int:
    if as_json:
        print(json.dumps([{"name": b.name, "script": b.script, "page": b.page and f"docs/{b.page}",
                           "json": b.json and f"docs/{b.json}", "measures": b.measures, "duration": b.duration,
                           "needs": list(b.needs), "images": [f"docs/{i}" for i in b.images],
                           "quick": None if b.quick is None else list(b.quick), "why_not_quick": b.why_not_quick}
                          for b in BENCHMARKS], indent=1))
        return 0
    width = max(len(b.name) for b in BENCHMARKS)
    for b in BENCHMARKS:
        outputs = ", ".join(f"docs/{p}" for p in (b.page, b.json) if p) or ", ".join(f"docs/{i}" for i in b.images)
        quick = "" if b.quick is not None else "  [not in --quick]"
        print(f"{b.name:<{width}}  {b.script}  ->  {outputs}\n{'':<{width}}  {b.measures}; full run {b.duration}"
              f"{quick}")
    return 0


def _arguments(b: Benchmark, quick: bool, docs: Path | None, extra: list[str]) -> list[str]:
    argv = list(b.quick if quick else b.args)
    if docs is not None:
        argv += [b.folder_option, str(docs / b.folder_under) if b.folder_under else str(docs)]
    return argv + extra


def _exit_code(code) -> int:
    if code is None:
        return 0
    if isinstance(code, int):
        return code
    print(code, file=sys.stderr)  # SystemExit("error: ...")
    return 1


def run_one(b: Benchmark, argv: list[str], quiet: bool) -> tuple[int, float, str]:
    """Runs a benchmark's main() here with `argv` as its command line; (exit code, seconds, its output when
    `quiet`)."""
    log = io.StringIO()
    started = time.perf_counter()
    saved = sys.argv
    redirect = (contextlib.redirect_stdout(log), contextlib.redirect_stderr(log)) if quiet else ()
    try:
        with contextlib.ExitStack() as stack:
            for r in redirect:
                stack.enter_context(r)
            try:
                module = importlib.import_module(f"bench.{b.module}")
                sys.argv = [str(ROOT / b.script), *argv]
                code = _exit_code(module.main())
            except SystemExit as exit_:
                code = _exit_code(exit_.code)
            except Exception:  # a failed benchmark is reported, and the others still run
                traceback.print_exc()
                code = 1
    finally:
        sys.argv = saved
    return code, time.perf_counter() - started, log.getvalue()


def _missing_outputs(b: Benchmark, docs: Path) -> list[str]:
    """What the smoke pass should have written under `docs` and did not."""
    expected = [b.page] if b.page else []
    expected += [b.json] if b.json and b.quick_json else []
    expected += list(b.images)
    return [p for p in expected if not (docs / p).is_file()]


def _run(names: list[str], quick: bool, build: Path | None, docs_arg: Path | None, keep: bool,
         extra: list[str]) -> int:
    chosen = list(BENCHMARKS) if names == ["all"] else [get(n) for n in names]
    if extra and len(chosen) != 1:
        print(f"error: {' '.join(extra)}: extra arguments go to one benchmark's script; name one", file=sys.stderr)
        return 2
    if build is not None:
        use_build(build)
    docs = docs_arg.resolve() if docs_arg else (Path(tempfile.mkdtemp(prefix="culinarycut-bench-quick-"))
                                                if quick else None)
    skipped = [b for b in chosen if quick and b.quick is None]
    todo = [b for b in chosen if b not in skipped]
    print(f"{'smoke pass' if quick else 'running'}: {len(todo)} benchmark(s) into {docs or DOCS}", flush=True)
    results, started = [], time.perf_counter()
    for i, b in enumerate(todo, 1):
        print(f"[{i}/{len(todo)}] {b.name} ...", end=" " if quick else "\n", flush=True)
        code, seconds, log = run_one(b, _arguments(b, quick, docs, extra), quiet=quick)
        absent = _missing_outputs(b, docs) if quick and code == 0 else []
        if absent:
            code, log = 1, log + f"\nthe smoke pass wrote no {', '.join(absent)}\n"
        results.append((b, code, seconds))
        print(f"{'ok' if code == 0 else f'FAILED (exit {code})'} in {seconds:.1f} s", flush=True)
        if code != 0 and quick:
            print("    " + "\n    ".join(log.rstrip().splitlines()[-40:]), flush=True)
    for b in skipped:
        print(f"-- {b.name}: not in the smoke pass: {b.why_not_quick}")
    index_docs = Docs(docs) if docs else Docs()
    print(f"wrote {write_index(index_docs)}")
    failed = [b.name for b, code, _ in results if code != 0]
    total = time.perf_counter() - started
    print(f"{len(results) - len(failed)} of {len(results)} passed in {total:.0f} s"
          + (f"; failed: {', '.join(failed)}" if failed else ""))
    if quick and docs_arg is None:
        if keep or failed:
            print(f"kept {docs}")
        else:
            shutil.rmtree(docs, ignore_errors=True)
    return 1 if failed else 0


def check() -> list[str]:
    """What disagrees between the registry and docs/: every registered script, page and JSON exists, every page
    has its JSON and every JSON its page, and every page and JSON under docs/benchmarks/ is registered."""
    problems = []
    for b in BENCHMARKS:
        if not (ROOT / b.script).is_file():
            problems.append(f"{b.name}: no script {b.script}")
        if bool(b.page) != bool(b.json):
            problems.append(f"{b.name}: a page needs its JSON and a JSON its page ({b.page}, {b.json})")
        for path in (b.page, b.json, *b.images):
            if path and not (DOCS / path).is_file():
                problems.append(f"{b.name}: no docs/{path}")
        if b.quick is None and not b.why_not_quick:
            problems.append(f"{b.name}: left out of the smoke pass without a reason")
    registered = {p for b in BENCHMARKS for p in (b.page, b.json) if p} | {INDEX}
    for path in sorted((DOCS / "benchmarks").iterdir()):
        relative = path.relative_to(DOCS).as_posix()
        if path.suffix in (".md", ".json") and relative not in registered:
            problems.append(f"docs/{relative}: no benchmark in bench/registry.py writes it")
    names = [b.name for b in BENCHMARKS]
    problems += [f"{n}: registered twice" for n in sorted({n for n in names if names.count(n) > 1})]
    return problems


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench", description=__doc__.splitlines()[0],
                                     epilog="Every benchmark: bench/registry.py, docs/benchmarks/README.md.")
    commands = parser.add_subparsers(dest="command", required=True)
    listing = commands.add_parser("list", help="every benchmark")
    listing.add_argument("--json", action="store_true", help="as JSON")
    run = commands.add_parser("run", help="regenerate benchmarks (`all`), or their smoke pass (--quick)")
    run.add_argument("names", nargs="+", metavar="NAME", help="benchmark names (python -m bench list), or all")
    run.add_argument("--quick", action="store_true",
                     help="each one's tiny case (seconds), into a temporary folder: docs/ stays as it is")
    run.add_argument("--build", type=Path, help="the CMake build folder with the server, cc-cut and bench binaries "
                                                "(default $CULINARYCUT_BUILD, else build/)")
    run.add_argument("--docs", type=Path, help="write under this folder instead of docs/ (or the temporary one)")
    run.add_argument("--keep", action="store_true", help="with --quick: keep the temporary folder")
    index = commands.add_parser("index", help=f"write docs/{INDEX}")
    index.add_argument("--docs", type=Path, help="the docs folder (default docs/)")
    commands.add_parser("check", help="the registry and docs/ agree (exit 1 if not)")
    args, extra = parser.parse_known_args(argv)
    if extra and args.command != "run":
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    if args.command == "list":
        return _list(args.json)
    if args.command == "run":
        try:
            return _run(args.names, args.quick, args.build, args.docs, args.keep, extra)
        except KeyError as err:
            print(f"error: {err.args[0]}", file=sys.stderr)
            return 2
    if args.command == "index":
        print(f"wrote {write_index(Docs(args.docs))}")
        return 0
    problems = check()
    print("\n".join(problems) or "the registry and docs/ agree")
    return 1 if problems else 0

#!/usr/bin/env python3
"""The learned baseline on the benchmark suites: the study in learning/scripts/baseline_study.py (generate a
training split, export, train, serve, run the suites beside the floors), which writes docs/benchmarks/baselines.md
and .json. It lives with the learning package (it needs torch); this entry lets the harness list and run it.

    .venv/bin/python bench/baselines.py --out studies/baseline --server 127.0.0.1:50051 [study options]
"""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

STUDIES = Path(__file__).resolve().parents[1] / "learning" / "scripts"


def run_study(name: str, argv: list[str]) -> int:
    """learning/scripts/NAME.py's main with `argv` (a script, not a module of the package: loaded by its path)."""
    spec = importlib.util.spec_from_file_location(name, STUDIES / f"{name}.py")
    study = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(study)
    return study.main(argv)


def main() -> int:
    return run_study("baseline_study", sys.argv[1:])


if __name__ == "__main__":
    sys.exit(main())

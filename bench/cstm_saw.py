#!/usr/bin/env python3
"""The CulinaryCut paper's saw experiment with the learned policy and the CSTM: the study in
learning/scripts/cstm_saw_study.py (the policy trained on saw cuts and on normal cuts, the contact classifier, the
style generator, a suite of saw cuts with the oracle, both policies and the normal one restyled), which writes
docs/benchmarks/cstm_saw.md and .json. It lives with the learning package (it needs torch); this entry lets the
harness list and run it.

    .venv/bin/python bench/cstm_saw.py --out studies/cstm-saw --data studies/baseline/export \\
        --server 127.0.0.1:50051 [study options]
"""
from __future__ import annotations

import sys
from pathlib import Path

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.baselines import run_study  # noqa: E402


def main() -> int:
    return run_study("cstm_saw_study", sys.argv[1:])


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The renderer's example images for docs/rendering.md: runs bench_render_frames (bench/render_frames.cc), which
writes what the cameras see as PNG files: the front, left and right views side by side for the table and kitchen
scenes with a whole and a cut cucumber, the wrist view, and the depth and segmentation channels of one view.

    .venv/bin/python bench/render_frames.py [--binary build/bench/bench_render_frames]
"""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import arguments, bench_binary, docs_for, missing  # noqa: E402


def main() -> int:
    parser = arguments(__doc__)
    parser.add_argument("--binary", type=Path, default=bench_binary("bench_render_frames"))
    args = parser.parse_args()
    docs = docs_for(args)  # the smoke pass renders the same images, into its own folder
    if code := missing(args.binary, "--binary"):
        return code
    images = docs.root / "images"
    images.mkdir(parents=True, exist_ok=True)
    done = subprocess.run([str(args.binary), str(images)], capture_output=True, text=True)
    print(done.stdout + done.stderr, end="")
    return done.returncode


if __name__ == "__main__":
    sys.exit(main())

"""Where the checkout, its docs and the build's binaries are."""
from __future__ import annotations

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
# The CMake build folder the benchmarks take their binaries from (default: the checkout's build/).
BUILD_ENV = "CULINARYCUT_BUILD"
SERVER_ENV = "CULINARYCUT_SERVER"  # culinarycut.launch starts this server binary when it is set


def build_dir() -> Path:
    return Path(os.environ.get(BUILD_ENV) or ROOT / "build")


def use_build(build: Path) -> None:
    """Make `build` the folder every benchmark of this process (and its children) takes its binaries from,
    the server included."""
    build = build.resolve()
    os.environ[BUILD_ENV] = str(build)
    os.environ[SERVER_ENV] = str(build / "server" / "culinarycut-server")


def cc_cut() -> Path:
    return build_dir() / "tools" / "cc_cut" / "cc-cut"


def bench_binary(name: str) -> Path:
    """A C++ benchmark built from bench/CMakeLists.txt, e.g. bench_step_latency."""
    return build_dir() / "bench" / name


def server_binary() -> Path:
    return Path(os.environ.get(SERVER_ENV) or build_dir() / "server" / "culinarycut-server")


def missing(binary: Path, option: str) -> int:
    """0 when `binary` exists; else says how to get it and returns 2 (a script's exit code for it)."""
    if Path(binary).is_file():
        return 0
    print(f"error: no {binary}; build it (scripts/build.sh), give the build folder (python -m bench run ... "
          f"--build DIR) or pass {option}", file=sys.stderr)
    return 2

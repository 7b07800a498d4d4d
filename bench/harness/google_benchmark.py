"""Running one of the C++ benchmarks (Google Benchmark, bench/*.cc) and reading its JSON report."""
from __future__ import annotations

import json
import subprocess
from pathlib import Path


def google_benchmark(binary: Path, *arguments: str, env: dict | None = None) -> dict:
    """The JSON report of `binary --benchmark_format=json ARGUMENTS...`; CalledProcessError when it fails."""
    done = subprocess.run([str(binary), "--benchmark_format=json", *arguments], check=True, capture_output=True,
                          text=True, env=env)
    return json.loads(done.stdout)

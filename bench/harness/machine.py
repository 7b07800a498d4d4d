"""What machine a benchmark ran on, which checkout it measured, and what else the machine was doing."""
from __future__ import annotations

import os
import platform
import subprocess
import threading
import time
from datetime import date
from functools import lru_cache
from pathlib import Path

from bench.harness.paths import ROOT


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def machine_info() -> dict:
    """The machine description every benchmark's JSON carries under "machine" (pages and the index read its keys)."""
    import grpc
    import numpy as np
    return {"cpu_model": cpu_model(), "cores": os.cpu_count(), "platform": platform.platform(),
            "python": platform.python_version(), "grpcio": grpc.__version__, "numpy": np.__version__}


def today() -> str:
    return date.today().isoformat()


def dated_machine_info() -> dict:
    """machine_info() with today's date, the form most pages print ("Machine: ...; 2026-11-27.")."""
    return {**machine_info(), "date": today()}


@lru_cache(maxsize=1)
def kernel_instruction_set() -> str:
    """The instruction set the benchmarked build's MPM kernels run on this machine by default (the loader's pick,
    as cc-cut and GetServerInfo say it); "unknown" without a built cc-cut."""
    from bench.harness.paths import cc_cut
    from culinarycut.safety.binary import cc_cut_presets
    try:
        return cc_cut_presets(cc_cut()).get("simd", "unknown")
    except Exception:  # no build yet, or one from before the field: the page says unknown
        return "unknown"


@lru_cache(maxsize=1)
def build_id() -> str:
    """The checkout's commit as `git describe --always --dirty` gives it ("-dirty": uncommitted changes were
    measured too); "unknown" outside a git checkout."""
    try:
        done = subprocess.run(["git", "-C", str(ROOT), "describe", "--always", "--dirty", "--abbrev=10"],
                              capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.TimeoutExpired):
        return "unknown"
    return done.stdout.strip() if done.returncode == 0 and done.stdout.strip() else "unknown"


def idle_percent(seconds: float = 2.0) -> float:
    """The share of CPU time the whole machine spent idle over the next `seconds`."""
    def sample() -> tuple[int, int]:
        fields = [int(v) for v in Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:]]
        return fields[3], sum(fields)
    idle0, total0 = sample()
    time.sleep(seconds)
    idle1, total1 = sample()
    return 100.0 * (idle1 - idle0) / max(1, total1 - total0)


def wait_for_idle(min_idle_percent: float, max_wait_s: float) -> float:
    """Waits until other jobs leave the machine at least this idle for 2 s (a shared machine), or max_wait_s;
    returns the idle share it last saw."""
    deadline = time.monotonic() + max_wait_s
    while True:
        idle = idle_percent()
        if idle >= min_idle_percent or time.monotonic() > deadline:
            return idle


class LoadSampler:
    """The 1-minute load average every `period_s` while a run goes: on a shared machine it says what the run had."""

    def __init__(self, period_s: float = 10.0):
        self.samples: list[float] = []
        self._period_s = period_s
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._sample, daemon=True)

    def _sample(self) -> None:
        while not self._stop.wait(self._period_s):
            self.samples.append(os.getloadavg()[0])

    def __enter__(self):
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()

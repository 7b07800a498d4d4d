"""`culinarycut bench ...` as a user runs it, in a subprocess, with this folder on PYTHONPATH (for the
misbehaving policies of bench_policies and the Dask worker preload)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def with_tests_on_path(env: dict) -> dict:
    """The environment plus this folder on PYTHONPATH, keeping what PYTHONPATH already named."""
    return {**env, "PYTHONPATH": os.pathsep.join(filter(None, [str(HERE), env.get("PYTHONPATH")]))}


def bench(*argv, timeout=600, check=True) -> subprocess.CompletedProcess:
    env = with_tests_on_path(dict(os.environ))
    done = subprocess.run([sys.executable, "-m", "culinarycut", "bench", *argv], capture_output=True, text=True,
                          timeout=timeout, env=env)
    if check:
        assert done.returncode == 0, f"exit {done.returncode}\n{done.stdout}\n{done.stderr}"
    return done

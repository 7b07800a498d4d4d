"""A stand-in model server in its own process (`python -m culinarycut_policies.standins`): what tests use
to kill or freeze a model server, and what the overhead benchmark uses so the model side does not share
the client's interpreter. `queries` counts the queries it has received."""
from __future__ import annotations

import os
import subprocess
import sys
import threading
import time


class StandinProcess:
    def __init__(self, model: str, *args: str):
        # This interpreter and its environment: they import the culinarycut_policies this process imports.
        self.proc = subprocess.Popen([sys.executable, "-m", "culinarycut_policies.standins", model, "--port", "0",
                                      "--log-queries", *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     text=True)
        first = self.proc.stdout.readline()
        if not first.startswith("listening on "):
            self.proc.kill()
            raise RuntimeError(f"stand-in {model} did not start: {first}{self.proc.stdout.read()}")
        self.url = first.split()[-1]
        self.queries = 0
        self._reader = threading.Thread(target=self._count, daemon=True)
        self._reader.start()

    def _count(self) -> None:
        for line in self.proc.stdout:
            if line.startswith("query "):
                self.queries = int(line.split()[1])

    def wait_for_queries(self, count: int, timeout_s: float = 60.0) -> None:
        deadline = time.monotonic() + timeout_s
        while self.queries < count:
            if time.monotonic() > deadline or self.proc.poll() is not None:
                raise TimeoutError(f"the stand-in saw {self.queries} of {count} queries")
            time.sleep(0.01)

    def signal(self, number: int) -> None:
        os.kill(self.proc.pid, number)

    def close(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.wait(10)

"""Start a culinarycut-server subprocess on ephemeral ports and learn its addresses from stdout."""
from __future__ import annotations

import contextlib
import os
import queue
import re
import shutil
import signal
import subprocess
import threading
import time
from pathlib import Path

SERVER_NAME = "culinarycut-server"
# Where the package sits when it runs from a CulinaryCut checkout (an editable install).
CHECKOUT_ROOT = Path(__file__).resolve().parents[3]
_LISTEN_RE = re.compile(r"listening on (\S+)")  # host:port, or unix:/path
_TELEMETRY_RE = re.compile(r"telemetry on (tcp://127\.0\.0\.1:\d+)")


def server_binary() -> Path:
    """$CULINARYCUT_SERVER if set; else, from a checkout, its build/server/culinarycut-server; else the
    culinarycut-server on PATH."""
    env = os.environ.get("CULINARYCUT_SERVER")
    if env:
        return Path(env)
    if (CHECKOUT_ROOT / "proto" / "culinarycut").is_dir():
        return CHECKOUT_ROOT / "build" / "server" / SERVER_NAME
    return Path(shutil.which(SERVER_NAME) or SERVER_NAME)


def cores_per_local_server(servers: int) -> int:
    """The cores each of `servers` servers started together on this machine gives its Steps (--step-cores):
    a server shares only the cores it is told of among its own Steps, so servers that each took every core
    would run cores x servers MPM threads and oversubscribe the machine."""
    return max(1, (os.cpu_count() or 1) // max(1, servers))


@contextlib.contextmanager
def local_servers(count: int, **options):
    """`count` ServerProcess(**options) started together on this machine, sharing its cores
    (step_cores=cores_per_local_server(count)); all stopped on exit."""
    cores = cores_per_local_server(count)
    with contextlib.ExitStack() as stack:
        yield [stack.enter_context(ServerProcess(step_cores=cores, **options)) for _ in range(count)]


class ServerProcess:
    """A running server; `address` is host:port for gRPC, `telemetry` the ZeroMQ PUB endpoint. `step_cores`:
    the cores its Steps share (--step-cores; None: every core), cores_per_local_server() when several run here."""

    def __init__(self, binary: Path | str | None = None, max_sessions: int = 8, idle_timeout_s: float = 60,
                 extra_args: list[str] | None = None, startup_timeout_s: float = 30.0, listen: str = "127.0.0.1:0",
                 step_cores: int | None = None):
        self.binary = Path(binary) if binary else server_binary()
        if not (self.binary.is_file() and os.access(self.binary, os.X_OK)):
            raise FileNotFoundError(
                f"culinarycut-server binary not found or not executable at {self.binary}; "
                "build it with scripts/build.sh or set CULINARYCUT_SERVER to its path")
        self.args = [str(self.binary), "--listen", listen, "--telemetry", "tcp://127.0.0.1:0",
                     "--max-sessions", str(max_sessions), "--idle-timeout", f"{idle_timeout_s:g}",
                     *(["--step-cores", str(step_cores)] if step_cores else []), *(extra_args or [])]
        self.lines: list[str] = []  # everything the server printed (stdout and stderr interleaved)
        self._lines_q: queue.Queue[str | None] = queue.Queue()
        self.proc = subprocess.Popen(self.args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     text=True, bufsize=1)
        # Drain the pipe for the server's whole life so a chatty server never blocks on a full pipe.
        self._reader = threading.Thread(target=self._drain, daemon=True)
        self._reader.start()
        try:
            self.address, self.telemetry = self._wait_for_addresses(startup_timeout_s)
        except Exception:
            self.kill()
            raise

    def _drain(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.append(line.rstrip("\n"))
            self._lines_q.put(line)
        self._lines_q.put(None)

    def _wait_for_addresses(self, timeout_s: float) -> tuple[str, str]:
        address = telemetry = None
        deadline = time.monotonic() + timeout_s
        while address is None or telemetry is None:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimeoutError(f"server did not print its addresses within {timeout_s:.0f} s; "
                                   f"args {self.args}; output so far:\n{self.output()}")
            try:
                line = self._lines_q.get(timeout=remaining)
            except queue.Empty:
                continue
            if line is None:
                code = self.proc.wait()
                raise RuntimeError(f"server exited with code {code} before it was ready; args {self.args}; "
                                   f"output:\n{self.output()}")
            if m := _LISTEN_RE.search(line):
                address = m.group(1)
            if m := _TELEMETRY_RE.search(line):
                telemetry = m.group(1)
        return address, telemetry

    def output(self, last: int = 60) -> str:
        return "\n".join(self.lines[-last:])

    def stop(self, timeout_s: float = 20.0) -> int:
        """SIGTERM and wait; returns the exit code (kills and raises TimeoutError if it hangs)."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        try:
            code = self.proc.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            self.kill()
            raise TimeoutError(f"server did not exit within {timeout_s:.0f} s of SIGTERM; "
                               f"output:\n{self.output()}") from None
        self._reader.join(timeout=5)
        self.proc.stdout.close()
        return code

    def kill(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()

    def __enter__(self) -> "ServerProcess":
        return self

    def __exit__(self, *exc) -> None:
        self.stop()

"""Serving a policy server from the command line until it is told to stop (the stand-ins' and the learned
policy's `serve` commands share it)."""
from __future__ import annotations

import signal
import threading
from typing import Callable


def serve_until_stopped(server, banner: Callable[[], str]) -> None:
    """Starts `server` (anything with start() and stop()), prints `banner()` once it listens (a port asked as 0
    is known only then), and serves until SIGTERM or Ctrl-C; then stops it."""
    stopped = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stopped.set())
    server.start()
    print(banner(), flush=True)
    try:
        stopped.wait()
    except KeyboardInterrupt:
        pass
    server.stop()

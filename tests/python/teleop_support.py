"""`culinarycut data teleop` as the tests run it: started on a free port, the URL it printed (with its token)
read back, stopped with SIGTERM."""
from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import parse_qs, urlsplit

import pytest


@dataclass
class Teleop:
    process: subprocess.Popen
    url: str          # http://127.0.0.1:PORT (no path)
    page: str         # the printed URL: the page, with ?token=
    token: str        # "" when the printed URL carries none
    session: str
    demos: Path

    @property
    def port(self) -> int:
        return urlsplit(self.url).port

    def stop(self) -> None:
        self.process.terminate()
        self.process.wait(timeout=20)


def start_teleop(address: str, demos: Path) -> Teleop:
    process = subprocess.Popen([sys.executable, "-m", "culinarycut", "data", "teleop", "--server", address,
                                "--out", str(demos), "--port", "0", "--image-size", "64"],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    line = process.stdout.readline()
    if "teleoperation of session" not in line:
        process.kill()
        pytest.fail(f"teleop did not start: {line}{process.stdout.read()}")
    session = line.split("session ")[1].split(":")[0]
    page = line.split(": ", 1)[1].split()[0]
    parts = urlsplit(page)
    token = parse_qs(parts.query).get("token", [""])[0]
    return Teleop(process, f"{parts.scheme}://{parts.netloc}", page, token, session, demos)

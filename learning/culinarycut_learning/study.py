"""What the resumable studies (learning/scripts/*_study.py) share: a study folder whose study.json keeps the options
and each stage's accumulated wall time, a policy server started from a checkpoint on a port the study keeps (the
runner's run folders record the policy's url, so a resumed study must serve on the same one), and a run folder's
success rate with its 95 % Wilson interval."""
from __future__ import annotations

import datetime
import json
import os
import platform
import shutil
import socket
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

CHECKOUT = Path(__file__).resolve().parents[2]


class Study:
    """STUDY/study.json: the options of the study and each stage's accumulated wall time. `fixed` names the options
    a folder keeps for good (those that decide its data): another value for one of them is refused."""

    def __init__(self, root: Path, options: dict, fixed: tuple[str, ...], name: str):
        self.root, self.name = root, name
        self.path = root / "study.json"
        root.mkdir(parents=True, exist_ok=True)
        self.state = json.loads(self.path.read_text()) if self.path.is_file() else {"options": options, "stages": {}}
        changed = [k for k in fixed if self.state["options"].get(k) != options.get(k)]
        if changed:
            raise SystemExit(f"{root} holds a study with other data options ({', '.join(changed)}); use another --out")
        self.state["options"] = options
        self.called: list[str] = []  # stages in the order this run reached them (the report's order)
        self.save()

    def log(self, text: str) -> None:
        print(f"[{self.name}] {text}", file=sys.stderr, flush=True)

    def save(self) -> None:
        temporary = self.path.with_suffix(".tmp")
        temporary.write_text(json.dumps(self.state, indent=1, sort_keys=True) + "\n")
        os.replace(temporary, self.path)

    def stage(self, name: str, command: list, ok_codes=(0,)) -> int:
        """Runs `command` (python -m ...) with this interpreter, adding its wall time to the stage; a stage that
        already finished with the same command is not run again (its exit code is returned), so that a resumed
        study neither waits on nor adds the time of stages with nothing left to do. Delete its entry from
        study.json to run it again."""
        text = [str(part) for part in command]
        self.called.append(name)
        entry = self.state["stages"].get(name)
        if entry and entry.get("command") == text and entry.get("exit_code") in ok_codes:
            self.log(f"{name}: done ({entry['wall_s']:.0f} s)")
            return entry["exit_code"]
        self.log(f"{name}: {' '.join(text)}")
        started = time.monotonic()
        code = subprocess.call([sys.executable, *text], cwd=CHECKOUT)
        entry = self.state["stages"].setdefault(name, {"wall_s": 0.0})
        entry["wall_s"] = round(entry["wall_s"] + time.monotonic() - started, 1)
        entry["exit_code"], entry["command"] = code, text
        self.save()
        if code not in ok_codes:
            raise SystemExit(f"{name} exited {code}; fix what it says and run the same command again to resume")
        return code

    def stage_times(self) -> dict[str, float]:
        """Each stage's accumulated wall time (s), in the order this run reached them, then any others."""
        stages = self.state["stages"]
        names = [n for n in self.called if n in stages] + sorted(n for n in stages if n not in self.called)
        return {name: stages[name]["wall_s"] for name in dict.fromkeys(names)}

    def port(self, key: str = "port", wanted: int | None = None) -> int:
        """A policy server's port under `key`: `wanted`, else the one chosen free on the study's first run."""
        if wanted:
            self.state[key] = wanted
        elif not self.state.get(key):
            with socket.socket() as probe:
                probe.bind(("127.0.0.1", 0))
                self.state[key] = probe.getsockname()[1]
        self.save()
        return int(self.state[key])


def machine() -> dict:
    """The date and machine a study's JSON carries under "machine" (the benchmark index reads its date, CPU model
    and cores)."""
    import torch
    model = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                  if line.startswith("model name")), None) if Path("/proc/cpuinfo").is_file() else None
    return {"date": datetime.date.today().isoformat(), "cpu_model": model or platform.processor() or "unknown",
            "cores": os.cpu_count(), "platform": platform.platform(), "python": platform.python_version(),
            "torch": torch.__version__}


def serve(checkpoint: Path, device: str, port: int) -> tuple[subprocess.Popen, str]:
    """`python -m culinarycut_learning serve` on the checkpoint; the process and its ws:// url."""
    process = subprocess.Popen([sys.executable, "-m", "culinarycut_learning", "serve", "--checkpoint", str(checkpoint),
                                "--port", str(port), "--device", device], stdout=subprocess.PIPE, text=True,
                               cwd=CHECKOUT)
    first = process.stdout.readline()
    if not first.startswith("listening on "):
        process.kill()
        raise SystemExit(f"the policy server did not start: {first}")
    return process, first.split()[2]


def summarise(results: Path) -> dict:
    """Episodes, successes, rate, 95 % Wilson interval and errors of a run folder, and per food."""
    from culinarycut.bench.stats import wilson_interval
    with sqlite3.connect(results / "results.sqlite") as db:
        rows = db.execute("SELECT food, outcome FROM episodes").fetchall()

    def numbers(outcomes: list[str]) -> dict:
        n, s = len(outcomes), sum(o == "success" for o in outcomes)
        low, high = wilson_interval(s, n)
        return {"episodes": n, "successes": s, "rate": s / n if n else None, "ci95": [low, high],
                "errors": sum(o == "error" for o in outcomes)}
    out = numbers([o for _, o in rows])
    out["by_food"] = {food: numbers([o for f, o in rows if f == food]) for food in sorted({f for f, _ in rows})}
    return out


def runs_report(folder: Path, runs: list[Path], labels: list[str], study_root: Path) -> None:
    """Run folders side by side as `culinarycut bench report` writes them (per task, style, food and group, the ratio
    radars, cut quality, forces, failures), named by `labels`, in FOLDER (replaced whole): its markdown and PNGs,
    not the HTML page, which repeats the PNGs inline. The runs' folders are named from the study's (STUDY/...), so
    the report says nothing of the machine it ran on."""
    from culinarycut.bench.report import write_report
    if folder.exists():
        shutil.rmtree(folder)
    names = [f"STUDY/{run.resolve().relative_to(study_root.resolve())}" for run in runs]
    write_report(runs, folder, labels=labels, folder_names=names)
    (folder / "report.html").unlink()

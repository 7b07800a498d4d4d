"""A force dataset on disk: DIR/dataset.json (format, version, provenance, the sweep) and DIR/samples.jsonl
(one row per cut). Rows are appended one write each and fsynced, so a killed run loses only the cuts in
flight; a rerun with the same DIR runs only the samples not recorded yet."""
from __future__ import annotations

import hashlib
import json
import os
import platform
import shutil
import tempfile
import time
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path

from culinarycut.safety.binary import engine_files, snapshot_cc_cut
from culinarycut.safety.cut_run import CutFailed, run_sample
from culinarycut.safety.sweep import Sample, Sweep

FORMAT = "culinarycut.safety.force_dataset"
VERSION = 1
HEADER_FILE = "dataset.json"
ROWS_FILE = "samples.jsonl"


class DatasetMismatch(ValueError):
    """DIR holds a dataset made with another quality or cut than the one asked for."""


def engine_build(cc_cut: Path) -> str:
    """cc-cut has no version flag: identify the engine by the hash of the binary and its MPM library builds."""
    digest = hashlib.sha256()
    for path in engine_files(cc_cut):
        digest.update(path.read_bytes())
    return f"cc-cut sha256:{digest.hexdigest()[:16]}"


def read_header(directory: Path) -> dict:
    header = json.loads((Path(directory) / HEADER_FILE).read_text())
    if header.get("format") != FORMAT or header.get("version") != VERSION:
        raise DatasetMismatch(f"{directory / HEADER_FILE}: not a {FORMAT} version {VERSION} dataset")
    return header


def read_rows(directory: Path) -> list[dict]:
    """The recorded rows; a last line cut short by a kill is not a row."""
    path = Path(directory) / ROWS_FILE
    if not path.exists():
        return []
    rows = []
    for line in path.read_text().splitlines(keepends=True):
        if line.endswith("\n"):
            rows.append(json.loads(line))
    return rows


def dataset_sha256(directory: Path) -> str:
    return hashlib.sha256((Path(directory) / ROWS_FILE).read_bytes()).hexdigest()


def _drop_partial_line(path: Path) -> None:
    """Cut a line a kill left half written, so the next row starts on its own line."""
    if not path.exists():
        return
    data = path.read_bytes()
    end = data.rfind(b"\n") + 1
    if end != len(data):
        with open(path, "r+b") as f:
            f.truncate(end)


def _append(fd: int, row: dict) -> None:
    os.write(fd, (json.dumps(row, sort_keys=True) + "\n").encode())  # one write: the row is whole or absent
    os.fsync(fd)


def _open_header(directory: Path, sweep: Sweep, cc_cut: Path) -> dict:
    """Write the header of a new dataset, or check that an existing one was made with the same cut."""
    path = directory / HEADER_FILE
    cut = {"quality": sweep.quality, "knife": sweep.knife, "seed": sweep.seed}
    if path.exists():
        header = read_header(directory)
        recorded = {k: header["sweep"][k] for k in cut}
        for name, value in cut.items():
            if recorded[name] != value:
                option = "--quality" if name == "quality" else name
                raise DatasetMismatch(f"{option}: {directory} was made with {name} {recorded[name]!r}, not {value!r}; "
                                      "use another --out")
        build = engine_build(cc_cut)
        if build not in header["engine_builds"]:  # a rebuilt engine: its rows say which one made them
            header["engine_builds"].append(build)
        header["sweeps"] = header.get("sweeps", []) + [sweep.to_json()]
    else:
        header = {"format": FORMAT, "version": VERSION, "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
                  "engine_builds": [engine_build(cc_cut)], "quality": sweep.quality, "sweep": sweep.to_json(),
                  "sweeps": [sweep.to_json()], "host": {"machine": platform.machine(), "system": platform.platform()},
                  "rows": ROWS_FILE}
    _write_header(directory, header)
    return header


def _write_header(directory: Path, header: dict) -> None:
    path = directory / HEADER_FILE
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(header, indent=1) + "\n")
    os.replace(tmp, path)  # the header is whole or the old one


@dataclass
class SweepResult:
    total: int
    already_done: int
    ran: int
    failed: int
    wall_s: float


def run_sweep(sweep: Sweep, directory: Path, cc_cut: Path, workers: int, progress: bool = True) -> SweepResult:
    """Run every sample of the sweep not yet in DIR, `workers` cc-cut processes at a time."""
    from tqdm import tqdm
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    scratch = Path(tempfile.mkdtemp(prefix="culinarycut-safety-"))  # cc-cut's outputs, read and removed per cut
    # Every cut of a run uses this copy: a rebuild of the binary during the run cannot mix two engines.
    cc_cut = snapshot_cc_cut(cc_cut, scratch)
    try:
        header = _open_header(directory, sweep, cc_cut)
    except BaseException:
        shutil.rmtree(scratch, ignore_errors=True)
        raise
    build = engine_build(cc_cut)
    rows_path = directory / ROWS_FILE
    _drop_partial_line(rows_path)
    done = {row["key"] for row in read_rows(directory)}
    samples = sweep.samples()
    todo = [s for s in samples if s.key() not in done]
    # Slow cuts first: a stiff food at a low speed takes the most substeps, so the pool ends together.
    todo.sort(key=lambda s: s.youngs_modulus_mpa ** 0.5 * s.scale / s.speed_m_s, reverse=True)
    started = time.perf_counter()
    started_at = datetime.now(timezone.utc).isoformat(timespec="seconds")
    failed = 0
    cut_wall_s = 0.0  # the cuts' own wall time, summed over the workers
    fd = os.open(rows_path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
    try:
        with ThreadPoolExecutor(max_workers=workers) as pool, \
                tqdm(total=len(samples), initial=len(samples) - len(todo), unit="cut", disable=not progress,
                     desc="safety dataset") as bar:
            pending = {pool.submit(run_sample, cc_cut, sweep, s, scratch / f"{i}"): s for i, s in enumerate(todo)}
            try:
                while pending:
                    finished, _ = wait(pending, return_when=FIRST_COMPLETED)
                    for future in finished:
                        sample: Sample = pending.pop(future)
                        try:
                            row = future.result()
                        except CutFailed as err:
                            failed += 1
                            bar.write(f"failed: {err}")
                            continue
                        _append(fd, {**row, "engine_build": build, "quality": sweep.quality})
                        cut_wall_s += row["wall_s"]
                        bar.update(1)
            except BaseException:
                for future in pending:
                    future.cancel()
                raise
    finally:
        os.close(fd)
        shutil.rmtree(scratch, ignore_errors=True)
    wall_s = time.perf_counter() - started
    rows = read_rows(directory)
    if rows and "dx_m" not in header:  # the preset's resolution, as the engine resolved it
        header["dx_m"] = rows[0]["dx_m"]
    # What this run did and how long it took: the throughput report (bench/safety_dataset.py) reads it.
    header.setdefault("runs", []).append({
        "started": started_at, "wall_s": round(wall_s, 1), "ran": len(todo) - failed, "failed": failed,
        "workers": workers, "cpu_count": os.cpu_count(), "cut_wall_s": round(cut_wall_s, 1), "engine_build": build})
    _write_header(directory, header)
    return SweepResult(total=len(samples), already_done=len(samples) - len(todo), ran=len(todo) - failed,
                       failed=failed, wall_s=wall_s)

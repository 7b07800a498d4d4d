"""`culinarycut data generate`: the dataset's jobs in shards on Dask workers bound to servers (a local
cluster by default, culinarycut.bench.dispatch), resumable.

Each finished job leaves, in this order, its episode file (kept episodes only) and a row file
rows/<key>.json, both renamed into place whole. The main process records rows in the generation
store as shards finish and, on start, first takes in the row files of a run that was killed before
recording them; a job with a row is never run again, and a job without one is run again from its seed
and overwrites its half-made outputs with the same bytes, so no episode is lost or duplicated.

A server's transient failure (RESOURCE_EXHAUSTED, DEADLINE_EXCEEDED, UNAVAILABLE, INTERNAL) says nothing
about the episode: the job is tried again after a backoff, then on the other servers, and when it
still fails it leaves an error file errors/<key>.json and no row, so the next run of the same command
runs it again and the success filter never counts it.
"""
from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import grpc

from culinarycut.bench.dispatch import _worker_server_order, start_cluster
from culinarycut.bench.runner import _progress
from culinarycut.client import Client
from culinarycut.datasets.demo import write_text_atomic
from culinarycut.datasets.episode_file import episode_path, write_episode
from culinarycut.datasets.jobs import DatasetConfig, EpisodeJob, make_jobs, shards
from culinarycut.datasets.record import record_episode
from culinarycut.datasets.store import GenerationStore
from culinarycut.errors import CulinaryCutError

CONFIG_NAME = "dataset_config.json"
RPC_TIMEOUT_S = 600.0
PROGRESS_POLL_S = 1.0  # how often the progress bar counts the row files the workers have written


TRANSIENT_CODES = frozenset({grpc.StatusCode.RESOURCE_EXHAUSTED, grpc.StatusCode.DEADLINE_EXCEEDED,
                             grpc.StatusCode.UNAVAILABLE, grpc.StatusCode.INTERNAL})


class TransientJobError(RuntimeError):
    """A job the server failed with a transient code on every try."""


@dataclass(frozen=True)
class RetryPolicy:
    attempts: int = 3        # tries of a job on one server
    backoff_s: float = 2.0   # wait before the second try, doubled before each next one

    def __post_init__(self):
        if self.attempts < 1 or self.backoff_s < 0:
            raise ValueError(f"retry: attempts must be >= 1 and backoff_s >= 0 s, got {self}")


@dataclass
class GenerateSummary:
    jobs: int
    already_done: int
    ran: int
    kept: int
    wall_s: float
    errors: int = 0          # jobs left without a row by transient server errors; the next run retries them


def row_path(root: Path, key: str) -> Path:
    return root / "rows" / (key.replace("/", "__") + ".json")


def error_path(root: Path, key: str) -> Path:
    return root / "errors" / (key.replace("/", "__") + ".json")


def _record_with_retries(job: EpisodeJob, config: DatasetConfig, server: str, retry: RetryPolicy):
    """The episode, after up to retry.attempts tries on `server` when it fails with a transient code."""
    for attempt in range(retry.attempts):
        try:
            with Client(server, timeout_s=RPC_TIMEOUT_S) as client:
                return record_episode(job, config, client)
        except CulinaryCutError as err:
            if err.code not in TRANSIENT_CODES:
                raise
            if attempt + 1 == retry.attempts:
                raise TransientJobError(f"{server}: {err.code.name}: {err.details}"[:2000]) from err
            time.sleep(retry.backoff_s * 2 ** attempt)
    raise AssertionError("unreachable")


def run_job(job: EpisodeJob, config: DatasetConfig, root: Path, server: str,
            retry: RetryPolicy = RetryPolicy()) -> dict:
    """One job on `server`; a request the server refuses (e.g. a plan it cannot make for the drawn object)
    is a rejected job with the server's reason. TransientJobError goes up when transient failures
    outlast the retries: the job moves to another server, and leaves no row."""
    started = time.perf_counter()
    row = {"key": job.key, "seed": job.seed, "source": job.source, "kept": 0, "steps": 0, "file": None,
           "server": server, "scene": job.variation["scene"]}
    try:
        episode = _record_with_retries(job, config, server, retry)
    except TransientJobError:
        raise
    except CulinaryCutError as err:
        row["reason"] = f"server_error: {err.code.name}: {err.details}"[:2000]
    else:
        if episode.success:
            path = episode_path(root, job.key)
            write_episode(path, episode.meta, episode.steps)
            row["file"] = str(path.relative_to(root))
        row.update(kept=int(episode.success), reason=episode.reason, steps=len(episode.steps.get("rewards", ())))
    row["wall_s"] = time.perf_counter() - started
    write_text_atomic(row_path(root, job.key), json.dumps(row, sort_keys=True))
    error_path(root, job.key).unlink(missing_ok=True)
    return row


def generate_shard(jobs: list[EpisodeJob], config_json: str, root: str, servers: list[str],
                   retry: RetryPolicy = RetryPolicy()) -> list[dict]:
    """Runs on a Dask worker: the shard's jobs that have no row file yet, on this worker's server first.
    A job every server failed transiently comes back as {"key", "error"} with an error file, no row."""
    config, root_path = DatasetConfig.from_json(config_json), Path(root)
    rows = []
    for job in jobs:
        existing = row_path(root_path, job.key)
        if existing.is_file():
            rows.append(json.loads(existing.read_text()))
            continue
        failures = []
        for server in _worker_server_order(servers):
            try:
                rows.append(run_job(job, config, root_path, server, retry))
                break
            except TransientJobError as err:
                failures.append(str(err))
        else:
            error = {"key": job.key, "error": "; ".join(failures)}
            write_text_atomic(error_path(root_path, job.key), json.dumps(error, sort_keys=True))
            rows.append(error)
    return rows


def count_files(folder: Path, pattern: str) -> int:
    return sum(1 for _ in folder.glob(pattern)) if folder.is_dir() else 0


def ingest_row_files(store: GenerationStore, root: Path) -> int:
    folder = root / "rows"
    added = 0
    for path in sorted(folder.glob("*.json")) if folder.is_dir() else ():  # only finished jobs have rows
        added += store.record(json.loads(path.read_text()))
    return added


def generate(config: DatasetConfig, root: Path, servers: list[str], *, workers: int = 1, shard_size: int = 4,
             scheduler: str | None = None, progress: bool = True,
             provenance: dict | None = None, retry: RetryPolicy = RetryPolicy()) -> GenerateSummary:
    """Runs the jobs without a row; `provenance` (e.g. server versions) is kept in the store for the card."""
    started = time.perf_counter()
    root.mkdir(parents=True, exist_ok=True)
    jobs = make_jobs(config)
    with GenerationStore(root) as store:
        store.claim_config(config.to_json(), {"jobs": len(jobs), **(provenance or {})})
        (root / CONFIG_NAME).write_text(json.dumps(json.loads(config.to_json()), indent=2, sort_keys=True))
        ingest_row_files(store, root)
        done = store.done_keys()
        pending = [job for job in jobs if job.key not in done]
        already, ran, errors = len(jobs) - len(pending), 0, 0
        bar = _progress(len(jobs), already, progress)
        dask_client = cluster = None
        try:
            if pending:
                dask_client, cluster = start_cluster(scheduler, workers)
                from distributed import wait
                run_started, rows_before = time.perf_counter(), count_files(root / "rows", "*.json")
                kept_before = count_files(root / "episodes", "*.h5")
                futures = [dask_client.submit(generate_shard, shard, config.to_json(), str(root), servers,
                                              retry, retries=2, pure=False, key=f"shard-{i}-{shard[0].key}")
                           for i, shard in enumerate(shards(pending, shard_size))]
                while futures:
                    try:
                        wait(futures, timeout=PROGRESS_POLL_S, return_when="FIRST_COMPLETED")
                    except TimeoutError:
                        pass  # no shard done yet: the bar still moves with each episode's row file
                    for future in [f for f in futures if f.done()]:
                        for row in future.result():
                            if "error" in row:
                                errors += 1
                                continue
                            ran += store.record(row)
                    futures = [f for f in futures if not f.done()]
                    finished = count_files(root / "rows", "*.json") - rows_before  # episode by episode
                    bar.update(max(0, already + finished - bar.n))
                    hours = (time.perf_counter() - run_started) / 3600.0
                    kept_now = count_files(root / "episodes", "*.h5") - kept_before
                    bar.set_postfix_str(f"{finished / max(hours, 1e-9):.0f} episodes/h, kept {kept_now}/{finished}"
                                        + (f", {errors} errors" if errors else ""))
        finally:
            bar.close()
            if dask_client is not None:
                dask_client.close()
            if cluster is not None:
                cluster.close()
        kept = len(store.rows(kept_only=True))
    return GenerateSummary(jobs=len(jobs), already_done=already, ran=ran, kept=kept,
                           wall_s=time.perf_counter() - started, errors=errors)

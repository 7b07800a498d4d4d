"""`culinarycut bench run`: every episode of a suite that has no row yet (with --retry-errors, also those
whose row is an error), on one or more servers through Dask, each result stored as it ends; a progress
bar; Ctrl-C, a lost server, a policy that keeps failing, a storage fault or a failed task stops cleanly and
says how to resume."""
from __future__ import annotations

import json
import shlex
import sys
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path

from culinarycut.bench.dispatch import AllServersLost, WorkerResult, run_on_worker, start_cluster
from culinarycut.bench.episode import EpisodeOptions
from culinarycut.bench.episode_scene import suite_episodes
from culinarycut.bench.policy_error_streak import DEFAULT_MAX_CONSECUTIVE_POLICY_ERRORS, PolicyErrorStreak
from culinarycut.bench.preflight import (auto_workers, check_policy_ready, check_qualities, check_tasks, server_infos,
                                         server_versions)
from culinarycut.bench.run_errors import BadRunInput, RunError
from culinarycut.bench.storage_faults import storage_faults
from culinarycut.bench.store import DATABASE_NAME, ResultStore
from culinarycut.bench.suite import Suite
from culinarycut.policies.registry import UnknownPolicy, make_policy


@dataclass
class RunConfig:
    suite: Suite
    servers: list[str]
    out: Path
    policy: str
    policy_options: dict = field(default_factory=dict)
    workers: int | None = 1  # None: as many as the servers' cores (preflight.auto_workers)
    scheduler: str | None = None
    record_failures: bool = False
    allow_mixed_versions: bool = False
    retry_errors: bool = False       # rerun the episodes stored with outcome error, replacing their rows
    act_timeout_s: float = 60.0
    # Stop after this many policy_error episodes in a row (a model server gone); 0: never.
    max_consecutive_policy_errors: int = DEFAULT_MAX_CONSECUTIVE_POLICY_ERRORS
    progress: bool = True
    command_line: str = ""  # how this run was started, for the resume hint


@dataclass
class RunSummary:
    episodes: int          # in the suite
    already_done: int      # found in the store at the start
    ran: int               # recorded by this run
    retried: int           # of those, stored errors run again (--retry-errors)
    successes: int         # of all stored episodes
    wall_s: float
    interrupted: bool = False
    errors: dict[str, int] = field(default_factory=dict)  # the suite's episodes stored as errors, by end_reason


def _version_text(version: tuple[str, str, str]) -> str:
    return f"{version[0]} (build {version[1] or '?'}, {version[2] or 'simd ?'})"


def check_versions(versions: dict[str, tuple[str, str, str]], store: ResultStore,
                   allow_mixed: bool) -> set[tuple[str, str, str]] | None:
    """The (version, build id, instruction set) triples this run may store: the servers' and the stored
    rows', which must be one unless mixing is allowed (then None: any)."""
    distinct = set(versions.values()) | {tuple(v) for v in store.server_versions()}
    if allow_mixed:
        return None
    if len(distinct) > 1:
        listed = "; ".join(f"{s}: {_version_text(v)}" for s, v in versions.items())
        stored = ", ".join(_version_text(v) for v in store.server_versions()) or "none"
        raise RunError(f"servers of different versions, builds or instruction sets would mix in one run: {listed}; "
                       f"already stored: {stored}. Use one build at one --simd level, another --out, or "
                       "--allow-mixed-versions")
    return distinct


def check_row_version(row: dict, allowed: set[tuple[str, str, str]] | None, stored: int, resume: str) -> None:
    """An episode from a server of another version, build or instruction set than the run's stops the run before it is
    stored: a worker bound by CULINARYCUT_SERVER to a server the pre-flight check never asked. A row
    without a version (the server failed before it said) has nothing to compare."""
    version = (row.get("server_version") or "", row.get("build_id") or "", row.get("simd") or "")
    if allowed is None or not version[0] or version in allowed:
        return
    raise RunError(f"episode {row['task']} trial {row['trial']} ran on {row['server']}, "
                   f"{_version_text(version)}, but this run's servers and rows are "
                   f"{', '.join(sorted(_version_text(v) for v in allowed))}: a Dask worker bound by "
                   f"CULINARYCUT_SERVER to another build? It was not stored ({stored} episodes are). Point every "
                   f"worker at one build and resume with:\n  {resume}\nor pass --allow-mixed-versions")


def check_identity(store: ResultStore, config: RunConfig) -> None:
    """A run folder belongs to one suite (as it was) and one policy with its options."""
    identity = {"suite": config.suite.name, "suite_sha256": config.suite.digest, "policy": config.policy,
                "policy_options": json.dumps(config.policy_options, sort_keys=True)}
    stored = store.metadata()
    for key, value in identity.items():
        if key in stored and stored[key] != value:
            raise RunError(f"{config.out} holds a run with {key} = {stored[key]}, not {value}; "
                           "use another --out for a different suite, policy or suite file")
    store.set_metadata({**identity, "schema": "1", "started_at": stored.get("started_at", str(time.time()))})


def _progress(total: int, done: int, enabled: bool):
    from tqdm import tqdm
    return tqdm(total=total, initial=done, unit="episode", disable=not enabled, dynamic_ncols=True,
                smoothing=0.1, file=sys.stderr)


def _video_name(task: str, trial: int) -> str:
    return "videos/" + task.replace("/", "_") + f"_trial{trial}.gif"


def _store_result(store: ResultStore, out: Path, done: WorkerResult, retrying: bool) -> bool:
    """Writes the episode's video (if any) and row; `retrying` replaces the episode's stored error row."""
    row = done.result.row
    video = out / _video_name(row["task"], row["trial"])
    if done.video_gif:
        video.parent.mkdir(exist_ok=True)
        video.write_bytes(done.video_gif)
        row["video"] = _video_name(row["task"], row["trial"])
    elif retrying:
        video.unlink(missing_ok=True)  # the failed attempt's video would not belong to the new row
    return store.record(row, done.result.trace, replace_error=retrying)


def _task_failure(err: Exception, episode: str, stored: int, total: int, resume: str) -> RunError:
    """A clear RunError for an episode task that failed on its worker (not a recorded episode fault)."""
    from distributed import KilledWorker
    where = f"{stored} of {total} episodes are stored; resume with:\n  {resume}"
    if isinstance(err, AllServersLost):
        return RunError(f"the servers stopped answering ({err}); start them again. {where}")
    if isinstance(err, KilledWorker):
        return RunError(f"{episode}: the Dask workers running it died (out of memory or killed) more often than "
                        f"the scheduler allows (distributed.scheduler.allowed-failures). {where}")
    frames = traceback.extract_tb(err.__traceback__)
    at = f" (at {Path(frames[-1].filename).name} line {frames[-1].lineno}, in {frames[-1].name})" if frames else ""
    return RunError(f"{episode} failed on its worker: {type(err).__name__}: {err}{at}. {where}")


def _stored_errors(store: ResultStore, episodes) -> dict[str, int]:
    """The suite's episodes stored with outcome error, counted by end_reason."""
    keys = {e.key for e in episodes}
    counts: dict[str, int] = {}
    for row in store.episodes("outcome = 'error'"):
        if (row["task"], row["trial"]) in keys:
            counts[row["end_reason"]] = counts.get(row["end_reason"], 0) + 1
    return counts


def run_suite(config: RunConfig) -> RunSummary:
    """Runs what is missing of the suite (and, with retry_errors, what is stored as an error). Raises
    BadRunInput for an unknown policy or bad options and RunError when the run cannot start or go on
    (servers down or lost, a policy not ready or failing episode after episode, another run's folder, mixed
    versions, an episode task that failed), StorageFault when the run folder cannot be written or read."""
    started = time.perf_counter()
    try:
        policy = make_policy(config.policy, config.policy_options)  # unknown names and bad options fail here
    except (UnknownPolicy, ValueError) as err:
        raise BadRunInput(str(err)) from None
    infos = server_infos(config.servers)
    versions = server_versions(infos)
    resume = config.command_line or "the same command"
    database, resume_step = config.out / DATABASE_NAME, f"resume with: {resume}"
    with storage_faults(database, resume_step):
        store = ResultStore(config.out)
    with store:
        with storage_faults(database, resume_step):
            check_identity(store, config)
            episodes = suite_episodes(config.suite)
            retry_keys = store.error_keys() if config.retry_errors else set()
            done_keys = store.done_keys() - retry_keys
            pending = [e for e in episodes if e.key not in done_keys]
            # A finished run looked at again from another build stores nothing, so nothing can mix.
            allowed = check_versions(versions, store, config.allow_mixed_versions) if pending else None
            successes = len(store.episodes("outcome = 'success'"))
        check_qualities(infos, config.suite)
        check_tasks(config.servers[0], config.suite)
        already = len(episodes) - len(pending)
        if pending:
            check_policy_ready(config.policy, policy)
        options = EpisodeOptions(policy=config.policy, policy_options=config.policy_options,
                                 act_timeout_s=config.act_timeout_s, record_video=config.record_failures)
        streak = PolicyErrorStreak(config.max_consecutive_policy_errors)
        ran = retried = 0
        interrupted = False
        bar = _progress(len(episodes), already, config.progress)
        dask_client = cluster = None
        try:
            if pending:
                workers = config.workers or auto_workers(infos)
                dask_client, cluster = start_cluster(config.scheduler, workers)
                from distributed import as_completed
                futures = {dask_client.submit(run_on_worker, spec, config.servers, options, retries=2, pure=False,
                                              key=f"episode-{spec.task.name}-{spec.trial}"): spec
                           for spec in pending}
                for future in as_completed(futures):
                    try:
                        done = future.result()
                    except Exception as err:  # AllServersLost, KilledWorker, a bug in a policy or the harness
                        spec = futures[future]
                        raise _task_failure(err, f"episode {spec.task.name} trial {spec.trial}",
                                            len(store.done_keys()), len(episodes), resume) from None
                    row = done.result.row
                    check_row_version(row, allowed, len(store.done_keys()), resume)
                    retrying = (row["task"], row["trial"]) in retry_keys
                    with storage_faults(database, resume_step):
                        recorded = _store_result(store, config.out, done, retrying)
                    if recorded:
                        ran += 1
                        retried += retrying
                        successes += row["outcome"] == "success"
                        streak.add(row, already + ran, len(episodes), resume)
                    bar.update(1)
                    stored = already + ran
                    bar.set_postfix_str(f"success {successes}/{stored} ({100.0 * successes / max(1, stored):.0f} %)")
        except KeyboardInterrupt:
            interrupted = True
        finally:
            bar.close()
            if dask_client is not None:
                dask_client.close()
            if cluster is not None:
                cluster.close()
        with storage_faults(database, resume_step):
            stored = len(store.done_keys())
            errors = _stored_errors(store, episodes)
        if interrupted:
            print(f"\nstopped: {stored} of {len(episodes)} episodes are stored in {config.out}; "
                  f"resume with:\n  {resume}", file=sys.stderr)
    return RunSummary(episodes=len(episodes), already_done=already, ran=ran, retried=retried, successes=successes,
                      wall_s=time.perf_counter() - started, interrupted=interrupted, errors=errors)


def command_line(argv: list[str]) -> str:
    return "culinarycut " + " ".join(shlex.quote(a) for a in argv)

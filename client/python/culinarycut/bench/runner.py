"""`culinarycut bench run`: every episode of a suite that has no row yet, on one or more servers through
Dask, each result stored as it ends; a progress bar; Ctrl-C stops cleanly and says how to resume."""
from __future__ import annotations

import json
import shlex
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from culinarycut.bench.dispatch import AllServersLost, WorkerResult, run_on_worker, start_cluster
from culinarycut.bench.episode import EpisodeOptions
from culinarycut.bench.episode_scene import suite_episodes
from culinarycut.bench.store import ResultStore
from culinarycut.bench.suite import Suite
from culinarycut.client import Client
from culinarycut.errors import CulinaryCutError
from culinarycut.policies.registry import make_policy

PREFLIGHT_TIMEOUT_S = 10.0


class RunError(RuntimeError):
    """The run cannot start (or go on); the message says why and what to do."""


@dataclass
class RunConfig:
    suite: Suite
    servers: list[str]
    out: Path
    policy: str
    policy_options: dict = field(default_factory=dict)
    workers: int = 1
    scheduler: str | None = None
    record_failures: bool = False
    allow_mixed_versions: bool = False
    act_timeout_s: float = 60.0
    progress: bool = True
    command_line: str = ""  # how this run was started, for the resume hint


@dataclass
class RunSummary:
    episodes: int          # in the suite
    already_done: int      # found in the store at the start
    ran: int               # recorded by this run
    successes: int         # of all stored episodes
    wall_s: float
    interrupted: bool = False


def server_versions(servers: list[str]) -> dict[str, tuple[str, str]]:
    """(version, build id) of each server; RunError naming any that does not answer."""
    versions = {}
    for server in servers:
        try:
            with Client(server, timeout_s=PREFLIGHT_TIMEOUT_S) as client:
                info = client.server_info()
        except CulinaryCutError as err:
            raise RunError(f"server {server} is not reachable ({err.code.name}: {err.details}); start it with "
                           f"culinarycut-server --listen {server}, or pass the right --server") from None
        versions[server] = (info.version, info.build_id)
    return versions


def check_versions(versions: dict[str, tuple[str, str]], store: ResultStore, allow_mixed: bool) -> None:
    distinct = set(versions.values()) | {tuple(v) for v in store.server_versions()}
    if len(distinct) > 1 and not allow_mixed:
        listed = "; ".join(f"{s}: {v} (build {b or '?'})" for s, (v, b) in versions.items())
        stored = ", ".join(f"{v} (build {b or '?'})" for v, b in store.server_versions()) or "none"
        raise RunError(f"servers of different versions would mix in one run: {listed}; already stored: {stored}. "
                       "Use one build, another --out, or --allow-mixed-versions")


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


def check_tasks(server: str, suite: Suite) -> None:
    """Every task can be said in its language split (one instruction each), before any episode runs."""
    with Client(server, timeout_s=PREFLIGHT_TIMEOUT_S) as client:
        for task in suite.tasks:
            try:
                client.tasks.generate_instructions(task.cut_spec(), seed=0, count=1, split=task.language)
            except CulinaryCutError as err:
                raise RunError(f"suite {suite.name}, task {task.name}: {err.details}") from None


def _progress(total: int, done: int, enabled: bool):
    from tqdm import tqdm
    return tqdm(total=total, initial=done, unit="episode", disable=not enabled, dynamic_ncols=True,
                smoothing=0.1, file=sys.stderr)


def _video_name(task: str, trial: int) -> str:
    return "videos/" + task.replace("/", "_") + f"_trial{trial}.gif"


def _store_result(store: ResultStore, out: Path, done: WorkerResult) -> bool:
    row = done.result.row
    if done.video_gif:
        name = _video_name(row["task"], row["trial"])
        (out / name).parent.mkdir(exist_ok=True)
        (out / name).write_bytes(done.video_gif)
        row["video"] = name
    return store.record(row, done.result.trace)


def run_suite(config: RunConfig) -> RunSummary:
    """Runs what is missing of the suite; raises RunError before any episode when it cannot start."""
    started = time.perf_counter()
    make_policy(config.policy, config.policy_options)  # unknown names and bad options fail here
    versions = server_versions(config.servers)
    with ResultStore(config.out) as store:
        check_identity(store, config)
        check_versions(versions, store, config.allow_mixed_versions)
        check_tasks(config.servers[0], config.suite)
        episodes = suite_episodes(config.suite)
        done_keys = store.done_keys()
        pending = [e for e in episodes if e.key not in done_keys]
        already = len(episodes) - len(pending)
        options = EpisodeOptions(policy=config.policy, policy_options=config.policy_options,
                                 act_timeout_s=config.act_timeout_s, record_video=config.record_failures)
        successes = len(store.episodes("outcome = 'success'"))
        ran = 0
        interrupted = False
        bar = _progress(len(episodes), already, config.progress)
        dask_client = cluster = None
        try:
            if pending:
                dask_client, cluster = start_cluster(config.scheduler, config.workers)
                from distributed import as_completed
                futures = [dask_client.submit(run_on_worker, spec, config.servers, options, retries=2, pure=False,
                                              key=f"episode-{spec.task.name}-{spec.trial}")
                           for spec in pending]
                for future in as_completed(futures):
                    try:
                        done = future.result()
                    except AllServersLost as err:
                        raise RunError(f"the servers stopped answering ({err}); start them again and rerun "
                                       "the same command to resume") from None
                    if _store_result(store, config.out, done):
                        ran += 1
                        successes += done.result.row["outcome"] == "success"
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
        if interrupted:
            stored = already + ran
            print(f"\nstopped: {stored} of {len(episodes)} episodes are stored in {config.out}; "
                  f"resume with:\n  {config.command_line or 'the same command'}", file=sys.stderr)
    return RunSummary(episodes=len(episodes), already_done=already, ran=ran, successes=successes,
                      wall_s=time.perf_counter() - started, interrupted=interrupted)


def command_line(argv: list[str]) -> str:
    return "culinarycut " + " ".join(shlex.quote(a) for a in argv)

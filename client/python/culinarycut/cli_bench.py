"""`culinarycut bench`: list suites, run one against servers, report on stored runs."""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from culinarycut.bench.policy_error_streak import DEFAULT_MAX_CONSECUTIVE_POLICY_ERRORS

# Exit codes of `bench run` (the table in docs/evaluation.md).
EXIT_CLEAN = 0            # every episode of the suite is stored, none as an error
EXIT_RUN_FAILED = 1       # could not start or go on: servers down or lost, policy not ready or failing in a row, ...
EXIT_USAGE = 2            # unknown suite, task field or policy; bad options
EXIT_EPISODE_ERRORS = 3   # every episode ran, but some are stored as errors (policy_error, server_error)
EXIT_STORAGE = 4          # the run folder cannot be written or read: read-only, disk full, corrupt database
EXIT_INTERRUPTED = 130


class UsageError(ValueError):
    """A bad command-line value (the message names it)."""


def _policy_options(pairs: list[str]) -> dict:
    """key=value pairs; values are read as JSON where they parse (numbers, booleans), else as text."""
    options = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            raise UsageError(f"--policy-option {pair!r}: use key=value")
        try:
            options[key] = json.loads(value)
        except json.JSONDecodeError:
            options[key] = value
    return options


def cmd_list(args) -> int:
    from culinarycut.bench.suite import available_suites, load_suite
    for name in available_suites():
        suite = load_suite(name)
        print(f"{name:<20} {len(suite.tasks):4d} tasks {suite.episode_count:6d} episodes  {suite.description}")
    return 0


def cmd_show(args) -> int:
    from culinarycut.bench.suite import load_suite
    suite = load_suite(args.suite)
    print(f"{suite.name}: {suite.description}\npolicy {suite.policy['name']}, {suite.episode_count} episodes")
    for task in suite.tasks:
        print(f"  {task.name:<48} {task.trials:3d} trials  {task.quality} {task.language} "
              f"max {task.max_episode_steps} steps")
    return 0


def cmd_run(args) -> int:
    from culinarycut.bench.run_errors import BadRunInput, RunError, StorageFault, retry_errors_command
    from culinarycut.bench.runner import RunConfig, command_line, run_suite
    from culinarycut.bench.storage_faults import storage_faults
    from culinarycut.bench.store import DATABASE_NAME, ResultStore
    from culinarycut.bench.suite import load_suite
    from culinarycut.bench.tables import results_text
    suite = load_suite(args.suite)
    if args.trials:
        suite = suite.with_trials(args.trials)
    if args.tasks:
        suite = suite.only_tasks(args.tasks)
    policy = args.policy or suite.policy["name"]
    options = suite.policy.get("options", {}) if args.policy in (None, suite.policy["name"]) else {}
    options = {**options, **_policy_options(args.policy_option)}
    if args.policy_url:
        options["url"] = args.policy_url
    out = Path(args.out or f"runs/{suite.name}-{policy.replace(':', '-')}")
    config = RunConfig(suite=suite, servers=args.server, out=out, policy=policy, policy_options=options,
                       workers=args.workers, scheduler=args.scheduler, record_failures=args.record_failures,
                       allow_mixed_versions=args.allow_mixed_versions, retry_errors=args.retry_errors,
                       act_timeout_s=args.act_timeout,
                       max_consecutive_policy_errors=args.max_consecutive_policy_errors,
                       progress=not args.no_progress, command_line=command_line(args.argv))
    try:
        summary = run_suite(config)
        with storage_faults(out / DATABASE_NAME, f"resume with: {config.command_line}"), ResultStore(out) as store:
            rows = store.episodes()
    except BadRunInput as err:  # only the run's input: a ValueError from inside a run is no usage error
        print(f"error: {err}", file=sys.stderr)
        return EXIT_USAGE
    except StorageFault as err:
        print(f"error: {err}", file=sys.stderr)
        return EXIT_STORAGE
    except RunError as err:
        print(f"error: {err}", file=sys.stderr)
        return EXIT_RUN_FAILED
    print(results_text(rows, f"{suite.name} with {policy}: {len(rows)} of {summary.episodes} episodes in {out}"))
    retried = f", {summary.retried} stored errors run again" if summary.retried else ""
    print(f"this run: {summary.ran} episodes in {summary.wall_s:.1f} s ({summary.already_done} were already stored"
          f"{retried})")
    if summary.interrupted:
        return EXIT_INTERRUPTED
    if summary.errors:
        counts = ", ".join(f"{count} {reason}" for reason, count in sorted(summary.errors.items()))
        print(f"error: not every episode ran cleanly: {counts} stored (each row's error column says why); "
              f"run them again with:\n  {retry_errors_command(config.command_line)}", file=sys.stderr)
        return EXIT_EPISODE_ERRORS
    return EXIT_CLEAN


def cmd_report(args) -> int:
    from culinarycut.bench.report import ReportError, write_report
    from culinarycut.bench.run_errors import StorageFault
    try:
        written = write_report([Path(d) for d in args.runs], Path(args.out) if args.out else None)
    except ReportError as err:
        print(f"error: {err}", file=sys.stderr)
        return EXIT_USAGE
    except StorageFault as err:
        print(f"error: {err}", file=sys.stderr)
        return EXIT_STORAGE
    for path in written:
        print(f"wrote {path}")
    return 0


def register(sub) -> None:
    bench = sub.add_parser("bench", help="benchmark suites: list, show, run, report")
    bench.set_defaults(func=run_command, timeout=30.0)
    commands = bench.add_subparsers(dest="bench_command", required=True, metavar="{list,show,run,report}")
    listing = commands.add_parser("list", help="the suites found under benchmarks/")
    listing.set_defaults(bench_func=cmd_list)
    show = commands.add_parser("show", help="a suite's tasks")
    show.add_argument("suite", help="suite name or .toml path")
    show.set_defaults(bench_func=cmd_show)

    run = commands.add_parser("run", help="run a suite's missing episodes against one or more servers")
    run.add_argument("suite", help="suite name (see `culinarycut bench list`) or .toml path")
    run.add_argument("--policy", help="policy name (oracle, random, noop, grpc, an installed plugin's or "
                                      "module:Class); default: the suite's")
    run.add_argument("--policy-option", action="append", default=[], metavar="KEY=VALUE",
                     help="an option for the policy's constructor (repeatable)")
    run.add_argument("--policy-url", metavar="URL",
                     help="where a remote policy's model server listens (the option url), e.g. "
                          "http://HOST:8000 for openvla, ws://HOST:8000 for octo, rdt, openpi (docs/policies.md), "
                          "HOST:PORT for grpc (docs/policy_protocol.md)")
    run.add_argument("--server", action="append", metavar="HOST:PORT",
                     help="a culinarycut-server (repeatable; default 127.0.0.1:50051)")
    run.add_argument("--workers", type=_workers, default=None, metavar="N|auto",
                     help="episodes at once (default auto: one per core the servers' Steps share, so each Step's "
                          "MPM runs one thread; at most 16)")
    run.add_argument("--scheduler", help="a Dask scheduler, tcp://HOST:PORT (default: a local cluster)")
    run.add_argument("--out", help="run folder: results.sqlite and videos (default runs/SUITE-POLICY); "
                                   "an existing one is resumed")
    run.add_argument("--trials", type=int, help="trials per task instead of the suite's (a quick look)")
    run.add_argument("--tasks", metavar="PATTERN", help="only the tasks whose name matches this shell pattern, "
                                                        "e.g. 'cucumber/*'")
    run.add_argument("--record-failures", action="store_true", help="keep a short video of each failed episode")
    run.add_argument("--allow-mixed-versions", action="store_true",
                     help="let servers of different versions (or builds) add to one run")
    run.add_argument("--retry-errors", action="store_true",
                     help="also rerun the episodes stored with outcome error (server_error, e.g. a deadline or "
                          "RESOURCE_EXHAUSTED, or policy_error), replacing their rows")
    run.add_argument("--act-timeout", type=float, default=60.0,
                     help="s a policy may take for one action before the episode is a policy_error")
    run.add_argument("--max-consecutive-policy-errors", type=int, default=DEFAULT_MAX_CONSECUTIVE_POLICY_ERRORS,
                     metavar="N", help="stop the run after N policy_error episodes in a row, e.g. a model server "
                                       "gone (default %(default)s; 0: never)")
    run.add_argument("--no-progress", action="store_true", help="no progress bar")
    run.set_defaults(bench_func=cmd_run)

    report = commands.add_parser("report", help="Markdown and HTML report of one run, or of several side by side")
    report.add_argument("runs", nargs="+", help="run folders (from bench run --out)")
    report.add_argument("--out", help="report folder (default: the first run's folder)")
    report.set_defaults(bench_func=cmd_report)


def _workers(text: str) -> int | None:
    """--workers: a count, or auto (None)."""
    if text == "auto":
        return None
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of workers or auto") from None


def validate_run_args(args) -> str | None:
    """A message for bad run arguments, or None."""
    if args.workers is not None and args.workers < 1:
        return "--workers must be at least 1, or auto"
    if args.trials is not None and args.trials < 1:
        return "--trials must be at least 1"
    if args.act_timeout <= 0:
        return "--act-timeout must be positive"
    if args.max_consecutive_policy_errors < 0:
        return "--max-consecutive-policy-errors must be 0 (never stop) or more"
    if not args.server:
        args.server = ["127.0.0.1:50051"]
    return None


def run_command(args) -> int:
    """Entry for the bench commands: usage errors exit 2 with a message."""
    if args.bench_command == "run":
        problem = validate_run_args(args)
        if problem:
            print(f"error: {problem}", file=sys.stderr)
            return EXIT_USAGE
    from culinarycut.bench.suite import SuiteError
    try:
        return args.bench_func(args)
    except (SuiteError, UsageError) as err:  # an unknown suite or task pattern, a bad --policy-option
        print(f"error: {err}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        return EXIT_INTERRUPTED


__all__ = ["register", "run_command"]

"""Checks before a run's first episode: every server answers (and says its version), every task's quality is a
preset the servers have, every task can be said in its language split, and the policy is ready (a remote model's
server answers its handshake)."""
from __future__ import annotations

from culinarycut.bench.run_errors import RunError
from culinarycut.bench.suite import Suite
from culinarycut.client import Client
from culinarycut.errors import CulinaryCutError
from culinarycut.policies.base import Policy

PREFLIGHT_TIMEOUT_S = 10.0


def server_infos(servers: list[str]) -> dict:
    """Each server's ServerInfo; RunError naming any that does not answer."""
    infos = {}
    for server in servers:
        try:
            with Client(server, timeout_s=PREFLIGHT_TIMEOUT_S) as client:
                infos[server] = client.server_info()
        except CulinaryCutError as err:
            raise RunError(f"server {server} is not reachable ({err.code.name}: {err.details}); start it with "
                           f"culinarycut-server --listen {server}, or pass the right --server") from None
    return infos


def server_versions(infos: dict) -> dict[str, tuple[str, str, str]]:
    """(version, build id, instruction set of its MPM kernels) of each server: results are the same bits only
    where all three are."""
    return {server: (info.version, info.build_id, info.simd) for server, info in infos.items()}


MAX_AUTO_WORKERS = 16
OLD_SERVER_WORKERS = 2  # a server too old to say how many cores its Steps share


def auto_workers(infos: dict) -> int:
    """Episodes at once that keep every server's cores busy without oversubscribing them: one per core its
    Steps share (each Step's MPM then runs one thread), within the sessions it has free; at most 16."""
    total = 0
    for info in infos.values():
        limits = info.limits
        cores = limits.step_cores or OLD_SERVER_WORKERS
        free_sessions = max(1, limits.max_sessions - limits.active_sessions)
        total += max(1, min(cores, free_sessions))
    return max(1, min(MAX_AUTO_WORKERS, total))


def check_qualities(infos: dict, suite: Suite) -> None:
    """Every task's quality is a preset of every server (the engine is the presets' one source, so the suite
    schema keeps no copy of their names)."""
    for server, info in infos.items():
        names = [preset.name for preset in info.quality_presets]
        for task in suite.tasks:
            if names and task.quality not in names:  # a server too old to publish its presets: it refuses the scene
                raise RunError(f"suite {suite.name}, task {task.name}: quality {task.quality!r} is not a preset of "
                               f"server {server} (it has {', '.join(names)})")


def check_tasks(server: str, suite: Suite) -> None:
    """Every task can be said in its language split (one instruction each), before any episode runs."""
    with Client(server, timeout_s=PREFLIGHT_TIMEOUT_S) as client:
        for task in suite.tasks:
            try:
                client.tasks.generate_instructions(task.cut_spec(), seed=0, count=1, split=task.language)
            except CulinaryCutError as err:
                raise RunError(f"suite {suite.name}, task {task.name}: {err.details}") from None


def check_policy_ready(name: str, policy: Policy) -> None:
    """Runs the policy's optional `preflight()` (a remote model's handshake with its server); a failure
    stops the run before its first episode instead of storing every episode as a policy_error."""
    preflight = getattr(policy, "preflight", None)
    if preflight is None:
        return
    try:
        preflight()
    except Exception as err:  # whatever the policy raises: it is not ready
        reason = " ".join(str(err).split())  # one line: a model server's traceback may span many
        raise RunError(f"policy {name} is not ready, no episode was run: {type(err).__name__}: {reason}; start "
                       "its model server or pass the right --policy-url") from None

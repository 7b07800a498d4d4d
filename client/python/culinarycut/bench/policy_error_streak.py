"""Stopping a run whose policy keeps failing: after N policy_error episodes in a row (a model server that
went away, a policy broken for every task) the run stops instead of storing an error row for every
episode left."""
from __future__ import annotations

from culinarycut.bench.run_errors import RunError, retry_errors_command

DEFAULT_MAX_CONSECUTIVE_POLICY_ERRORS = 5


class PolicyErrorStreak:
    """Counts the policy_error episodes in a row, in the order they end; at `limit` (0: never) add() stops
    the run."""

    def __init__(self, limit: int):
        self.limit = limit
        self.count = 0

    def add(self, row: dict, stored: int, total: int, resume: str) -> None:
        self.count = self.count + 1 if row["end_reason"] == "policy_error" else 0
        if not self.limit or self.count < self.limit:
            return
        last = "".join((row["error"] or "").strip().splitlines()[:1])
        raise RunError(f"stopped after {self.count} policy errors in a row (--max-consecutive-policy-errors), the "
                       f"last in {row['task']} trial {row['trial']}: {last}. {stored} of {total} episodes are "
                       "stored; fix the policy or its model server, then run the errors again with:\n  "
                       + retry_errors_command(resume))

"""What stops `culinarycut bench run`: bad input before anything starts, a run that cannot start or go on,
and, of those, a fault of the run folder's storage."""
from __future__ import annotations


class RunError(RuntimeError):
    """The run cannot start (or go on); the message says why and what to do."""


class BadRunInput(ValueError):
    """The run was asked for something that cannot be: an unknown policy or bad policy options. Raised
    before anything starts; every other fault of a run is a RunError."""


class StorageFault(RunError):
    """The run folder cannot be written or read (read-only, full disk, a corrupt database); one line that
    names the file and says how to resume. What was stored stays as it was."""


def retry_errors_command(command: str) -> str:
    """The run's command with --retry-errors: what reruns the episodes stored as errors."""
    return command if "--retry-errors" in command.split() else f"{command} --retry-errors"

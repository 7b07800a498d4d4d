"""Storage faults of a run folder as one-line StorageFaults: a read-only folder, a full disk, a corrupt
results database. Each names the file and says what to do next (the command that resumes); the database is
never repaired or replaced here, so nothing stored is lost."""
from __future__ import annotations

import contextlib
import errno
import sqlite3
from pathlib import Path

from culinarycut.bench.run_errors import StorageFault

_READ_ONLY_ERRNOS = (errno.EACCES, errno.EPERM, errno.EROFS)
# SQLite's primary result codes (the low byte of an extended code such as SQLITE_READONLY_DIRECTORY).
_SQLITE_FULL = (sqlite3.SQLITE_FULL,)
_SQLITE_READ_ONLY = (sqlite3.SQLITE_READONLY, sqlite3.SQLITE_CANTOPEN, sqlite3.SQLITE_PERM)
_SQLITE_CORRUPT = (sqlite3.SQLITE_NOTADB, sqlite3.SQLITE_CORRUPT)


def describe(err: Exception, file: Path, next_step: str) -> StorageFault | None:
    """The StorageFault for `err` (an OSError or an sqlite3 error met on `file`), ending in `next_step`
    (e.g. "resume with: COMMAND"); None when it is no storage fault."""
    if isinstance(err, OSError):
        file = Path(err.filename) if err.filename else file
        kind = "full" if err.errno == errno.ENOSPC else "read-only" if err.errno in _READ_ONLY_ERRNOS else "io"
        reason = err.strerror or str(err)
    elif isinstance(err, sqlite3.Error):
        code = (getattr(err, "sqlite_errorcode", None) or 0) & 0xFF
        kind = ("full" if code in _SQLITE_FULL else "read-only" if code in _SQLITE_READ_ONLY
                else "corrupt" if code in _SQLITE_CORRUPT else None)
        if kind is None:
            return None
        reason = str(err)
    else:
        return None
    if kind == "full":
        return StorageFault(f"cannot write {file}: the disk is full ({reason}); what is stored is kept. "
                            f"Free some space and {next_step}")
    if kind == "read-only":
        return StorageFault(f"cannot write {file}: {reason} (a read-only folder or file?); what is stored is kept. "
                            f"Make {file.parent} writable and {next_step}")
    if kind == "corrupt":
        return StorageFault(f"{file} is not a readable SQLite database ({reason}); it was left as it is. Recover "
                            f"its rows (sqlite3 {file} .recover | sqlite3 recovered.sqlite) or move it aside, "
                            f"then {next_step}")
    return StorageFault(f"cannot write {file}: {reason}; what is stored is kept. Then {next_step}")


@contextlib.contextmanager
def storage_faults(file: Path, next_step: str):
    """Turns an OSError or sqlite3 error raised inside into a StorageFault naming `file` (or the OSError's
    own file) and ending in `next_step`; anything else passes through."""
    try:
        yield
    except (OSError, sqlite3.Error) as err:
        fault = describe(err, file, next_step)
        if fault is None:
            raise
        raise fault from None

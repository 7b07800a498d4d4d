"""Reading a benchmark run's results database in tests: every stored episode row, in task and trial order."""
from __future__ import annotations

import sqlite3
from pathlib import Path


def rows(folder: Path) -> list[dict]:
    db = sqlite3.connect(folder / "results.sqlite")
    db.row_factory = sqlite3.Row
    try:
        return [dict(r) for r in db.execute("SELECT * FROM episodes ORDER BY task, trial")]
    finally:
        db.close()


def rows_so_far(folder: Path) -> list[dict]:
    """Rows of a run in progress, or of one refused before it stored anything: the runner may not have created
    the file yet, or not yet its tables."""
    if not (folder / "results.sqlite").exists():
        return []
    try:
        return rows(folder)
    except sqlite3.OperationalError as error:
        if "no such table" in str(error):
            return []
        raise

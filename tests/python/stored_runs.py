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

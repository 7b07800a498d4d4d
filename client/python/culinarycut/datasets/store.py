"""The generation's progress: an SQLite database beside the dataset, one row per finished job (kept or
rejected, with the reason), in the pattern of the benchmark store (culinarycut.bench.store): WAL,
synchronous=FULL, one transaction per episode, the job key as primary key, so a generator killed at
any moment keeps every finished episode once and runs only the rest when started again."""
from __future__ import annotations

import json
import sqlite3
import time
from pathlib import Path
from typing import Any

from culinarycut.bench.store import DurableDatabase

DATABASE_NAME = "generation.sqlite"


class DatasetStoreError(RuntimeError):
    pass


def require_dataset(root: Path) -> None:
    """ValueError unless `root` holds a generated dataset (so reading one never creates an empty one)."""
    if not (root / DATABASE_NAME).is_file():
        raise ValueError(f"{root} is not a generated dataset (no {DATABASE_NAME}); make one with "
                         "culinarycut data generate --out FOLDER")


class GenerationStore(DurableDatabase):
    def __init__(self, root: str | Path):
        self.root = Path(root)
        self.root.mkdir(parents=True, exist_ok=True)
        super().__init__(self.root / DATABASE_NAME)
        self.db.execute("CREATE TABLE IF NOT EXISTS jobs (key TEXT PRIMARY KEY, seed INTEGER NOT NULL, "
                        "source TEXT NOT NULL, kept INTEGER NOT NULL, reason TEXT NOT NULL, steps INTEGER NOT NULL, "
                        "file TEXT, server TEXT, wall_s REAL, finished_at REAL, scene TEXT)")
        if "scene" not in {row[1] for row in self.db.execute("PRAGMA table_info(jobs)")}:
            self.db.execute("ALTER TABLE jobs ADD COLUMN scene TEXT")  # stores written before scenes were drawn
        self.db.execute("CREATE TABLE IF NOT EXISTS dataset (key TEXT PRIMARY KEY, value TEXT NOT NULL)")

    def metadata(self) -> dict[str, str]:
        return dict(self.db.execute("SELECT key, value FROM dataset").fetchall())

    def claim_config(self, config_json: str, extra: dict[str, Any]) -> None:
        """A dataset folder belongs to one config; a different one is refused."""
        stored = self.metadata().get("config")
        if stored is not None and stored != config_json:
            old, new = json.loads(stored), json.loads(config_json)
            differ = sorted(k for k in old.keys() | new.keys() if old.get(k) != new.get(k))
            raise DatasetStoreError(f"{self.root} holds a dataset of another config (it differs in "
                                    f"{', '.join(differ) or 'its encoding'}); give the same options to resume it, "
                                    "or use another --out")
        with self.db:
            self.db.execute("BEGIN")
            self.db.executemany("INSERT OR REPLACE INTO dataset (key, value) VALUES (?, ?)",
                                [("config", config_json)] + [(k, json.dumps(v)) for k, v in extra.items()])

    def done_keys(self) -> set[str]:
        return {row[0] for row in self.db.execute("SELECT key FROM jobs")}

    def record(self, row: dict[str, Any]) -> bool:
        """One finished job, atomically; False when its key was already there."""
        row = {**row, "finished_at": row.get("finished_at", time.time())}
        names = ("key", "seed", "source", "kept", "reason", "steps", "file", "server", "wall_s", "finished_at",
                 "scene")
        with self.db:
            self.db.execute("BEGIN IMMEDIATE")
            cursor = self.db.execute(f"INSERT OR IGNORE INTO jobs ({', '.join(names)}) VALUES "
                                     f"({', '.join('?' for _ in names)})", [row.get(n) for n in names])
        return cursor.rowcount == 1

    def rows(self, kept_only: bool = False) -> list[dict[str, Any]]:
        self.db.row_factory = sqlite3.Row
        try:
            where = " WHERE kept = 1" if kept_only else ""
            return [dict(r) for r in self.db.execute(f"SELECT * FROM jobs{where} ORDER BY key")]
        finally:
            self.db.row_factory = None

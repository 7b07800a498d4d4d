"""The results of one suite run: an SQLite database, one row per episode, in the run's folder.

Each episode is written in its own transaction when it ends (WAL journal, synchronous=FULL), so a
runner killed at any moment, kill -9 included, leaves every finished episode stored and none half
written; started again on the same folder it runs only the episodes without a row (and, asked to,
those whose row is an error). The primary key (task, trial) means an episode is recorded once,
whatever retries happened on the way.
"""
from __future__ import annotations

import json
import sqlite3
import time
from pathlib import Path
from typing import Any, Iterable

DATABASE_NAME = "results.sqlite"
SCHEMA_VERSION = "1"

# The episodes table: name, SQL type, meaning (units in the name where there are any).
EPISODE_COLUMNS = (
    ("suite", "TEXT NOT NULL", "suite name"),
    ("task", "TEXT NOT NULL", "task name within the suite"),
    ("trial", "INTEGER NOT NULL", "0, 1, ... within the task"),
    ("seed", "INTEGER NOT NULL", "from (suite, task, trial): replays the episode"),
    ("group_name", "TEXT", "the task's group label (e.g. train-objects)"),
    ("food", "TEXT", "target food"),
    ("style", "TEXT", "cut style"),
    ("state", "TEXT", "cut state"),
    ("ratio", "REAL", "ratio cuts: the fraction"),
    ("side", "TEXT", "directional reference"),
    ("pieces_required", "INTEGER", "split cuts: the piece count"),
    ("distractors", "INTEGER", "distractor foods in the scene"),
    ("topology", "INTEGER", "1: topology updates on"),
    ("scene", "TEXT", "table or kitchen"),
    ("language", "TEXT", "train or held_out templates"),
    ("quality", "TEXT", "MPM preset"),
    ("instruction", "TEXT", "the instruction the policy was given"),
    ("policy", "TEXT", "policy name"),
    ("policy_name", "TEXT", "the policy's own name (a grpc policy server's, from its metadata)"),
    ("policy_version", "TEXT", "policy version (a grpc policy server's, from its metadata)"),
    ("policy_options", "TEXT", "JSON"),
    ("server", "TEXT", "host:port it ran on"),
    ("server_version", "TEXT", "culinarycut-server version"),
    ("build_id", "TEXT", "the server's build id"),
    ("simd", "TEXT", "the instruction set the server's MPM kernels ran (x86-64, x86-64-v3, ...): same bits only "
                     "within one"),
    ("resolved_scene", "TEXT", "the SceneSpec the server resolved, JSON"),
    ("outcome", "TEXT NOT NULL", "success, failure or error"),
    ("end_reason", "TEXT", "success, task_failed, step_limit, policy_finished, knife_stalled, policy_error, "
                           "server_error"),
    ("error", "TEXT", "what went wrong, for outcome error"),
    ("cuts_required", "INTEGER", ""),
    ("cuts_correct", "INTEGER", "in position and angle"),
    ("cuts_within_tolerance", "INTEGER", "in position (the paper's split table)"),
    ("extra_cuts", "INTEGER", ""),
    ("wrong_object_cuts", "INTEGER", ""),
    ("cuts", "TEXT", "JSON: per required cut target, measured fraction, position error (fraction), angle error (deg)"),
    ("score_summary", "TEXT", "the server's one-line summary"),
    ("saw_strokes", "INTEGER", "reversals of the knife along its blade while in the food (a saw cut's strokes)"),
    ("pivot_deg", "REAL", "range of the blade's pitch while in the food (deg; a guillotine pivots)"),
    ("pieces", "INTEGER", "pieces at the end"),
    ("peak_force_n", "REAL", "peak knife force at the wrist (N)"),
    ("peak_speed_m_s", "REAL", "peak knife (TCP) speed (m/s)"),
    ("peak_knife_force_n", "REAL", "peak food force on the knife over every physics step (N; the session's safety totals)"),
    ("peak_cutting_speed_m_s", "REAL", "peak knife (TCP) speed along its cutting direction while in the food (m/s)"),
    ("safety_limiter", "INTEGER", "1: the safety limiter was on (docs/safety.md)"),
    ("safety_settings", "TEXT", "JSON: the limiter's settings as the suite gave them (max_force_n, margin, guards, "
                                "max_entry_angle_deg; unset: the server's defaults)"),
    ("safety_max_force_n", "REAL", "the limiter's F_max (N); empty with it off"),
    ("peak_commanded_speed_m_s", "REAL", "peak speed into the food the actions commanded, before the limit (m/s; "
                                         "the limiter measures it, so empty with it off)"),
    ("safety_acted_steps", "INTEGER", "control steps whose joint target the limiter shortened"),
    ("interventions_speed", "INTEGER", "steps the limiter's speed guard bound"),
    ("interventions_force", "INTEGER", "steps the limiter's force guard bound"),
    ("interventions_entry_angle", "INTEGER", "steps the limiter's entry-angle guard bound"),
    ("stalled_steps", "INTEGER", "steps the knife was in the food with the arm at its effort limit"),
    ("steps", "INTEGER", "control steps"),
    ("sim_time_s", "REAL", "simulated time (s)"),
    ("wall_s", "REAL", "episode wall time (s)"),
    ("env_wall_s", "REAL", "wall time in reset and step calls (s)"),
    ("policy_wall_s", "REAL", "wall time in the policy (s)"),
    ("policy_latency", "TEXT", "JSON: a remote policy's queries and their latency (mean, p50, p95, max ms)"),
    ("stage_wall_s", "TEXT", "JSON: the server's wall time by stage (s)"),
    ("attempts", "INTEGER", "servers tried before it ran to the end"),
    ("video", "TEXT", "file of the failure video, relative to the run folder"),
    ("finished_at", "REAL", "Unix time the row was written"),
)
COLUMN_NAMES = tuple(name for name, _, _ in EPISODE_COLUMNS)


class StoreError(RuntimeError):
    pass


class DurableDatabase:
    """An SQLite file that keeps every committed transaction through a crash (WAL journal, synchronous=FULL)
    and lets readers look while a writer writes; a context manager that closes it."""

    def __init__(self, path: Path):
        self.db = sqlite3.connect(path, timeout=30.0, isolation_level=None)
        self.db.execute("PRAGMA journal_mode=WAL")
        self.db.execute("PRAGMA synchronous=FULL")

    def close(self) -> None:
        self.db.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class ResultStore(DurableDatabase):
    """Open (or create) the database in `folder`."""

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.path = self.folder / DATABASE_NAME
        super().__init__(self.path)
        columns = ", ".join(f"{name} {kind}" for name, kind, _ in EPISODE_COLUMNS)
        self.db.execute(f"CREATE TABLE IF NOT EXISTS episodes ({columns}, PRIMARY KEY (task, trial))")
        # A run folder from before a column was added gets it (empty for its earlier rows) and resumes.
        present = {row[1] for row in self.db.execute("PRAGMA table_info(episodes)")}
        for name, kind, _ in EPISODE_COLUMNS:
            if name not in present:
                self.db.execute(f"ALTER TABLE episodes ADD COLUMN {name} {kind}")
        self.db.execute("CREATE TABLE IF NOT EXISTS traces (task TEXT NOT NULL, trial INTEGER NOT NULL, "
                        "trace TEXT NOT NULL, PRIMARY KEY (task, trial))")
        self.db.execute("CREATE TABLE IF NOT EXISTS run (key TEXT PRIMARY KEY, value TEXT NOT NULL)")

    # The run's identity: which suite, policy and server versions its rows belong to.
    def metadata(self) -> dict[str, str]:
        return dict(self.db.execute("SELECT key, value FROM run").fetchall())

    def set_metadata(self, values: dict[str, Any]) -> None:
        with self.db:
            self.db.execute("BEGIN")
            self.db.executemany("INSERT OR REPLACE INTO run (key, value) VALUES (?, ?)",
                                [(k, v if isinstance(v, str) else json.dumps(v)) for k, v in values.items()])

    def done_keys(self) -> set[tuple[str, int]]:
        return set(self.db.execute("SELECT task, trial FROM episodes").fetchall())

    def error_keys(self) -> set[tuple[str, int]]:
        """The episodes stored with outcome error (server_error, policy_error): what --retry-errors reruns."""
        return set(self.db.execute("SELECT task, trial FROM episodes WHERE outcome = 'error'").fetchall())

    def server_versions(self) -> set[tuple[str, str, str]]:
        """(version, build id, instruction set) of the servers the rows ran on; rows without a version (a
        server_error before the server said its version) name none."""
        return set(self.db.execute("SELECT DISTINCT server_version, COALESCE(build_id, ''), COALESCE(simd, '') "
                                   "FROM episodes "
                                   "WHERE server_version IS NOT NULL AND server_version != ''").fetchall())

    def record(self, row: dict[str, Any], trace: dict | None = None, replace_error: bool = False) -> bool:
        """Writes one episode (and its trace) atomically; False if it was already there. With replace_error
        a stored row of the same episode is replaced when, and only when, its outcome is error."""
        unknown = set(row) - set(COLUMN_NAMES)
        if unknown:
            raise StoreError(f"unknown result columns {sorted(unknown)}")
        row = {**row, "finished_at": row.get("finished_at", time.time())}
        names = [n for n in COLUMN_NAMES if n in row]
        placeholders = ", ".join("?" for _ in names)
        with self.db:
            self.db.execute("BEGIN IMMEDIATE")
            if replace_error:
                self.db.execute("DELETE FROM episodes WHERE task = ? AND trial = ? AND outcome = 'error'",
                                (row["task"], row["trial"]))
            cursor = self.db.execute(f"INSERT OR IGNORE INTO episodes ({', '.join(names)}) VALUES ({placeholders})",
                                     [row[n] for n in names])
            if cursor.rowcount and trace is not None:
                self.db.execute("INSERT OR REPLACE INTO traces (task, trial, trace) VALUES (?, ?, ?)",
                                (row["task"], row["trial"], json.dumps(trace, separators=(",", ":"))))
        return cursor.rowcount == 1

    def episodes(self, where: str = "", params: Iterable = ()) -> list[dict[str, Any]]:
        self.db.row_factory = sqlite3.Row
        try:
            query = "SELECT * FROM episodes" + (f" WHERE {where}" if where else "") + " ORDER BY task, trial"
            return [dict(r) for r in self.db.execute(query, tuple(params)).fetchall()]
        finally:
            self.db.row_factory = None

    def trace(self, task: str, trial: int) -> dict | None:
        found = self.db.execute("SELECT trace FROM traces WHERE task = ? AND trial = ?", (task, trial)).fetchone()
        return json.loads(found[0]) if found else None

"""`culinarycut data verify`: a finished dataset's counts, schema and files, and episodes replayed from
their seed and resolved scene (the recorded actions stepped open loop must give the recorded TCP
poses and the same success)."""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from culinarycut.client import Client
from culinarycut.datasets.episode_file import read_episode
from culinarycut.datasets.generate import CONFIG_NAME
from culinarycut.datasets.jobs import DatasetConfig, make_jobs
from culinarycut.datasets.store import DATABASE_NAME, GenerationStore
from culinarycut.env import CulinaryCutEnv

REQUIRED = ("actions", "rewards", "dones", "phase", "knife_contact", "obs/qpos", "obs/qvel", "obs/tcp_pose",
            "obs/tcp_velocity", "obs/wrist_wrench")
REPLAY_TOLERANCE_M = 1e-6  # replayed TCP positions must match the recorded ones this closely


@dataclass
class VerifyReport:
    jobs: int = 0
    kept: int = 0
    rejected: int = 0
    replayed: int = 0
    problems: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.problems


def check_episode_file(path: Path) -> tuple[dict, dict, list[str]]:
    try:
        meta, steps = read_episode(path)
    except ValueError as err:
        return {}, {}, [str(err)]
    problems = [f"{path.name}: missing {name}" for name in REQUIRED if name not in steps]
    if problems:
        return meta, steps, problems
    length = len(steps["actions"])
    problems += [f"{path.name}: {name} has {len(values)} steps, actions {length}"
                 for name, values in steps.items() if len(values) != length]
    if not any(name.endswith("_rgb") for name in steps):
        problems.append(f"{path.name}: no camera images")
    if len(meta.get("instructions", [])) < 5:
        problems.append(f"{path.name}: {len(meta.get('instructions', []))} instructions, fewer than 5")
    return meta, steps, problems


def replay(client: Client, meta: dict, steps: dict) -> list[str]:
    scene = dict(meta["resolved_scene"])
    with CulinaryCutEnv(client=client, scene=scene, control_mode=meta["control_mode"]) as env:
        env.reset(seed=meta["seed"])
        poses, info = [], {}
        for action in steps["actions"]:
            observation, _, _, _, info = env.step(action)
            poses.append(observation["extra"]["tcp_pose"][:3])
    recorded = steps["obs/tcp_pose"][1:, :3]  # observation before step t+1 = after step t
    error_m = float(np.max(np.abs(np.asarray(poses)[:-1] - recorded))) if len(recorded) else 0.0
    problems = []
    if error_m > REPLAY_TOLERANCE_M:
        problems.append(f"{meta['key']}: replay departs from the recording by {error_m * 1e3:.3f} mm")
    if not info.get("success"):
        problems.append(f"{meta['key']}: replay does not succeed ({info.get('task', {}).get('summary', '')})")
    return problems


def verify(root: Path, server: str | None = None, replay_count: int | None = None) -> VerifyReport:
    """replay_count None replays every kept episode, 0 none (then server is not needed)."""
    report = VerifyReport()
    if not (root / DATABASE_NAME).is_file() or not (root / CONFIG_NAME).is_file():
        report.problems.append(f"{root} is not a generated dataset (no {DATABASE_NAME} or {CONFIG_NAME})")
        return report
    config = DatasetConfig.from_json(json.dumps(json.loads((root / CONFIG_NAME).read_text())))
    expected = {job.key for job in make_jobs(config)}
    with GenerationStore(root) as store:
        rows = store.rows()
    report.jobs = len(rows)
    keys = {row["key"] for row in rows}
    if keys != expected:
        report.problems.append(f"{len(expected - keys)} jobs have no row (unfinished), {len(keys - expected)} rows "
                               "belong to no job")
    report.problems += [f"leftover partial file {p.relative_to(root)}" for p in root.rglob("*.tmp")]
    kept_rows = [row for row in rows if row["kept"]]
    report.kept, report.rejected = len(kept_rows), len(rows) - len(kept_rows)
    report.problems += [f"{row['key']}: rejected without a reason" for row in rows if not row["kept"] and not row["reason"]]
    files = {root / row["file"] for row in kept_rows}
    strays = set((root / "episodes").glob("*.h5")) - files
    report.problems += [f"episode file {p.name} is not in the store" for p in sorted(strays)]
    to_replay = {row['key'] for row in (kept_rows if replay_count is None else kept_rows[:replay_count])}
    client = Client(server, timeout_s=600.0) if to_replay and server else None
    if to_replay and client is None:
        report.problems.append("replaying needs a server (--server)")
    try:
        for row in kept_rows:
            meta, steps, problems = check_episode_file(root / row["file"])
            report.problems += problems
            if problems or client is None or row["key"] not in to_replay:
                continue
            report.problems += replay(client, meta, steps)
            report.replayed += 1
    finally:
        if client is not None:
            client.close()
    return report

"""One `culinarycut bench run` as a user runs it, and where its episodes' time went, from the rows it stored:
the run's wall time, and per episode the server's stages (its own timers), the rest of the server calls, the
policy and the harness. Shared by the benchmarks that time whole suites (suite_throughput, draft_lever,
simd_lever)."""
from __future__ import annotations

import json
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

# The server's stages as the rows store them (StepInfo.stage_wall_time_ms summed by the session), in page order.
STAGES = ("mpm", "physics", "render", "rollback", "topology", "task", "control", "safety")
SERVER_OTHER = "server, outside the stages (scene set-up, reset, observations, the wire)"


def with_top_level(suite: Path, line: str, folder: Path) -> Path:
    """The suite's TOML with `line` added at its top level, before its first table (same name, in `folder`)."""
    text = suite.read_text()
    first_table = text.index("\n[")
    path = folder / suite.name
    path.write_text(text[:first_table] + f"\n{line}\n" + text[first_table:])
    return path


def run_suite(suite: str | Path, servers: list[str], workers: int, out: Path, extra: list[str] = ()) -> dict:
    """Runs the suite into a fresh folder `out`; its wall time and sums over the episodes it stored."""
    command = [sys.executable, "-m", "culinarycut", "bench", "run", str(suite), "--workers", str(workers),
               "--out", str(out), "--no-progress", *extra]
    for server in servers:
        command += ["--server", server]
    started = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    wall_s = time.perf_counter() - started
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}")
    db = sqlite3.connect(out / "results.sqlite")
    rows = db.execute("SELECT outcome, wall_s, env_wall_s, policy_wall_s, stage_wall_s, resolved_scene, simd "
                      "FROM episodes").fetchall()
    db.close()
    stages = {stage: 0.0 for stage in STAGES}
    for row in rows:
        for stage, seconds in json.loads(row[4] or "{}").items():
            stages[stage] = stages.get(stage, 0.0) + seconds
    episode_s = sum(r[1] for r in rows)
    server_s, policy_s = sum(r[2] for r in rows), sum(r[3] for r in rows)
    return {"wall_s": wall_s, "workers": workers, "servers": len(servers), "episodes": len(rows),
            "successes": sum(r[0] == "success" for r in rows), "episode_s": episode_s, "server_call_s": server_s,
            "policy_s": policy_s, "harness_s": episode_s - server_s - policy_s, "stages_s": stages,
            "resolved_cfl": sorted({json.loads(r[5])["mpm"]["cfl"] for r in rows}),
            "simd": sorted({r[6] or "" for r in rows})}


def rounds_totals(runs: list[dict]) -> dict:
    """The rounds of one setting summed: episodes per hour over all of them, seconds per episode by part."""
    episodes = sum(r["episodes"] for r in runs)
    wall_s = sum(r["wall_s"] for r in runs)
    return {"episodes": episodes, "successes": sum(r["successes"] for r in runs), "wall_s": wall_s,
            "episodes_per_hour": 3600.0 * episodes / wall_s,
            "episode_s": sum(r["episode_s"] for r in runs) / episodes,
            "per_episode_s": per_episode_parts(runs),
            "resolved_cfl": sorted({c for r in runs for c in r["resolved_cfl"]}),
            "simd": sorted({s for r in runs for s in r.get("simd", [])}), "runs": runs}


def per_episode_parts(runs: list[dict]) -> dict[str, float]:
    """Seconds per episode by part over these runs: each stage, the rest of the server calls, policy, harness."""
    episodes = sum(r["episodes"] for r in runs)
    parts = {stage: sum(r["stages_s"].get(stage, 0.0) for r in runs) / episodes for stage in STAGES}
    parts[SERVER_OTHER] = sum(r["server_call_s"] for r in runs) / episodes - sum(parts.values())
    parts["policy"] = sum(r["policy_s"] for r in runs) / episodes
    parts["harness"] = sum(r["harness_s"] for r in runs) / episodes
    return parts

#!/usr/bin/env python3
"""Robustness benchmark: network fuzz, connection floods (past the soft descriptor limit, and past the
hard one), a short soak and the stop signals' exit times, measured on this machine against the built
server; writes docs/robustness.md and docs/benchmarks/robustness.json.

    .venv/bin/python bench/robustness.py            # about 10 minutes on 2 cores; writes the docs
    .venv/bin/python bench/robustness.py --quick    # seconds; prints the results, writes nothing
    .venv/bin/python bench/robustness.py --from-json docs/benchmarks/robustness.json   # the page again, no run

Exits 1 when a check fails (a crash, a hang, an UNKNOWN status, a flood that leaves new clients
unserved once it ends, a stop that is not prompt or exits with the wrong code).
Imports only the standard library, numpy, and culinarycut with its gRPC dependency.
"""
from __future__ import annotations

import argparse
import json
import os
import queue
import random
import re
import resource
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import grpc
import numpy as np
from culinarycut import Client
from culinarycut.errors import CulinaryCutError, DeadlineExceeded
from culinarycut.launch import ServerProcess, server_binary
from culinarycut.policies import ScriptedOracle, run_oracle_episode
from culinarycut.scenes import cut_cucumber_scene
from culinarycut.wire_fuzz import RANDOM_BYTES, RANDOM_MESSAGE, all_methods, random_request

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness.machine import dated_machine_info  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
FUZZ_SEED = 20261124        # the network fuzz test's seed: its 1,500 requests are this run's first 1,500
FUZZ_DEADLINE_S = 10.0      # per request; DEADLINE_EXCEEDED counts as a hang
SOFT_LIMIT = 64             # the flood's server starts with this soft descriptor limit (its hard one kept)
HARD_LIMIT = 256            # the hard-limit flood's server gets this as soft and hard limit
HARD_FLOOD = 400            # connections opened against it, from one address and then from many
PER_ADDRESS_CAP = 16        # the hard-limit flood's server's --max-connections-per-address
FLOOD_SOURCES = [f"127.0.1.{i}" for i in range(1, 41)]  # 40 client addresses, 25 of 1,000 each
SECOND_SIGNAL_GAP_S = 0.3
# The mid-step stop's scene (as tests/python/test_call_lifecycle.py): a large draft cucumber at a CFL
# factor 25 times below the preset's, so a control step with the knife in the food is seconds of work.
SLOW_SCENE = {"quality": "draft", "mpm": {"cfl": 0.012},
              "effects": {"mpm": True, "damage": True, "friction": True, "topology": True, "force_sensing": True},
              "objects": [{"food": "cucumber", "scale": 1.5}]}

FULL = {"fuzz_requests": 20000, "flood_connections": 1000, "flood_hold_s": 15.0, "hard_recovery_wait_s": 30.0,
        "robot_episodes": 2000, "cutting_episodes": 4, "stop_repeats": 3}
QUICK = {"fuzz_requests": 150, "flood_connections": 100, "flood_hold_s": 0.0, "hard_recovery_wait_s": 1.0,
         "robot_episodes": 10, "cutting_episodes": 0, "stop_repeats": 1}


# --- the machine and the server process -----------------------------------------------------------------

def machine_info() -> dict:
    """The harness's machine description with this page's extras: memory and the load when the run began."""
    try:
        memory_gb = int(Path("/proc/meminfo").read_text().split()[1]) / 2**20
    except (OSError, IndexError, ValueError):
        memory_gb = 0.0
    return {**dated_machine_info(), "memory_gb": round(memory_gb, 1),
            "load_average_at_start": [round(x, 2) for x in os.getloadavg()]}


def proc_status(pid: int, key: str) -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith(key + ":"):
            return int(line.split()[1])
    raise RuntimeError(f"no {key} in /proc/{pid}/status")


def rss_mb(pid: int) -> float:
    return proc_status(pid, "VmRSS") / 1024.0


def open_descriptors(pid: int) -> int:
    return len(os.listdir(f"/proc/{pid}/fd"))


def descriptor_limits(pid: int) -> tuple[int, int]:
    for line in Path(f"/proc/{pid}/limits").read_text().splitlines():
        if line.startswith("Max open files"):
            soft, hard = line.split()[3:5]
            return int(soft), int(hard)
    raise RuntimeError("no 'Max open files' line")


def grpc_library(pid: int) -> str:
    """The libgrpc++ the server loaded, e.g. libgrpc++.so.1.51."""
    names = {Path(line.split()[-1]).name for line in Path(f"/proc/{pid}/maps").read_text().splitlines()
             if "libgrpc++.so" in line}
    return ", ".join(sorted(names)) or "unknown (statically linked?)"


class RawServer:
    """The server started with the descriptor limits given (soft, hard) and its output drained; for the
    floods, which need limits the launcher cannot set."""

    def __init__(self, soft: int, hard: int, extra_args: tuple[str, ...] = ()):
        def limits():
            resource.setrlimit(resource.RLIMIT_NOFILE, (soft, hard))

        self.proc = subprocess.Popen([str(server_binary()), "--listen", "127.0.0.1:0", "--max-sessions", "4",
                                      *extra_args],
                                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1,
                                     preexec_fn=limits)
        self.lines: list[str] = []
        ready: queue.Queue[str] = queue.Queue()

        def drain():
            for line in self.proc.stdout:
                self.lines.append(line.rstrip("\n"))
                if m := re.search(r"listening on (\S+:\d+)", line):
                    ready.put(m.group(1))

        threading.Thread(target=drain, daemon=True).start()
        self.address = ready.get(timeout=30)
        self.host, port = self.address.rsplit(":", 1)
        self.port = int(port)

    def stop(self) -> int:
        self.proc.send_signal(signal.SIGTERM)
        try:
            return self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            return self.proc.wait()


def served(address: str, timeout_s: float) -> bool:
    """Whether a new client on a connection of its own gets GetServerInfo answered within timeout_s. Its own:
    gRPC shares a connected subchannel between channels of one process with the same target and options,
    so a plain second Client could ride on an earlier client's connection and never touch the listener."""
    options = [("grpc.use_local_subchannel_pool", 1)]
    with grpc.insecure_channel(address, options=options) as channel:
        info = channel.unary_unary("/culinarycut.v1.Simulator/GetServerInfo", request_serializer=None,
                                   response_deserializer=None)
        try:
            info(b"", timeout=timeout_s)
            return True
        except grpc.RpcError:
            return False


def first_served(address: str, wait_s: float, attempt_s: float) -> float | None:
    """Seconds until a new client is served (new clients tried one after another), or None within wait_s."""
    started = time.monotonic()
    while True:
        if served(address, attempt_s):
            return time.monotonic() - started
        if time.monotonic() - started > wait_s:
            return None


# --- network fuzz ----------------------------------------------------------------------------------------

def network_fuzz(requests: int) -> dict:
    rng = random.Random(FUZZ_SEED)
    methods = all_methods()
    by_kind = {RANDOM_BYTES: {}, RANDOM_MESSAGE: {}}
    by_method: dict[str, dict[str, int]] = {}
    slowest = {RANDOM_BYTES: 0.0, RANDOM_MESSAGE: 0.0}
    longest_message = 0
    hangs, unknown, crash = [], [], None
    with ServerProcess(server_binary(), max_sessions=8) as server:
        pid = server.proc.pid
        before = {"rss_mb": rss_mb(pid), "descriptors": open_descriptors(pid), "threads": proc_status(pid, "Threads")}
        channel = grpc.insecure_channel(server.address)
        started = time.monotonic()
        sent = 0
        for index in range(requests):
            path, kind, payload = random_request(rng, methods)
            call = channel.unary_unary(path, request_serializer=None, response_deserializer=None)
            t0 = time.monotonic()
            try:
                call(payload, timeout=FUZZ_DEADLINE_S)
                code = "OK"
            except grpc.RpcError as err:
                code = err.code().name
                longest_message = max(longest_message, len(err.details() or ""))
                if code == "DEADLINE_EXCEEDED":
                    hangs.append({"index": index, "method": path})
                if code == "UNKNOWN":
                    unknown.append({"index": index, "method": path, "details": (err.details() or "")[:300]})
            slowest[kind] = max(slowest[kind], time.monotonic() - t0)
            sent += 1
            by_kind[kind][code] = by_kind[kind].get(code, 0) + 1
            by_method.setdefault(path, {})
            by_method[path][code] = by_method[path].get(code, 0) + 1
            if server.proc.poll() is not None:
                crash = {"index": index, "method": path, "exit_code": server.proc.returncode,
                         "output": server.output(20)}
                break
        wall_s = time.monotonic() - started
        health = None
        if crash is None:
            check = channel.unary_unary("/grpc.health.v1.Health/Check", request_serializer=None,
                                        response_deserializer=None)
            health = "SERVING" if check(b"", timeout=10) == b"\x08\x01" else "NOT SERVING"
            after = {"rss_mb": rss_mb(pid), "descriptors": open_descriptors(pid), "threads": proc_status(pid, "Threads"),
                     "peak_rss_mb": proc_status(pid, "VmHWM") / 1024.0}
        else:
            after = None
        channel.close()
    ok = crash is None and not hangs and not unknown and health == "SERVING"
    return {"seed": FUZZ_SEED, "requests": sent, "methods": len(methods), "deadline_s": FUZZ_DEADLINE_S,
            "by_kind": by_kind, "by_method": by_method, "slowest_s": slowest, "longest_message_chars": longest_message,
            "hangs": hangs, "unknown": unknown, "crash": crash, "health_after": health, "server_before": before,
            "server_after": after, "wall_s": wall_s, "ok": ok}


# --- connection floods -----------------------------------------------------------------------------------

def open_flood(host: str, port: int, count: int, sources: list[str]) -> tuple[list[socket.socket], str | None]:
    """`count` idle TCP connections, from the loopback addresses `sources` in turn (any 127.x.y.z is this
    machine), since the server caps the connections of one client address."""
    flood, error = [], None
    for i in range(count):
        try:
            flood.append(socket.create_connection((host, port), timeout=5, source_address=(sources[i % len(sources)], 0)))
        except OSError as err:
            error = f"{type(err).__name__}: {err}"
            break
    return flood, error


def soft_limit_flood(connections: int, hold_s: float) -> dict:
    """The server starts with a soft limit of SOFT_LIMIT (it raises it to the hard one); `connections` idle
    TCP connections that never speak HTTP/2; a new client during the flood, the descriptors the server holds
    over `hold_s` (the 10 s handshake timeout closes silent connections), and a new client after."""
    hard = resource.getrlimit(resource.RLIMIT_NOFILE)[1]
    server = RawServer(SOFT_LIMIT, hard)
    flood: list[socket.socket] = []
    try:
        pid = server.proc.pid
        limits = descriptor_limits(pid)
        baseline = open_descriptors(pid)
        started = time.monotonic()
        flood, error = open_flood(server.host, server.port, connections, FLOOD_SOURCES)
        opened_s = time.monotonic() - started
        time.sleep(0.5)
        peak = open_descriptors(pid)
        during = served(server.address, 10)
        # How long the server keeps the silent connections: until its handshake timeout closes them.
        released_s = None
        while time.monotonic() - started < hold_s:
            if open_descriptors(pid) <= baseline + 2:
                released_s = time.monotonic() - started
                break
            time.sleep(0.25)
        held_at_end = open_descriptors(pid)
        for connection in flood:
            connection.close()
        recovery_s = first_served(server.address, wait_s=30, attempt_s=5)
        after_close = open_descriptors(pid)
        alive = server.proc.poll() is None
        code = server.stop()
    finally:
        for connection in flood:
            connection.close()
        if server.proc.poll() is None:
            server.proc.kill()
    ok = during and recovery_s is not None and alive
    return {"start_soft_limit": SOFT_LIMIT, "limits_after_start": {"soft": limits[0], "hard": limits[1]},
            "raised_line": next((line for line in server.lines if "descriptor limit raised" in line), None),
            "connections_requested": connections, "connections_opened": len(flood), "open_error": error,
            "open_s": opened_s, "server_descriptors": {"before": baseline, "during": peak,
                                                        "after_hold": held_at_end, "after_close": after_close},
            "hold_s": hold_s, "silent_connections_closed_by_server_after_s": released_s,
            "new_client_served_during": during, "new_client_served_after_s": recovery_s,
            "server_alive": alive, "exit_code": code, "ok": ok}


def hard_limit_flood(wait_s: float) -> dict:
    """The server at soft = hard = HARD_LIMIT descriptors (no room to raise) and PER_ADDRESS_CAP connections
    per address; a client connected before the flood; HARD_FLOOD connections from one address (is a client
    at another address served?), then HARD_FLOOD from FLOOD_SOURCES (the total cap); then is the earlier
    client still served, and is a new one served once the flood is closed (tried for wait_s)?"""
    server = RawServer(HARD_LIMIT, HARD_LIMIT, ("--max-connections-per-address", str(PER_ADDRESS_CAP)))
    flood: list[socket.socket] = []
    try:
        pid = server.proc.pid
        earlier = Client(server.address, timeout_s=5)
        earlier.server_info()
        flood, error = open_flood(server.host, server.port, HARD_FLOOD, ["127.0.0.2"])
        during_one_address = served(server.address, 3)
        many, error_many = open_flood(server.host, server.port, HARD_FLOOD, FLOOD_SOURCES)
        flood += many
        time.sleep(0.5)
        peak = open_descriptors(pid)
        during_new = served(server.address, 3)
        during_earlier = _answers(earlier)
        for connection in flood:
            connection.close()
        time.sleep(0.5)
        after_close = open_descriptors(pid)
        recovery_s = first_served(server.address, wait_s=wait_s, attempt_s=2)
        after_earlier = _answers(earlier)
        earlier.close()
        alive = server.proc.poll() is None
        code = server.stop()
    finally:
        for connection in flood:
            connection.close()
        if server.proc.poll() is None:
            server.proc.kill()
    caps = next((line for line in server.lines if re.search(r"at most \d+ connections", line)), "")
    refused = next((re.search(r"(\d+) relayed; refused (\d+) at --max-connections, (\d+) at "
                              r"--max-connections-per-address, (\d+) out of descriptors", line)
                    for line in server.lines if "relayed; refused" in line), None)
    counts = dict(zip(("relayed", "refused_total_cap", "refused_address_cap", "refused_no_descriptor"),
                      map(int, refused.groups()))) if refused else None
    ok = (during_one_address and during_earlier and after_earlier and recovery_s is not None and alive
          and code == 0)
    return {"limit": HARD_LIMIT, "per_address_cap": PER_ADDRESS_CAP, "connections_requested": 2 * HARD_FLOOD,
            "connections_opened": len(flood), "open_error": error or error_many,
            "server_descriptors": {"during": peak, "after_close": after_close},
            "cap_line": re.sub(r"^(\[[^\]]*\] )+", "", caps) or None, "gate_counts": counts,
            "accept_errors": [line for line in server.lines if "accept4" in line][:3],
            "other_address_served_during_one_address_flood": during_one_address,
            "earlier_client_served_during": during_earlier, "earlier_client_served_after": after_earlier,
            "new_client_served_during": during_new, "new_client_served_after_s": recovery_s,
            "waited_s": wait_s, "server_alive": alive, "exit_code": code, "ok": ok}


def _answers(client: Client) -> bool:
    try:
        return bool(client.server_info().version)
    except CulinaryCutError:
        return False


# --- soak ------------------------------------------------------------------------------------------------

def soak(robot_episodes: int, cutting_episodes: int) -> dict:
    """Robot-only episodes (create, reset, 20 steps, close) then cutting episodes (the oracle, draft
    cucumber, no cameras) on one server, its RSS sampled; as bench/soak.py, shorter."""
    every = max(1, robot_episodes // 50)
    robot, cutting = [], []
    with ServerProcess(server_binary(), max_sessions=4, idle_timeout_s=600) as server, \
            Client(server.address, timeout_s=600) as client:
        pid = server.proc.pid
        descriptors_before = open_descriptors(pid)
        started = time.monotonic()
        robot.append((0, rss_mb(pid)))
        for episode in range(1, robot_episodes + 1):
            session = client.create_session().session_id
            client.reset(session, seed=episode)
            for _ in range(20):
                client.step(session, "pd_ee_delta_pose", np.zeros(6))
            client.close_session(session)
            if episode % every == 0:
                robot.append((episode, rss_mb(pid)))
        robot_s = time.monotonic() - started
        cutting.append((0, rss_mb(pid)))
        complete = 0
        for episode in range(1, cutting_episodes + 1):
            trace = run_oracle_episode(client, cut_cucumber_scene(cameras=()), seed=episode)
            complete += bool(trace["complete"])
            cutting.append((episode, rss_mb(pid)))
        wall_s = time.monotonic() - started
        descriptors_after = open_descriptors(pid)
        threads = proc_status(pid, "Threads")
    return {"robot_only": {"episodes": robot_episodes, "steps_each": 20, "seconds": robot_s, "samples": robot,
                           **_growth(robot, skip=min(100, robot_episodes // 10))},
            "cutting": {"episodes": cutting_episodes, "complete": complete, "samples": cutting,
                        **_growth(cutting, skip=1 if cutting_episodes > 2 else 0)},
            "descriptors": {"before": descriptors_before, "after": descriptors_after}, "threads_after": threads,
            "wall_s": wall_s, "ok": complete == cutting_episodes}


def _growth(samples: list[tuple[int, float]], skip: int) -> dict:
    after = [(e, r) for e, r in samples if e >= skip]
    if len(after) < 2:
        return {}
    episodes = np.array([e for e, _ in after], dtype=float)
    rss = np.array([r for _, r in after])
    slope = float(np.polyfit(episodes, rss, 1)[0]) if len(after) > 2 else float((rss[-1] - rss[0]) / (episodes[-1] - episodes[0]))
    return {"warmup_episodes": skip, "min_mb": float(rss.min()), "max_mb": float(rss.max()),
            "slope_kb_per_episode": 1024 * slope}


# --- stop signals ----------------------------------------------------------------------------------------

def wait_exit(proc: subprocess.Popen, timeout_s: float = 15) -> tuple[int | None, float]:
    """Blocks on the process's exit (waitpid, not polling) up to timeout_s; (exit code, monotonic time)."""
    result: list = []
    waiter = threading.Thread(target=lambda: result.extend([proc.wait(), time.monotonic()]), daemon=True)
    waiter.start()
    waiter.join(timeout_s)
    if not result:
        proc.kill()
        waiter.join()
        return None, time.monotonic()
    return result[0], result[1]


def silent_peer(address: str) -> socket.socket:
    """A connection that never speaks, so never answers the stopping server's GOAWAY: the clean shutdown
    waits for it until its 1 s grace deadline."""
    host, port = address.rsplit(":", 1)
    return socket.create_connection((host, int(port)), timeout=5)


def stop_idle(peer: bool) -> dict:
    server = ServerProcess(server_binary(), max_sessions=2)
    connection = None
    try:
        served(server.address, 10)
        if peer:
            connection = silent_peer(server.address)
            time.sleep(0.2)  # taken from the listen backlog: one still in it when the server stops is reset
        sent = time.monotonic()
        server.proc.send_signal(signal.SIGTERM)
        code, ended = wait_exit(server.proc)
    finally:
        if connection:
            connection.close()
        server.kill()
    return {"exit_code": code, "after_first_s": ended - sent, "log_tail": server.lines[-2:]}


def slow_step(address: str, session: str) -> tuple[str, list[float]]:
    """Steps the oracle with a 1 s deadline until a step misses it; returns that step's action (not applied)."""
    with Client(address, timeout_s=30.0) as planner, Client(address, timeout_s=1.0) as hurried:
        oracle = ScriptedOracle(planner, session)
        oracle.reset("cut the cucumber in the middle")
        while not oracle.finished:
            mode, values = oracle.act()
            try:
                hurried.step(session, mode, values)
            except DeadlineExceeded:
                return mode, values
    raise RuntimeError("no step was slow: the knife never came near the food")


def stop_mid_step(signals: int, peer: bool) -> dict:
    """SIGTERM 0.5 s into a long Step (`signals` times, SECOND_SIGNAL_GAP_S apart), with or without a
    silent peer holding the clean shutdown."""
    server = ServerProcess(server_binary(), max_sessions=2)
    connection = None
    replies: list[str] = []
    try:
        with Client(server.address, timeout_s=60.0) as client:
            session = client.create_session(SLOW_SCENE).session_id
            client.reset(session, seed=0)
            mode, values = slow_step(server.address, session)
            if peer:
                connection = silent_peer(server.address)

            def long_step():
                try:
                    client.step(session, mode, values)
                    replies.append("OK")
                except CulinaryCutError as err:
                    replies.append(f"{err.code.name}: {err.details[:120]}")

            stepping = threading.Thread(target=long_step)
            stepping.start()
            time.sleep(0.5)
            first = last = time.monotonic()
            server.proc.send_signal(signal.SIGTERM)
            for _ in range(signals - 1):
                time.sleep(SECOND_SIGNAL_GAP_S)
                last = time.monotonic()
                server.proc.send_signal(signal.SIGTERM)
            code, ended = wait_exit(server.proc)
            stepping.join(timeout=15)
    finally:
        if connection:
            connection.close()
        server.kill()
    return {"exit_code": code, "after_first_s": ended - first, "after_last_s": ended - last,
            "step_reply": replies[0] if replies else None,
            "log": [line for line in server.lines if "SIGTERM" in line or "stop" in line][-3:]}


def stop_signals(repeats: int) -> dict:
    cases = {
        "idle": ("no sessions, no connections", lambda: stop_idle(peer=False)),
        "idle_silent_peer": ("no sessions; one connection that never answers GOAWAY", lambda: stop_idle(peer=True)),
        "mid_step": ("a long Step in flight", lambda: stop_mid_step(signals=1, peer=False)),
        "second_signal": (f"a long Step in flight and a silent peer; a second SIGTERM {SECOND_SIGNAL_GAP_S:g} s "
                          "after the first", lambda: stop_mid_step(signals=2, peer=True)),
    }
    expected = {"idle": 0, "idle_silent_peer": 0, "mid_step": 0, "second_signal": 1}
    results = {}
    for name, (what, run) in cases.items():
        runs = [run() for _ in range(repeats)]
        times = [r["after_first_s"] for r in runs]
        codes = [r["exit_code"] for r in runs]
        entry = {"what": what, "runs": runs, "exit_codes": codes, "after_first_s": {
            "median": float(np.median(times)), "max": float(max(times))}}
        if name == "second_signal":
            after_last = [r["after_last_s"] for r in runs]
            entry["after_second_s"] = {"median": float(np.median(after_last)), "max": float(max(after_last))}
            entry["ok"] = all(c == 1 for c in codes) and max(after_last) < 0.7
        else:
            entry["ok"] = all(c == expected[name] for c in codes) and max(times) < 2.0
        results[name] = entry
    return results


# --- the page --------------------------------------------------------------------------------------------

def _codes(counts: dict[str, int]) -> str:
    return ", ".join(f"`{code}` {n:,}" for code, n in sorted(counts.items(), key=lambda item: -item[1]))


def _yes(value: bool) -> str:
    return "yes" if value else "**no**"


def render(machine: dict, server: dict, results: dict, wall_s: float) -> str:
    fuzz, soft, hard = results["network_fuzz"], results["soft_limit_flood"], results["hard_limit_flood"]
    soaked, stops = results["soak"], results["stop_signals"]
    lines = [
        "# Robustness: fuzzing, soak, limits", "",
        "What keeps a server up whatever its clients send, and how it is checked. The limits and error codes",
        "themselves are in [protocol.md](protocol.md#errors); access control in",
        "[protocol.md](protocol.md#access-control).", "",
        f"The numbers on this page are generated by `bench/robustness.py` (raw results in",
        "[benchmarks/robustness.json](benchmarks/robustness.json)); edit the script, not the page. Measured on",
        f"{machine['date']}: {machine['cpu_model']}, {machine['cores']} cores, {machine['memory_gb']:g} GB, "
        f"{machine['platform']}; load average {machine['load_average_at_start'][0]:g} at the start (a shared "
        f"machine); server {server['version']} (build {server['build_id']}) on {server['grpc_library']}. "
        f"The run took {wall_s / 60:.1f} minutes.", "",
        "## Coverage-guided fuzzing (`tests/fuzz/`)",
        "Three libFuzzer targets, built by clang with the address and undefined-behaviour sanitizers in a",
        "build of their own (`build-fuzz/`):", "",
        "| target | input | what must hold |",
        "|---|---|---|",
        "| `fuzz_scene` | a `SceneSpec` as bytes -> `SceneFromWire` -> `CompileModel` | refused only with the wire's "
        "or the engine's error types; no crash, no sanitizer report |",
        "| `fuzz_snapshot` | snapshot bytes -> `RestoreSnapshot` (behind the HMAC seal: what a key holder could "
        "send) | a refused blob leaves the state unchanged; an accepted one steps without a crash |",
        "| `fuzz_action` | a `StepRequest` -> `ActionFromWire` -> validation -> one `Step` | no crash, no "
        "non-finite joint |", "",
        "```bash",
        "bash tests/fuzz/run_fuzz.sh 300        # each target 5 minutes; findings land in build-fuzz/findings/",
        "```", "",
        "The test suite runs each for 12 s from the committed corpus (`tests/fuzz/corpus/<target>`; seeds",
        "from `tests/fuzz/make_corpus.py`, and for snapshots from the target itself with",
        "`CULINARYCUT_FUZZ_WRITE_SEEDS=DIR`). New inputs go to a scratch copy; a finding worth keeping is",
        "copied into the corpus by hand with the fix. `fuzz_scene` pins the resolution to a coarse grid so",
        "each input takes milliseconds; the particle, grid and substep budgets have their own tests.", "",
        "## Network fuzz",
        "Random requests to every RPC of both services (`culinarycut.wire_fuzz`): 30 % random bytes (often not",
        "even a valid message) and the rest messages of the method's type with random values (NaN, infinities,",
        "1e300, huge counts, 5,000-character strings, NUL bytes) in random fields, one after another on one",
        f"connection, each with a {fuzz['deadline_s']:g} s deadline. `tests/python/test_network_fuzz.py` sends the "
        f"first 1,500 of the same seed ({fuzz['seed']}) and also checks that every `INVALID_ARGUMENT` names its",
        "field; this run sends more:", "",
        "| requests | of which | status codes |",
        "|---|---|---|",
    ]
    for kind in (RANDOM_BYTES, RANDOM_MESSAGE):
        counts = fuzz["by_kind"][kind]
        lines.append(f"| {sum(counts.values()):,} | {kind} | {_codes(counts)} |")
    before, after = fuzz["server_before"], fuzz["server_after"] or {}
    lines += [
        "",
        f"{fuzz['requests']:,} requests to {fuzz['methods']} methods in {fuzz['wall_s']:.0f} s: "
        f"{'no crash' if fuzz['crash'] is None else '**a crash** at request ' + str(fuzz['crash']['index'])}, "
        f"{len(fuzz['hangs'])} hangs (`DEADLINE_EXCEEDED` after {fuzz['deadline_s']:g} s), {len(fuzz['unknown'])} `UNKNOWN`; the slowest answer "
        f"took {max(fuzz['slowest_s'].values()) * 1000:.0f} ms and the longest message was "
        f"{fuzz['longest_message_chars']} characters; gRPC health afterwards: {fuzz['health_after']}. The server's "
        f"RSS went from {before['rss_mb']:.1f} MB to {after.get('rss_mb', float('nan')):.1f} MB (peak "
        f"{after.get('peak_rss_mb', float('nan')):.1f} MB; the requests open sessions nobody closes, up to "
        f"`--max-sessions` 8), its descriptors from {before['descriptors']} to {after.get('descriptors', '?')}, "
        f"its threads from {before['threads']} to {after.get('threads', '?')}. `INTERNAL` for random bytes is gRPC's own "
        "answer, with an empty message, to a request it cannot decode, before the server's code runs (see "
        "[protocol.md](protocol.md#errors)); codes per method are in the JSON.", "",
        "## Connection flood",
        "Every connection holds a descriptor. The server raises its soft descriptor limit to the hard one at",
        "start and takes every TCP connection itself (`server/connection_gate.cc`): past `--max-connections`",
        "(default 1,024, lowered to what the descriptor limit allows at 3 descriptors per connection) or",
        "`--max-connections-per-address` (default 64) it closes new ones at once, and when `accept4` runs out",
        "of descriptors it frees a spare one to take and drop the connection, so its listener never dies.",
        "The connections it keeps it relays to gRPC on a private unix socket; gRPC closes a connection that",
        "has not finished its TLS/HTTP/2 handshake within 10 s or has carried no call for 10 minutes, and",
        "answers more calls than `--max-handler-threads` with `RESOURCE_EXHAUSTED` instead of new threads.", "",
        f"**Past the soft limit.** The server started with a soft limit of {soft['start_soft_limit']} "
        f"descriptors (hard {soft['limits_after_start']['hard']:,}) and raised it to "
        f"{soft['limits_after_start']['soft']:,}. {soft['connections_opened']:,} of {soft['connections_requested']:,} "
        "TCP connections that never speak HTTP/2 were opened in "
        f"{soft['open_s']:.2f} s from {len(FLOOD_SOURCES)} client addresses; the server then held {soft['server_descriptors']['during']:,} descriptors "
        f"(from {soft['server_descriptors']['before']}). A new client was served during the flood: "
        f"{_yes(soft['new_client_served_during'])}.",
    ]
    if soft["hold_s"]:
        released = soft["silent_connections_closed_by_server_after_s"]
        lines[-1] += (" The server closed the silent connections itself (the handshake timeout) "
                      + (f"{released:.1f} s after the flood began" if released is not None else
                         f"**not within {soft['hold_s']:g} s**") + ".")
    served_after = soft["new_client_served_after_s"]
    lines[-1] += (" After the flood's connections were closed a new client was served "
                  + (f"after {served_after * 1000:.0f} ms" if served_after is not None else "**never (30 s)**")
                  + f"; the server's descriptors were back to {soft['server_descriptors']['after_close']}. "
                  "`tests/python/test_call_lifecycle.py` checks this with 300 connections at a soft limit of 64.")
    recovered = hard["new_client_served_after_s"]
    counts = hard["gate_counts"] or {}
    lines += [
        "",
        f"**At the hard limit.** The server at {hard['limit']} descriptors, soft and hard (as `prlimit "
        f"--nofile={hard['limit']}:{hard['limit']}` sets them: no room to raise) with "
        f"`--max-connections-per-address {hard['per_address_cap']}`; it said `{hard['cap_line']}`. A client "
        f"connected first; then {HARD_FLOOD} connections from one address: a new client at another address was "
        f"served during that flood: {_yes(hard['other_address_served_during_one_address_flood'])}. Then "
        f"{HARD_FLOOD} more from {len(FLOOD_SOURCES)} addresses, which fill the total cap: the server held "
        f"{hard['server_descriptors']['during']} descriptors and logged "
        + (f"`{_log_message(hard['accept_errors'][0])}`" if hard["accept_errors"] else "no accept error")
        + f"; a new client during it was served: {'yes' if hard['new_client_served_during'] else 'no (the cap)'}; "
        f"the client connected before the flood went on being served: {_yes(hard['earlier_client_served_during'])} "
        f"during, {_yes(hard['earlier_client_served_after'])} after. After the flood's connections were closed "
        f"(the server's descriptors fell back to {hard['server_descriptors']['after_close']}) a new client was served "
        + (f"after {recovered * 1000:.0f} ms." if recovered is not None else
           f"**never**: not in {hard['waited_s']:g} s of trying.")
        + (f" The gate relayed {counts['relayed']} connections and closed {counts['refused_address_cap']} at the "
           f"per-address cap, {counts['refused_total_cap']} at the total cap and {counts['refused_no_descriptor']} "
           "for want of a descriptor." if counts else ""),
        "",
        "Without the gate, gRPC 1.51 (Debian 12's) stopped accepting for good after its first `accept4` failed",
        "with `EMFILE` (grpc/grpc#20418; fixed upstream in July 2023 by grpc/grpc#33656): in the same flood a",
        "new client was never served again, even after the descriptors were free. `tests/python/test_call_lifecycle.py`",
        "checks both floods; `tests/server/test_connection_gate.cc` checks the relay and the caps. What a",
        "deployment still wants: a hard limit well above the connections it expects (`ulimit -Hn`;",
        "`LimitNOFILE=` under systemd; `--ulimit nofile=` or compose's `ulimits:` in a container), and behind",
        "a proxy or NAT, where every client shares one address, a `--max-connections-per-address` as high as",
        "`--max-connections`. The relay's cost on a Step is in [benchmarks/tls_overhead.md](benchmarks/tls_overhead.md).",
    ]
    robot, cutting = soaked["robot_only"], soaked["cutting"]
    lines += [
        "",
        "## Soak",
        f"A short soak on one server: {robot['episodes']:,} robot-only episodes (create, reset, 20 steps, close) in "
        f"{robot['seconds']:.0f} s, then {cutting['episodes']} cutting episodes (the oracle cutting a draft cucumber, "
        f"no cameras; {cutting['complete']} finished their plan), the server's RSS read from /proc.", "",
        "| phase | episodes | RSS after warm-up (MB) | slope (kB / episode) |",
        "|---|---|---|---|",
    ]
    for label, phase in (("robot-only", robot), ("cutting", cutting)):
        if "min_mb" in phase:
            # A trend over a handful of samples is noise: shown from 10 samples on.
            sampled = sum(episode >= phase["warmup_episodes"] for episode, _ in phase["samples"])
            slope = f"{phase['slope_kb_per_episode']:.2f}" if sampled >= 10 else "too few episodes for a trend"
            lines.append(f"| {label} (after {phase['warmup_episodes']} warm-up) | {phase['episodes']:,} | "
                         f"{phase['min_mb']:.1f} - {phase['max_mb']:.1f} | {slope} |")
    lines += [
        "",
        f"The server's descriptors went from {soaked['descriptors']['before']} to {soaked['descriptors']['after']} "
        f"and it ended with {soaked['threads_after']} threads. The long soak (thousands of episodes, 50 cutting "
        "ones, and why a closed session's memory goes back to the system) is `bench/soak.py`, in",
        "[benchmarks/soak.md](benchmarks/soak.md).", "",
        "## Stopping",
        "On SIGTERM (or SIGINT) a Step in flight stops at its next check between substeps and is rolled back",
        "(`UNAVAILABLE`: the server is shutting down, nothing applied); other calls still running after 1 s",
        "are cancelled; the server exits 0 within 2 s, else exits 1 at 2 s without waiting further. A second",
        "signal before the clean exit ends exits at once, code 1, the log saying `second stop signal`. Exit",
        f"times from the signal to the process's exit as its parent sees it, {len(stops['idle']['runs'])} "
        f"run{'s' if len(stops['idle']['runs']) > 1 else ''} each:", "",
        "| case | exit codes | after the first signal: median, max (s) | after the second (s) |",
        "|---|---|---|---|",
    ]
    for name in ("idle", "idle_silent_peer", "mid_step", "second_signal"):
        entry = stops[name]
        second = (f"{entry['after_second_s']['median']:.3f}, {entry['after_second_s']['max']:.3f}"
                  if "after_second_s" in entry else "")
        lines.append(f"| {entry['what']} | {', '.join(str(c) for c in entry['exit_codes'])} | "
                     f"{entry['after_first_s']['median']:.3f}, {entry['after_first_s']['max']:.3f} | {second} |")
    step_replies = sorted({r["step_reply"] for r in stops["mid_step"]["runs"] if r["step_reply"]})
    lines += [
        "",
        "A connection that never answers the server's GOAWAY (a stalled or hostile peer) holds the clean",
        "shutdown until the 1 s grace deadline, whatever the machine's speed; a well-behaved client closes",
        "at once. That second is also what makes the second signal testable: without such a peer the clean",
        "exit after a mid-step SIGTERM takes tens of milliseconds, too short to land a second signal in",
        "reliably; with one, `tests/python/test_call_lifecycle.py` sends it 0.3 s after the first and checks",
        "exit code 1 at once. The long Step's caller got: " + ("; ".join(f"`{r}...`" for r in step_replies) or "nothing")
        + ".", "",
        "## Reproduce",
        "```bash",
        "export CULINARYCUT_SERVER=build/server/culinarycut-server",
        "nice .venv/bin/python bench/robustness.py            # this page and benchmarks/robustness.json",
        "nice .venv/bin/python bench/robustness.py --quick    # seconds; prints, writes nothing",
        "```",
    ]
    return "\n".join(lines) + "\n"


def _log_message(line: str) -> str:
    """gRPC's log line without its time stamp and thread id: `tcp_server_posix.cc:205] Failed accept4: ...`."""
    match = re.search(r"(\S+\.cc:\d+\]\s+.*)$", line)
    return re.sub(r"\s+", " ", match.group(1)) if match else line


# --- main ------------------------------------------------------------------------------------------------

def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="a seconds-long run that prints its page (and writes it only under an --out given)")
    parser.add_argument("--out", help="where robustness.md and benchmarks/ go (default docs/)")
    parser.add_argument("--from-json", metavar="JSON", help="measure nothing: write the page again from a saved "
                        "run's robustness.json (after editing the prose here)")
    args = parser.parse_args()
    if args.from_json:
        saved = json.loads(Path(args.from_json).read_text())
        (Path(args.out or ROOT / "docs") / "robustness.md").write_text(
            render(saved["machine"], saved["server"], saved["results"], saved["wall_s"]))
        return 0
    sizes = QUICK if args.quick else FULL
    machine = machine_info()
    with ServerProcess(server_binary(), max_sessions=1) as probe, Client(probe.address) as client:
        info = client.server_info()
        server = {"binary": str(server_binary()), "version": info.version, "build_id": info.build_id,
                  "grpc_library": grpc_library(probe.proc.pid)}
    started = time.monotonic()
    results = {}
    steps = [("network_fuzz", lambda: network_fuzz(sizes["fuzz_requests"])),
             ("soft_limit_flood", lambda: soft_limit_flood(sizes["flood_connections"], sizes["flood_hold_s"])),
             ("hard_limit_flood", lambda: hard_limit_flood(sizes["hard_recovery_wait_s"])),
             ("stop_signals", lambda: stop_signals(sizes["stop_repeats"])),
             ("soak", lambda: soak(sizes["robot_episodes"], sizes["cutting_episodes"]))]
    for name, run in steps:
        t0 = time.monotonic()
        results[name] = run()
        print(f"{name}: {time.monotonic() - t0:.1f} s", file=sys.stderr, flush=True)
    wall_s = time.monotonic() - started
    checks = {"network_fuzz": results["network_fuzz"]["ok"], "soft_limit_flood": results["soft_limit_flood"]["ok"],
              "hard_limit_flood": results["hard_limit_flood"]["ok"],
              "soak": results["soak"]["ok"],
              **{f"stop_{name}": entry["ok"] for name, entry in results["stop_signals"].items()}}
    page = render(machine, server, results, wall_s)
    if args.quick and not args.out:  # a smoke pass never writes into docs/
        print(page)
    else:
        out = Path(args.out or ROOT / "docs")
        (out / "benchmarks").mkdir(parents=True, exist_ok=True)
        (out / "benchmarks" / "robustness.json").write_text(json.dumps(
            {"machine": machine, "server": server, "sizes": sizes, "checks": checks, "results": results,
             "wall_s": wall_s}, indent=1) + "\n")
        (out / "robustness.md").write_text(page)
        print(page)
    failed = [name for name, ok in checks.items() if not ok]
    print("checks: " + ("all passed" if not failed else "FAILED: " + ", ".join(failed)), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

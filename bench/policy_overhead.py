#!/usr/bin/env python3
"""Benchmark: what each policy adapter and transport adds per query (preprocessing + encoding + round
trip to a stand-in model that does nothing), as a ratio to the server's own Step time measured side by
side in the same episode: every control step calls the adapter's act, then the env's step, on a real
server with the adapter's cameras (256 x 256, draft cutting scene). Each adapter is set to query on every
step; the stand-ins run in their own processes. The policy protocol (--policy grpc) is measured the same
way against `culinarycut policy serve noop` (the whole observation as tensors, with and without a 256 x 256
camera). Writes docs/benchmarks/policy_overhead.{md,json}.

    .venv/bin/python bench/policy_overhead.py [--steps 100 --rounds 3]
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from datetime import date
from pathlib import Path

import numpy as np
from culinarycut import Client, CulinaryCutEnv
from culinarycut.bench.episode_scene import suite_episodes
from culinarycut.bench.suite import load_suite
from culinarycut.launch import ServerProcess, server_binary
from culinarycut.policies.grpc_policy import GrpcPolicy
from culinarycut_policies.octo import OctoPolicy
from culinarycut_policies.openpi import OpenPIPolicy
from culinarycut_policies.openvla import OpenVLAPolicy
from culinarycut_policies.openvla_oft import OpenVLAOFTPolicy
from culinarycut_policies.rdt import RDTPolicy
from culinarycut_policies.standins import example_statistics
from culinarycut_policies.standins.process import StandinProcess

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import machine_info  # noqa: E402  (the machine description every benchmark writes)

ROOT = Path(__file__).resolve().parents[1]

# name: (adapter class, stand-in model, transport, options that make it query every step)
ADAPTERS = {
    "openvla": (OpenVLAPolicy, "openvla", "REST + json-numpy", {"unnorm_key": example_statistics.DELTA_KEY}),
    "openvla (0.9 crop)": (OpenVLAPolicy, "openvla", "REST + json-numpy",
                           {"unnorm_key": example_statistics.DELTA_KEY, "center_crop": True}),
    "openvla-oft": (OpenVLAOFTPolicy, "openvla-oft", "REST + json-numpy",
                    {"unnorm_key": example_statistics.DELTA_KEY, "execute_steps": 1}),
    "octo": (OctoPolicy, "octo", "websocket + msgpack", {"unnorm_key": example_statistics.DELTA_KEY,
                                                          "wrist_camera": "wrist"}),
    "rdt": (RDTPolicy, "rdt", "websocket + msgpack", {"unnorm_key": example_statistics.RDT_KEY, "execute_steps": 1,
                                                        "normalization": "bounds"}),
    "openpi": (OpenPIPolicy, "openpi", "websocket + msgpack", {"replan_steps": 1}),
}
# name: the `culinarycut policy serve noop` arguments of its policy server (one action per Act, at the
# simulator's rate: a query every step)
GRPC_POLICIES = {
    "grpc (front 256 x 256)": ["--camera", "front=256x256"],
    "grpc (state only)": [],
}
GRPC_TRANSPORT = "gRPC + tensors"


class PolicyServeProcess:
    """`culinarycut policy serve noop` in its own process, as a policy server in another language would be."""

    def __init__(self, *args: str):
        self.proc = subprocess.Popen([sys.executable, "-m", "culinarycut", "policy", "serve", "noop", "--listen",
                                      "127.0.0.1:0", *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     text=True)
        first = self.proc.stdout.readline()
        if not first.startswith("serving policy"):
            self.proc.kill()
            raise RuntimeError(f"policy serve did not start: {first}{self.proc.stdout.read()}")
        self.url = first.split()[-1]

    def close(self) -> None:
        self.proc.terminate()
        self.proc.wait(10)


def measure(address: str, scene: dict, instruction: str, policy, steps: int) -> dict:
    """Per step: act (ms), the transport's share of it (ms), env.step (ms)."""
    scene = {**scene, "cameras": [dict(c) for c in policy.cameras], "task": {"instruction": instruction}}
    act_ms, transport_ms, step_ms = [], [], []
    with CulinaryCutEnv(address, scene=scene, control_mode=policy.control_mode) as env:
        observation, info = env.reset(seed=0)
        policy.reset(instruction, {"seed": 0, "control_frequency_hz": 1.0 / env.control_timestep})
        try:
            for i in range(steps + 1):  # the first step warms connection, caches and buffers
                queries = len(policy.latency.seconds)
                started = time.perf_counter()
                mode, action = policy.act(observation)
                acted = time.perf_counter()
                observation, *_ = env.step(action)
                stepped = time.perf_counter()
                if len(policy.latency.seconds) != queries + 1:
                    raise RuntimeError(f"{policy.name} did not query at step {i}: the benchmark needs one per step")
                if i:
                    act_ms.append(1e3 * (acted - started))
                    transport_ms.append(1e3 * policy.latency.seconds[-1])
                    step_ms.append(1e3 * (stepped - acted))
        finally:
            policy.close()
    return {"act_ms": act_ms, "transport_ms": transport_ms, "step_ms": step_ms}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=100, help="measured steps per adapter and round")
    parser.add_argument("--rounds", type=int, default=3, help="rounds over all adapters, alternating")
    parser.add_argument("--out", default=str(ROOT / "docs" / "benchmarks"))
    args = parser.parse_args()
    spec = suite_episodes(load_suite("smoke"))[0]  # the cucumber ratio cut at draft
    names = list(ADAPTERS) + list(GRPC_POLICIES)
    samples = {name: {"act_ms": [], "transport_ms": [], "step_ms": []} for name in names}
    with tempfile.TemporaryDirectory() as folder:
        statistics = str(example_statistics.write_statistics(Path(folder)))
        server = ServerProcess(server_binary())
        standins = {}
        try:
            with Client(server.address) as client:
                instruction = client.tasks.generate_instructions(spec.task.cut_spec(), seed=spec.seed, count=1)[0]
            for name, (_, model, _, _) in ADAPTERS.items():
                extra = ["--statistics", statistics, "--unnorm-key", example_statistics.DELTA_KEY] \
                    if model.startswith("openvla") else []
                standins[name] = StandinProcess(model, "--mode", "zero", *extra)
            for name, serve_args in GRPC_POLICIES.items():
                standins[name] = PolicyServeProcess(*serve_args)
            for _ in range(args.rounds):
                for name in names:
                    if name in GRPC_POLICIES:
                        policy = GrpcPolicy(url=standins[name].url)
                    else:
                        cls, model, _, options = ADAPTERS[name]
                        kwargs = {} if model == "openpi" else {"statistics": statistics}
                        policy = cls(url=standins[name].url, **kwargs, **options)
                    for key, values in measure(server.address, spec.scene, instruction, policy, args.steps).items():
                        samples[name][key] += values
        finally:
            for standin in standins.values():
                standin.close()
            server.stop()
    results = {}
    for name, s in samples.items():
        act, transport, step = (np.asarray(s[k]) for k in ("act_ms", "transport_ms", "step_ms"))
        transport_name = ADAPTERS[name][2] if name in ADAPTERS else GRPC_TRANSPORT
        results[name] = {"transport": transport_name, "queries": int(act.size),
                         "act_p50_ms": float(np.median(act)), "act_p90_ms": float(np.percentile(act, 90)),
                         "transport_p50_ms": float(np.median(transport)),
                         "preprocess_p50_ms": float(np.median(act - transport)),
                         "server_step_p50_ms": float(np.median(step)),
                         "ratio_act_to_step_p50": float(np.median(act) / np.median(step))}
    machine = {**machine_info(), "date": date.today().isoformat()}
    out = Path(args.out)
    (out / "policy_overhead.json").write_text(json.dumps({"machine": machine, "steps": args.steps,
                                                          "rounds": args.rounds, "results": results}, indent=1))
    lines = ["# Policy adapters: overhead per query", "",
             "Generated by `bench/policy_overhead.py`: each adapter drives a draft cucumber-cut session of a local "
             "server with its own cameras (256 x 256 RGB; front, plus wrist where the adapter asks for it), "
             "querying its stand-in model server (its own process, `--mode zero`: the model does nothing) on every "
             "control step. Per step the adapter's `act` (preprocessing, encoding, round trip, decoding, "
             "post-processing) and the env's `step` (the server's Step with rendering and the observation's "
             f"transfer) are timed side by side; {args.rounds} rounds of {args.steps} steps per adapter, "
             "adapters alternating. The policy protocol (`--policy grpc`, "
             "[policy_protocol.md](../policy_protocol.md)) is measured the same way against "
             "`culinarycut policy serve noop` in its own process: every step "
             "sends the whole observation as tensors (the state, and with a camera its 256 x 256 RGB image and "
             "parameters, raw) and decodes the answer's action.", "",
             f"Machine: {machine['cpu_model']}, {machine['cores']} cores, {machine['platform']}; {machine['date']}.", "",
             "| adapter | transport | act p50 (ms) | act p90 (ms) | of which transport p50 (ms) | preprocessing p50 (ms) "
             "| server step p50 (ms) | act / step (p50) |", "|---|---|---|---|---|---|---|---|"]
    for name, r in results.items():
        lines.append(f"| {name} | {r['transport']} | {r['act_p50_ms']:.2f} | {r['act_p90_ms']:.2f} | "
                     f"{r['transport_p50_ms']:.2f} | {r['preprocess_p50_ms']:.2f} | {r['server_step_p50_ms']:.2f} | "
                     f"{r['ratio_act_to_step_p50']:.3f} |")
    lines += ["", "Transport is what `LatencyLog` (for grpc, `GrpcPolicy.latency`) records per query: encoding, "
              "the loopback round trip with the "
              "stand-in's decoding and encoding, and decoding the answer; preprocessing is the rest of `act` "
              "(resizes, crops, padding, normalisation, the action's conversion). A real model adds its own "
              "inference time on top; with OpenVLA-OFT, RDT and openpi executing chunks open loop, the per-step "
              "cost is this per-query cost divided by the steps executed per chunk. A grpc policy does its own "
              "preprocessing in its server, so its `act` is nearly all transport; without a camera the server's "
              "step renders nothing and is much shorter, hence the larger ratio at a smaller cost."]
    (out / "policy_overhead.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())

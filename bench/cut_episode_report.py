#!/usr/bin/env python3
"""Wall time of the end-to-end example cut (examples/cut_cucumber.py: the oracle cuts a real cucumber at
0.3 from the left through the server, three 224 x 224 RGB cameras) at each quality setting, per
episode and per simulated second, split by stage: robot (control + physics), MPM (substeps +
topology), rendering, and RPC + client (everything the server's stages do not account for:
transport, serialisation, image decoding, the oracle's calls). The settings are the presets and two
from the accuracy study (docs/accuracy.md): the standard preset as it was before the study chose it
(8 ppc, CFL 0.2) and the standard preset with mass scaling x16, so the speed-ups are measured side by
side in one run. Writes docs/benchmarks/cut_episode.md, .json and docs/images/cut_episode_stages.png.

    .venv/bin/python bench/cut_episode_report.py [--settings draft standard ...] [--max-wall-s 900] [--render-only]

An episode that runs past --max-wall-s is stopped; its row then covers the simulated time reached
and is marked partial (its cut-phase rate still says what a simulated second of cutting costs).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from culinarycut import Client
from culinarycut.launch import ServerProcess
from culinarycut.policies import run_oracle_episode
from culinarycut.scenes import CUT_CUCUMBER_INSTRUCTION, cut_cucumber_scene

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import Docs, arguments, docs_for, machine_info, pyplot, save_figure, today  # noqa: E402
from bench.lib import quick  # noqa: E402
from bench.lib.accuracy import standard_verdict  # noqa: E402

PAGE, RESULTS = "benchmarks/cut_episode.md", "benchmarks/cut_episode.json"
STAGES = ("robot", "mpm", "render", "rpc_client")


def stage_split(trace: dict) -> dict:
    server = trace["stage_wall_s"]
    split = {"robot": server.get("control", 0.0) + server.get("physics", 0.0),
             "mpm": server.get("mpm", 0.0) + server.get("topology", 0.0),
             "render": server.get("render", 0.0)}
    split["rpc_client"] = max(0.0, trace["client_wall_s"] - sum(split.values()))
    return split


# Named settings: a preset, and explicit MPM values over it.
SETTINGS = {
    "draft": ("draft", {}),
    "standard": ("standard", {}),
    # The standard preset until the accuracy study.
    "previous standard": ("standard", {"cfl": 0.2, "particles_per_cell": 8}),
    "standard, mass x16": ("standard", {"mass_scaling": 16.0}),
    "fine": ("fine", {}),
}
# The side-by-side speed-up the accuracy study's target asks for: this setting over the previous standard.
FAST, YARDSTICK = "standard, mass x16", "previous standard"
# The two episodes the target compares run again after the others, and each keeps its fastest run: the machine's
# drift only ever slows a run down.
REPEATED = ("standard", YARDSTICK)


def measure(client: Client, preset: str, max_wall_s: float, tiny: bool = False) -> dict:
    """One episode at a setting; `tiny`: a coarse strawberry at 32 px (the smoke pass)."""
    quality, mpm = SETTINGS[preset]
    scene = cut_cucumber_scene(CUT_CUCUMBER_INSTRUCTION, quality, 224, 224)
    if mpm:
        scene["mpm"] = dict(mpm)
    if tiny:
        scene = quick.food_scene(scene, coarse=True)
    print(f"{preset}: running the episode (stops after {max_wall_s:.0f} s of wall time)...", flush=True)

    def progress(step, observation, info):
        if step % 20 == 0:
            print(f"  {preset} step {step} t={info['sim_time']:.2f} s", flush=True)

    trace = run_oracle_episode(client, scene, on_step=progress, max_wall_s=max_wall_s)
    sim_s = trace["time_s"][-1] if trace["time_s"] else 0.0
    contact = trace["first_contact_step"]
    end = trace["terminated_step"] or trace["steps"]
    cut_wall_s = float(np.sum(trace["step_wall_s"][contact - 1:end])) if contact else 0.0
    control_period_s = trace["time_s"][0] if trace["time_s"] else 0.0  # the first step's sim time
    cut_sim_s = (end - contact + 1) * control_period_s if contact else 0.0
    row = {"preset": preset, "complete": trace["complete"], "success": trace["success"], "steps": trace["steps"],
           "sim_s": sim_s, "wall_s": trace["client_wall_s"], "stages_s": stage_split(trace),
           "particles": trace["mpm_particles"], "mpm_substeps": trace["mpm_substeps"],
           "resolution": trace["resolution"], "cut_wall_s": cut_wall_s, "cut_sim_s": cut_sim_s,
           "error": trace["score"].get("required", [{}])[0].get("position_error_fraction"),
           "peak_wrist_force_n": float(np.linalg.norm(trace["wrist_force_n"], axis=1).max()) if trace["steps"] else 0.0}
    row["wall_per_sim_s"] = row["wall_s"] / sim_s if sim_s else float("nan")
    row["cut_wall_per_sim_s"] = cut_wall_s / cut_sim_s if cut_sim_s else float("nan")
    print(f"  {preset}: {row['wall_s']:.1f} s wall for {sim_s:.2f} s simulated, {row['particles']} particles, "
          f"stages {({k: round(v, 1) for k, v in row['stages_s'].items()})}", flush=True)
    return row


def plot(rows: list[dict], path: Path) -> None:
    fig, ax = pyplot().subplots(figsize=(7, 3.2), dpi=120)
    width = 0.8 / len(STAGES)
    for k, (stage, colour) in enumerate(zip(STAGES, ("tab:blue", "tab:orange", "tab:green", "tab:gray"))):
        values = [row["stages_s"][stage] / row["sim_s"] for row in rows]
        ax.bar(np.arange(len(rows)) + (k - 1.5) * width, values, width, label=stage.replace("_", " + "), color=colour)
    ax.set_xticks(np.arange(len(rows)), [r["preset"] + ("" if r["complete"] else " (partial)") for r in rows])
    ax.set_yscale("log")
    ax.set_ylabel("wall s per simulated s")
    ax.set_title("example cut: wall time per simulated second of the episode, by stage")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, path, dpi=None)


def main() -> int:
    parser = arguments(__doc__, whole_doc=True, render_only=True)
    parser.add_argument("--settings", nargs="+", default=["draft", "standard", YARDSTICK, FAST],
                        choices=list(SETTINGS), help="fine (dx 2 mm) takes most of an hour of 2 cores")
    parser.add_argument("--max-wall-s", type=float, default=900.0, help="per episode")
    args = parser.parse_args()
    docs = docs_for(args)
    if args.render_only:
        write_page(docs.stored(RESULTS), docs)
        return 0
    if args.quick:  # the smoke pass: the draft setting on a strawberry, 32 px cameras
        args.settings = ["draft"]
    rows: dict[str, dict] = {}
    repeats = list(REPEATED) if set(REPEATED) <= set(args.settings) else []
    server = ServerProcess(max_sessions=2, idle_timeout_s=3600)
    try:
        with Client(server.address, timeout_s=3600) as client:
            for preset in [*args.settings, *repeats]:
                row = measure(client, preset, args.max_wall_s, args.quick)
                runs = [*rows[preset]["wall_s_runs"], row["wall_s"]] if preset in rows else [row["wall_s"]]
                if preset not in rows or row["wall_s"] < rows[preset]["wall_s"]:
                    rows[preset] = row  # the fastest run: the machine's drift only ever slows a run down
                rows[preset]["wall_s_runs"] = runs
    finally:
        server.stop()
    stored = {"machine": machine_info(), "date": today(), "rows": list(rows.values())}
    docs.write_json(RESULTS, stored, __file__)
    write_page(stored, docs)
    return 0


def write_page(stored: dict, docs: Docs) -> None:
    """docs/benchmarks/cut_episode.md and its chart from a run's rows, machine and date."""
    rows = stored["rows"]
    lines = [
        "# End-to-end cut: wall time per preset",
        "",
        "Generated by `bench/cut_episode_report.py`: `examples/cut_cucumber.py`'s episode (the scripted",
        f"oracle: \"{CUT_CUCUMBER_INSTRUCTION}\", the real cucumber preset, three 224 x 224 RGB cameras",
        "rendered every step, 20 Hz control, 500 Hz robot physics) through a local server over TCP.",
        "",
        "Machine: {cpu_model}, {cores} cores, {platform}; llvmpipe rendering; ".format(**stored["machine"])
        + stored["date"] + ".",
        "",
        "Stages: robot = control + physics; MPM = substeps + piece detection; render = the three cameras;",
        "RPC + client = the rest of the client's wall time (transport, serialisation, decoding, the oracle's calls).",
        "",
        "| setting | dx (mm) | ppc | CFL | mass scaling | particles | MPM substeps | simulated s | wall s / episode | wall s per simulated s | cut phase: wall s per simulated s | robot s | MPM s | render s | RPC + client s | peak wrist force (N) | outcome |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        stages = row["stages_s"]
        episode = f"{row['wall_s']:.1f}"
        if not row["complete"]:
            episode = f"{row['wall_s']:.0f} (partial)"
        outcome = ("success" if row["success"] else "failed") if row["complete"] else "stopped at the wall-time cap"
        if row["error"] is not None and row["complete"]:
            outcome += f", error {100 * row['error']:.1f} % of the length"
        lines.append(
            f"| {row['preset']} | {1000 * row['resolution']['dx_m']:.0f} | {row['resolution']['particles_per_cell']} | "
            f"{row['resolution']['cfl']:g} | {row['resolution']['mass_scaling']:g} | "
            f"{row['particles']:,} | {row['mpm_substeps']:,} | {row['sim_s']:.2f} | {episode} | "
            f"{row['wall_per_sim_s']:.2f} | {row['cut_wall_per_sim_s']:.2f} | {stages['robot']:.2f} | "
            f"{stages['mpm']:.1f} | {stages['render']:.1f} | {stages['rpc_client']:.1f} | "
            f"{row['peak_wrist_force_n']:.1f} | {outcome} |")
    by_name = {row["preset"]: row for row in rows}
    yardstick = by_name.get(YARDSTICK)
    for name, accuracy in (("standard", standard_verdict()),
                           (FAST, "not as accurate: its windowed peak force is 1.4-2 % higher")):
        row = by_name.get(name)
        if row is None or yardstick is None or not (row["complete"] and yardstick["complete"]):
            continue
        walls, yard_walls = row.get("wall_s_runs", []), yardstick.get("wall_s_runs", [])
        repeated = (f"fastest of {len(walls)} runs each, run by run "
                    + ", ".join(f"{a / b:.2f}x" for a, b in zip(yard_walls, walls)) + "; ") if len(walls) > 1 else ""
        lines += ["", f"**{name}** against the **{YARDSTICK}** preset (8 ppc, CFL 0.2), side by side in this run: "
                  f"{yardstick['wall_s'] / row['wall_s']:.2f}x less wall time per episode and "
                  f"{(yardstick['particles'] * yardstick['mpm_substeps']) / (row['particles'] * row['mpm_substeps']):.1f}x "
                  f"less MPM work ({repeated}"
                  f"{yardstick['wall_s']:.0f} s -> {row['wall_s']:.0f} s; MPM {yardstick['stages_s']['mpm']:.0f} s -> "
                  f"{row['stages_s']['mpm']:.0f} s); from first contact until the task succeeds "
                  f"{yardstick['cut_wall_s'] / row['cut_wall_s']:.1f}x ({yardstick['cut_wall_s']:.0f} s -> "
                  f"{row['cut_wall_s']:.0f} s); {accuracy} (docs/accuracy.md, docs/benchmarks/seed_spread.md)."]
    lines += ["", "Both run on today's server, which wakes the food 2.5 grid cells from the knife; the episode the "
              "accuracy study's 5x target was set against woke it 2 cm out. That comparison (in-process, without "
              "cameras, the whole episode and until the task succeeds) is docs/benchmarks/wake_margin.md.",
              "", "The accuracy of each setting against a converged reference is measured on cc-cut's cuts in "
              "docs/accuracy.md (a robot episode at the reference's resolution would take hours)."]
    lines += ["", "![stages per preset](../images/cut_episode_stages.png)", ""]
    docs.write_page(PAGE, "\n".join(lines), __file__, RESULTS, stored)
    plot(rows, docs.image("cut_episode_stages.png"))
    print("\n".join(lines))


if __name__ == "__main__":
    sys.exit(main())

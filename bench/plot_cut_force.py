#!/usr/bin/env python3
"""Plots a cc-cut run: the force of the food on the blade against time, with the knife height,
the contact strength c-hat and the damaged-particle count (docs/images/mpm_cut_force.png).

Usage: .venv/bin/python bench/plot_cut_force.py [OUT_DIR_OF_CC_CUT] [--image docs/images/mpm_cut_force.png]
Without OUT_DIR_OF_CC_CUT it first runs build/tools/cc_cut/cc-cut tools/cc_cut/examples/cucumber_middle.json
(docs/mpm.md's example cut) into a temporary folder. Needs python3-matplotlib (Debian).
"""
from __future__ import annotations

import csv
import json
import subprocess
import sys
import tempfile
from pathlib import Path

if __package__ in (None, ""):  # run as a file (python bench/NAME.py): import the bench package from the checkout
    sys.path[0] = str(Path(__file__).resolve().parents[1])
from bench.harness import ROOT, arguments, cc_cut, docs_for, missing, pyplot, save_figure  # noqa: E402
from bench.lib.cc_cut import scene as cut_scene  # noqa: E402

EXAMPLE = ROOT / "tools" / "cc_cut" / "examples" / "cucumber_middle.json"


def main() -> int:
    parser = arguments(__doc__, whole_doc=True)
    parser.add_argument("run_dir", type=Path, nargs="?", help="a cc-cut --out folder (default: run the example)")
    parser.add_argument("--image", type=Path, default=None, help="default docs/images/mpm_cut_force.png")
    parser.add_argument("--cc-cut", type=Path, default=cc_cut())
    args = parser.parse_args()
    docs = docs_for(args)
    args.image = args.image or docs.image("mpm_cut_force.png")
    if args.run_dir is not None:
        return plot(args.run_dir, args.image)
    if code := missing(args.cc_cut, "--cc-cut"):
        return code
    with tempfile.TemporaryDirectory() as tmp:
        example = EXAMPLE
        if args.quick:  # the smoke pass: a coarse banana instead of the example cucumber
            example = Path(tmp) / "scene.json"
            example.write_text(json.dumps(cut_scene("banana", 0.008, 0.5)))
        subprocess.run([str(args.cc_cut), str(example), "--out", f"{tmp}/out", "--quiet"], check=True)
        return plot(Path(tmp) / "out", args.image)


def plot(run_dir: Path, image: Path) -> int:
    """The figure of one cc-cut run's output folder."""
    steps_csv = run_dir / "steps.csv"
    if not steps_csv.is_file():
        print(f"error: {steps_csv} not found; run cc-cut with --out {run_dir} first", file=sys.stderr)
        return 2
    with steps_csv.open() as f:
        rows = list(csv.DictReader(f))
    column = lambda name: [float(r[name]) for r in rows]  # noqa: E731
    t_ms = [1e3 * t for t in column("t_s")]
    summary = json.loads((run_dir / "summary.json").read_text())
    scene = summary.get("scene", {})

    fig, (top, bottom) = pyplot().subplots(2, 1, figsize=(9, 6), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    # The paper averages the impulse over an accumulation window; one cell of knife travel
    # (dx / v) removes the cell-crossing sawtooth of the per-substep force.
    resolved = summary.get("resolved", {})
    dx = float(resolved.get("dx_m", 0.004))
    speed = abs(float(scene.get("knife", {}).get("descent_speed_m_s", 0.5)))
    window_s = dx / speed
    dts = column("dt_s")  # substeps may differ in length (a fast particle shortens them): weight by dt

    def averaged_over_window(values: list[float]) -> list[float]:
        """Impulse over the last dx / v of time divided by that time, at every substep."""
        out, start, impulse, time = [], 0, 0.0, 0.0
        for i, (value, dt) in enumerate(zip(values, dts)):
            impulse += value * dt
            time += dt
            while start < i and time - dts[start] >= window_s:
                impulse -= values[start] * dts[start]
                time -= dts[start]
                start += 1
            out.append(impulse / time)
        return out

    fz = column("blade_fz_n")
    averaged = averaged_over_window(fz)
    edge_averaged = averaged_over_window(column("edge_fz_n"))
    top.plot(t_ms, fz, color="tab:red", lw=0.6, alpha=0.5, label="blade, vertical, per substep (N)")
    top.plot(t_ms, averaged, color="darkred", lw=1.6, label=f"blade, vertical, averaged over dx / v = {1e3 * window_s:.0f} ms")
    top.plot(t_ms, edge_averaged, color="black", lw=1.0, ls=":", label="its edge's part (G_c L), averaged the same")
    # Across the blade is along the food's long axis (the blade's normal), whichever way the food lies.
    axis = resolved.get("food", {}).get("axis_direction", [1.0, 0.0, 0.0])
    across = [axis[0] * fx + axis[1] * fy for fx, fy in zip(column("blade_fx_n"), column("blade_fy_n"))]
    top.plot(t_ms, across, color="tab:orange", lw=0.8, label="blade, across the blade (N)")
    top.set_ylabel("force of the food on the knife (N)")
    top.grid(alpha=0.3)
    height = top.twinx()
    height.plot(t_ms, [1e3 * z for z in column("knife_z_m")], color="tab:blue", lw=1.0, ls="--", label="edge height")
    height.set_ylabel("knife edge height (mm)", color="tab:blue")
    lines = top.get_legend_handles_labels()
    more = height.get_legend_handles_labels()
    top.legend(lines[0] + more[0], lines[1] + more[1], loc="upper right", fontsize=8)
    bottom.plot(t_ms, column("c_hat"), color="tab:green", lw=1.0, label="contact strength c-hat")
    bottom.set_ylabel("c-hat")
    damaged = bottom.twinx()
    damaged.plot(t_ms, column("damaged"), color="tab:purple", lw=0.8, label="particles gaining damage")
    damaged.set_ylabel("damaging (per substep)", color="tab:purple")
    bottom.set_xlabel("time (ms)")
    bottom.grid(alpha=0.3)
    food = (scene.get("scene", {}).get("objects") or [{}])[0]
    fig.suptitle(f"cc-cut: {food.get('food', '?')} at scale {food.get('scale') or 1}, "
                 f"{len(summary['summary'].get('pieces', []))} pieces", fontsize=11)
    fig.tight_layout()
    save_figure(fig, image)
    print(f"wrote {image}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

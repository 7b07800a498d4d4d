"""Every benchmark, once: the single place that knows each one's script, page and JSON, what it measures, how long
a full run takes, and its smoke pass. `python -m bench list` prints it; `python -m bench index` turns it and the
JSON files into docs/benchmarks/README.md; the harness names each page's command from it.

Paths of pages, JSON and images are relative to docs/. A benchmark's `quick` arguments make its smoke pass (a tiny
case of the same code, seconds); `quick=None` leaves it out of the pass, and `why_not_quick` says why.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path


@dataclass(frozen=True)
class Benchmark:
    name: str
    module: str                 # bench/<module>.py: its main() runs it (command line as `python bench/<module>.py`)
    page: str | None            # the page it writes, relative to docs/
    json: str | None            # the JSON beside it (None only for figure generators, which have no page either)
    measures: str               # one line: what it measures
    duration: str               # a full run, roughly, on the project's 2-core machine
    needs: tuple[str, ...] = ()  # built binaries: "server", "cc-cut", "bench_<name>"
    args: tuple[str, ...] = ()   # arguments of the full run (beyond the script's defaults)
    quick: tuple[str, ...] | None = ("--quick",)  # arguments of the smoke pass; None: not in it
    quick_does: str = "a tiny case of the full run"
    quick_json: bool = True     # whether the smoke pass writes the JSON too (False: it renders the stored one)
    why_not_quick: str = ""
    images: tuple[str, ...] = field(default_factory=tuple)
    also_writes: tuple[str, ...] = ()  # files outside docs/ the full run writes (relative to the checkout)
    folder_option: str = "--docs"      # the option that points its output at another folder than docs/
    folder_under: str = ""             # ...and where under that folder (an option that names a page folder)

    @property
    def script(self) -> str:
        return f"bench/{self.module}.py"


BENCHMARKS: tuple[Benchmark, ...] = (
    # The engine and the server, in-process and over the wire.
    Benchmark("robot_step", "robot_step_report", "benchmarks/robot_step.md", "benchmarks/robot_step.json",
              "robot-only Step latency and throughput: C++ and Python clients, 20 and 500 Hz control, TCP and a Unix "
              "socket, beside the engine's own step", "2 min", ("server", "bench_step_latency"),
              quick_does="20 Hz only, 10 steps per client"),
    Benchmark("mpm_throughput", "mpm_throughput_report", "benchmarks/mpm_throughput.md",
              "benchmarks/mpm_throughput.json",
              "MPM cutting substep: particle-steps per second at 10k / 100k / 1M particles on 1 and 2 threads, the "
              "stage split and a roofline", "5-15 min (each configuration waits for an idle machine)",
              ("bench_mpm_throughput",),
              quick_does="10k particles on one thread, the triad and FMA, once, no idle gate"),
    Benchmark("mpm_peers", "mpm_peers", "benchmarks/mpm_peers.md", "benchmarks/mpm_peers.json",
              "MPM per core against Taichi's and Warp's CPU backends at equal work: a falling elastic block at 10k and "
              "100k particles on 1 and 2 threads, interleaved, with the centre of mass's drop compared",
              "5-10 min, plus installing the peers", ("bench_mpm_falling_block",), quick=None,
              why_not_quick="it installs Taichi and Warp from PyPI into a throwaway virtualenv (about 700 MB), and CI "
                            "has no network for that; --quick runs it on 10k particles, one thread, one round"),
    Benchmark("render_throughput", "render_throughput_report", "benchmarks/render_throughput.md",
              "benchmarks/render_throughput.json",
              "three-camera sets per second on llvmpipe with a 100k-particle food's surface, 224 and 640 px",
              "2 min", ("bench_render_throughput",), quick_does="224 px, table, whole food, RGB, one repetition"),
    Benchmark("render_frames", "render_frames", None, None,
              "the renderer's example images (scenes, cameras, channels) for docs/rendering.md", "10 s",
              ("bench_render_frames",), quick_does="every image, into the temporary folder",
              images=("images/render_table_whole_front_left_right.png", "images/render_channels_front.png")),
    Benchmark("tls_overhead", "tls_overhead", "benchmarks/tls_overhead.md", "benchmarks/tls_overhead.json",
              "what TLS and bearer tokens, and the connection gate's relay, add to a Step round trip against "
              "plaintext", "1 min", ("server",),
              quick_does="1 round of 3 steps"),
    Benchmark("soak", "soak", "benchmarks/soak.md", "benchmarks/soak.json",
              "server memory (RSS) over 5,000 robot-only and 50 cutting episodes", "40 min", ("server",),
              quick_does="20 robot-only episodes and 1 cut of a coarse strawberry", images=("images/soak_rss.png",)),
    Benchmark("ee_pose_tracking", "ee_pose_tracking", "benchmarks/ee_pose_tracking.md",
              "benchmarks/ee_pose_tracking.json",
              "how pd_ee_pose_quat converges to random knife poses", "1 min", ("server",),
              quick_does="2 targets", images=("images/ee_pose_tracking.png",)),
    Benchmark("oracle_tracking", "plot_cut_trajectories", "benchmarks/oracle_tracking.md",
              "benchmarks/oracle_tracking.json",
              "the scripted oracle's planned against executed knife path for every cut style (knife in free air)",
              "1 min", ("server",), quick_does="the first task only", images=("images/cut_trajectories.png",)),
    # Safety and policies.
    Benchmark("safety_overhead", "safety_overhead", "benchmarks/safety_overhead.md",
              "benchmarks/safety_overhead.json",
              "what the safety limiter costs per Step, off against on, in free air and cutting", "15 min", ("server",),
              quick_does="1 round of 3 steps; the cut of a coarse strawberry"),
    Benchmark("safety_dataset", "safety_dataset", "benchmarks/safety_dataset.md", "benchmarks/safety_dataset.json",
              "samples per hour of the safety module's force dataset (from the runs its header records)",
              "seconds (report only); 5-8 min with --run", quick_does="the report of the committed dataset",
              ),
    Benchmark("policy_overhead", "policy_overhead", "benchmarks/policy_overhead.md",
              "benchmarks/policy_overhead.json",
              "what each policy adapter and transport adds per query against stand-in models, beside the Step",
              "5 min", ("server",), quick=("--steps", "2", "--rounds", "1"), quick_does="1 round of 2 steps",
              folder_option="--out", folder_under="benchmarks"),
    # Suites and datasets.
    Benchmark("suite_throughput", "suite_throughput", "benchmarks/suite_throughput.md",
              "benchmarks/suite_throughput.json",
              "suite runner: episodes per hour, the harness's share, scaling with 1-4 servers", "40 min", ("server",),
              quick_does="one strawberry episode as the 1-server scaling run"),
    Benchmark("draft_lever", "draft_lever", "benchmarks/draft_lever.md", "benchmarks/draft_lever.json",
              "the draft preset's CFL in whole episodes: the smoke suite at the draft and at the previous draft's CFL, "
              "side by side, with each episode's time by stage", "10 min", ("server",),
              quick_does="one strawberry episode per setting, one round"),
    Benchmark("simd_lever", "simd_lever", "benchmarks/simd_lever.md", "benchmarks/simd_lever.json",
              "the MPM kernels at the CPU's best x86-64 level against the baseline (SSE2): the one-thread cutting "
              "substep and the smoke suite's episodes per hour, side by side", "10 min",
              ("server", "cc-cut", "bench_mpm_throughput"),
              quick_does="one kernel pair per size and one strawberry episode per level"),
    Benchmark("oracle_verdicts", "oracle_verdicts", "benchmarks/oracle_verdicts.md",
              "benchmarks/oracle_verdicts.json",
              "the oracle under the orientation-scoring success rule, each style's signature, both scenes and their "
              "render cost", "2-3 h (resumable)", ("server",),
              quick_does="one strawberry episode, one generated episode, 3 render steps"),
    Benchmark("draft_coverage", "draft_coverage", "benchmarks/draft_coverage.md", "benchmarks/draft_coverage.json",
              "the draft preset's reach: every food in every style, the oracle's middle cut", "20-35 min (resumable)",
              ("server",), quick_does="the strawberry's normal cut"),
    Benchmark("dataset_throughput", "dataset_throughput", "benchmarks/dataset_throughput.md",
              "benchmarks/dataset_throughput.json",
              "dataset episodes per hour at draft (`culinarycut data generate`), the export's cost, the paper's "
              "325,000 trajectories projected", "5 min", ("server",),
              quick_does="one strawberry episode at 32 px, its export"),
    Benchmark("dataset_throughput_standard", "dataset_throughput", "benchmarks/dataset_throughput_standard.md",
              "benchmarks/dataset_throughput_standard.json",
              "the same at the standard preset (a sample of the styles)", "10 min", ("server",),
              args=("--quality", "standard", "--styles", "normal"), quick=None,
              why_not_quick="the same script and code as dataset_throughput's smoke pass, at another preset"),
    # The robot cutting food.
    Benchmark("cut_episode", "cut_episode_report", "benchmarks/cut_episode.md", "benchmarks/cut_episode.json",
              "the example cut's wall time per quality setting, by stage (robot, MPM, render, RPC)", "40 min",
              ("server",), quick_does="the draft setting on a coarse strawberry, 32 px cameras",
              images=("images/cut_episode_stages.png",)),
    Benchmark("real_foods", "real_foods", "benchmarks/real_foods_standard.md", "benchmarks/real_foods_standard.json",
              "the Panda cuts a cucumber, an apple and a banana at the standard preset", "30-60 min", ("server",),
              args=("--quality", "standard"), quick=("--quality", "standard", "--quick"),
              quick_does="a coarse strawberry"),
    Benchmark("e_sweep", "e_sweep", "benchmarks/e_sweep.md", "benchmarks/e_sweep.json",
              "the paper's E-sweep through the robot: peak wrist force and the knife's speed after impact, E 0.1-0.9 "
              "MPa", "5 min", ("server",), quick_does="E 0.9 MPa on a coarse strawberry",
              images=("images/e_sweep.png",)),
    Benchmark("wake_margin", "wake_margin_report", "benchmarks/wake_margin.md", "benchmarks/wake_margin.json",
              "waking the food at 2.5 cells against 2 cm: MPM work and wall time of the example cut, in-process",
              "40 min", ("bench_wake_margin",), quick=("--render-only",),
              quick_json=False, quick_does="the page from the stored JSON only",
              why_not_quick="each run is a whole cucumber episode in-process at the standard preset (4-8 min) and "
                            "bench_wake_margin has no smaller case"),
    # The cutting physics (cc-cut).
    Benchmark("physics_validation", "physics_validation", "physics_validation.md",
              "benchmarks/physics_validation.json",
              "real foods cut at dx 6, 4 and 3 mm (the force follows the food, not the grid) and twice the toughness",
              "10 min", ("cc-cut",), quick_does="the banana at dx 8 and 6 mm",
              images=("images/physics_validation_refinement.png",)),
    Benchmark("lsdyna_calibration", "lsdyna_calibration", "benchmarks/lsdyna_calibration.md",
              "benchmarks/lsdyna_calibration.json",
              "the edge toughness calibrated against DiSECt's LS-DYNA knife references (potato prism, cucumber "
              "half-cylinder)", "15 min", ("cc-cut",), quick_does="the potato prism at dx 16 mm, one secant step",
              images=("images/lsdyna_reference.png",)),
    Benchmark("physics_cases", "physics_cases", "benchmarks/physics_cases.md", "benchmarks/physics_cases.json",
              "hard cases: the food turned on the grid, E from 0.1 to 50 MPa, twice the toughness, sawing, a thin "
              "slice",
              "30 min (resumable)", ("cc-cut",), quick_does="one case at draft"),
    Benchmark("robustness", "robustness", "robustness.md", "benchmarks/robustness.json",
              "the server attacked from outside: network fuzz, connection floods at the soft and hard descriptor "
              "limits and recovery, stop signals' exit times, a soak's memory", "10 min", ("server",),
              quick_does="a few hundred fuzz requests, a small flood, one stop of each kind, a short soak",
              folder_option="--out"),
    Benchmark("thread_policy", "thread_policy", "benchmarks/thread_policy.md", "benchmarks/thread_policy.json",
              "two sessions cutting at once: the cores shared among the Steps running against each Step taking "
              "its food's threads", "10 min", ("server",), quick=None,
              why_not_quick="a cutting food's control step is about 1,000 MPM substeps even at draft: the "
                            "smallest round of two servers and two sessions takes 30-50 s"),
    Benchmark("baselines", "baselines", "benchmarks/baselines.md", "benchmarks/baselines.json",
              "the learned policy (learning/) against the oracle and random on the suites, with Wilson intervals",
              "many hours on 2 cores (train on a GPU); resumable", ("server",),
              args=("--out", "studies/baseline", "--server", "127.0.0.1:50051"), quick=None,
              why_not_quick="it generates a dataset, trains a model and plays suites; ctest's "
                            "python_learning_end_to_end runs the same path at a tiny size",
              folder_under="benchmarks"),
    Benchmark("cstm_saw", "cstm_saw", "benchmarks/cstm_saw.md", "benchmarks/cstm_saw.json",
              "the paper's saw experiment: the learned policy trained on saw cuts against trained on normal cuts and "
              "restyled by the CSTM, beside the oracle, with the contact classifier's held-out accuracy",
              "1 h on 2 cores after the baselines study (it trains on that study's export); resumable", ("server",),
              args=("--out", "studies/cstm-saw", "--data", "studies/baseline/export", "--server", "127.0.0.1:50051"),
              quick=None,
              why_not_quick="it trains two policies, a classifier and a generator and plays saw cuts; ctest's "
                            "python_cstm runs each part at a tiny size"),
    Benchmark("step_rollback", "step_rollback_report", "benchmarks/step_rollback.md", "benchmarks/step_rollback.json",
              "a cancellable Step's rollback while the food sleeps: lazy against the full state copy it replaced, "
              "draft, standard and fine", "1 min", ("bench_step_rollback",), quick_does="draft, 3 rounds"),
    Benchmark("hertz_contact", "hertz_contact_report", "benchmarks/hertz_contact.md", "benchmarks/hertz_contact.json",
              "a plate pressing a sphere through the MPM solver against Hertz, at dx 4, 3 and 2 mm", "10 min",
              ("bench_hertz_contact",), quick_does="dx 8 mm", images=("images/hertz_contact.png",)),
    Benchmark("rate_sweep", "rate_sweep", "benchmarks/rate_sweep.md", "benchmarks/rate_sweep.json",
              "knife speed against cutting force, elastic and with a Maxwell branch", "20 min (resumable)", ("cc-cut",),
              quick_does="2 and 10 m/s at draft", images=("images/rate_sweep.png",)),
    Benchmark("grid_extent", "grid_extent", "benchmarks/grid_extent.md", "benchmarks/grid_extent.json",
              "1, 2 or 3 empty cells around the particles, and where a cut's time goes by stage", "15 min", ("cc-cut",),
              quick_does="the banana at dx 8 mm, once"),
    Benchmark("cut_force", "plot_cut_force", None, None,
              "the force on the blade during cc-cut's example cut, for docs/mpm.md", "1 min", ("cc-cut",),
              quick_does="a coarse banana cut", images=("images/mpm_cut_force.png",)),
    # The accuracy study and what reads it.
    Benchmark("accuracy_cost", "accuracy_cost", "accuracy.md", "benchmarks/accuracy_cost.json",
              "what accuracy costs: a grid of MPM quality settings against a fine reference, Pareto fronts, the "
              "presets chosen from them, the 5x target at the robot's speed", "2 h of 2 cores (resumable, --runs)",
              ("cc-cut",), quick_json=False,
              quick_does="the guard's cut at draft, then the page, plot and engine table from the stored study (the "
                         "table must be the committed one)",
              images=("images/accuracy_pareto.png",), also_writes=("sim/world/measured_accuracy_table.cc",)),
    Benchmark("seed_spread", "seed_spread", "benchmarks/seed_spread.md", "benchmarks/seed_spread.json",
              "how far the accuracy study's errors move with the particle seed, and which of its calls survive it",
              "1.5 h of 2 cores (shares the accuracy study's --runs)", ("cc-cut",), quick=("--render-only",),
              quick_json=False, quick_does="the page and plot from the stored JSON only",
              why_not_quick="every run is a 0.05 m/s cut (1.5-9 min each); its cut and error code is the accuracy "
                            "study's", images=("images/seed_spread.png",)),
)

_BY_NAME = {b.name: b for b in BENCHMARKS}


def get(name: str) -> Benchmark:
    try:
        return _BY_NAME[name]
    except KeyError:
        raise KeyError(f"no benchmark {name!r}; `python -m bench list` lists them") from None


def entry_for(script: str, page: str | None = None) -> Benchmark | None:
    """The benchmark whose script this is and, given a page, whose page it is (one script may make several pages,
    and a page made with other arguments than the registry's is no benchmark's); None where none is."""
    name = Path(script).as_posix()
    mine = [b for b in BENCHMARKS if b.script == name]
    if page is not None:
        return next((b for b in mine if b.page == page), None)
    return mine[0] if mine else None

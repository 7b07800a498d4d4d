"""What every benchmark shares: the machine it ran on (machine), interleaved repeated timing (timing), its page
and JSON written side by side with the date, build id and machine (output), plots (plotting), the build's
binaries (paths) and the C++ benchmarks' JSON reports (google_benchmark)."""
from bench.harness.google_benchmark import google_benchmark
from bench.harness.machine import (LoadSampler, build_id, cpu_model, dated_machine_info, idle_percent,
                                   machine_info, today, wait_for_idle)
from bench.harness.output import Docs, arguments, docs_for, machine_words, stamp, stamp_of
from bench.harness.paths import ROOT, bench_binary, build_dir, cc_cut, missing, server_binary, use_build
from bench.harness.plotting import pyplot, save_figure
from bench.harness.timing import fastest, interleaved, percentiles, spread

__all__ = ["Docs", "LoadSampler", "ROOT", "arguments", "bench_binary", "build_dir", "build_id", "cc_cut",
           "cpu_model", "dated_machine_info", "docs_for", "fastest", "google_benchmark", "idle_percent", "interleaved", "machine_info",
           "machine_words", "missing", "percentiles", "pyplot", "save_figure", "server_binary", "spread", "stamp",
           "stamp_of", "today", "use_build", "wait_for_idle"]

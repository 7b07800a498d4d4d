#!/usr/bin/env bash
# Configures and builds CulinaryCut in Release into build/ (server, clients, tests, benchmarks,
# and the Python stubs in client/python/culinarycut/v1).
# The MPM library is built for the baseline x86-64 (SSE2) and for each x86-64 level in
# CULINARYCUT_MPM_LEVELS (default x86-64-v3: AVX2, FMA; e.g. "x86-64-v3;x86-64-v4"); the loader runs the
# best one the CPU has, and --simd chooses another (docs/mpm.md, "Instruction sets").
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="${CULINARYCUT_JOBS:-$(nproc)}"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release \
  ${CULINARYCUT_MPM_LEVELS:+"-DCULINARYCUT_MPM_LEVELS=$CULINARYCUT_MPM_LEVELS"}
cmake --build "$root/build" -j "$jobs"

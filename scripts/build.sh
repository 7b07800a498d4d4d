#!/usr/bin/env bash
# Configures and builds CulinaryCut in Release into build/ (server, clients, tests, benchmarks,
# and the Python stubs in client/python/culinarycut/v1).
# CULINARYCUT_MARCH=x86-64-v3 (or native) builds for a newer CPU than the compiler's default (SSE2):
# the MPM runs about 1.2x faster with AVX2 and FMA, and rounds differently from the default build (a
# cut's peak force moved 0.09 %; docs/mpm.md). The binaries then run only on CPUs that have them.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="${CULINARYCUT_JOBS:-$(nproc)}"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS="${CULINARYCUT_MARCH:+-march=$CULINARYCUT_MARCH}"
cmake --build "$root/build" -j "$jobs"
